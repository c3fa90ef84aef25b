/* The compiled kernels of ocp.indirect.taylor (its docstring states the mathematics): the Taylor
 * series of the pendulum's state and costate (and of their variations), the Jorba-Zou step, the
 * events located on each step's polynomial.
 *
 * IEEE double arithmetic in the order written (built with -ffp-contract=off, no fast-math: no fused
 * multiply-add, no reassociation), libm's sin, cos, pow, exp and hypot: the same operations, in the
 * same order, as the numba kernels this module replaced, which it reproduces bit for bit. min and
 * max are Python's (the first argument kept unless the second is strictly smaller, or larger).
 * Arrays are float64 buffers (numpy's, through the buffer protocol: ../_arrays.h), C-contiguous. */

#include "../_arrays.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* samples per step where sign changes are looked for */
#define SUBSTEPS 8

static inline double min2(double a, double b) { return b < a ? b : a; }
static inline double max2(double a, double b) { return b > a ? b : a; }

/* Coefficient k of component i: c[4 k + i]. */
#define C(c, k, i) ((c)[4 * (k) + (i)])

/* The workspace of a series of order K: the coefficients of y (c), of sin and cos of theta (s, co),
 * (j + 1) theta_{j+1} (jt: the terms of the series of sin and cos, each product formed once), of
 * the variations dy (d) and of sin(theta) p2 (g). */
typedef struct {
    int K;
    double *c, *s, *co, *jt, *d, *g;
} Series;

static int series_alloc(Series *w, int K, int variations)
{
    size_t n = (size_t)(K + 1);
    w->K = K;
    w->c = malloc(sizeof(double) * n * (variations ? 12 : 7));
    if (!w->c) {
        PyErr_NoMemory();
        return -1;
    }
    w->s = w->c + 4 * n;
    w->co = w->s + n;
    w->jt = w->co + n;
    w->d = variations ? w->jt + n : NULL;
    w->g = variations ? w->d + 4 * n : NULL;
    return 0;
}

/* The coefficients k = 0..K at y = (theta, omega, p1, p2) under u; with the variations (w->d), those
 * of dy: dtheta' = domega, domega' = -cos(theta) dtheta, dp1' = cos(theta) dp2 - sin(theta) p2 dtheta,
 * dp2' = -dp1. */
static void series(Series *w, const double *y, double u, double kappa, const double *dy)
{
    const int K = w->K;
    double *c = w->c, *s = w->s, *co = w->co, *jt = w->jt, *d = w->d, *g = w->g;
    for (int i = 0; i < 4; i++)
        C(c, 0, i) = y[i];
    s[0] = sin(y[0]);
    co[0] = cos(y[0]);
    if (d)
        for (int i = 0; i < 4; i++)
            C(d, 0, i) = dy[i];
    for (int k = 0; k < K; k++) {
        int k1 = k + 1;
        C(c, k1, 0) = C(c, k, 1) / k1;
        C(c, k1, 1) = ((k == 0 ? kappa * u : 0.0) - s[k]) / k1;
        C(c, k1, 3) = -C(c, k, 2) / k1;
        /* the independent sums of one order in one loop (each summed in its own order, as written
         * apart: their latencies overlap): p2 cos(theta) (acc), sin(theta) p2 (gk), and the
         * series of sin and cos, k s_k = sum_j j theta_j c_{k-j} (ss, term j + 1 at j) */
        jt[k] = k1 * C(c, k1, 0);
        double acc = 0.0, gk = 0.0, ss = 0.0, cc = 0.0;
        for (int j = 0; j <= k; j++) {
            acc += C(c, j, 3) * co[k - j];
            gk += s[j] * C(c, k - j, 3);
            ss += jt[j] * co[k - j];
            cc += jt[j] * s[k - j];
        }
        C(c, k1, 2) = acc / k1;
        if (d) {
            g[k] = gk;
            double cdt = 0.0, cdp2 = 0.0, gdt = 0.0;
            for (int j = 0; j <= k; j++) {
                cdt += co[k - j] * C(d, j, 0);
                cdp2 += co[k - j] * C(d, j, 3);
                gdt += g[k - j] * C(d, j, 0);
            }
            C(d, k1, 0) = C(d, k, 1) / k1;
            C(d, k1, 1) = -cdt / k1;
            C(d, k1, 2) = (cdp2 - gdt) / k1;
            C(d, k1, 3) = -C(d, k, 2) / k1;
        }
        s[k1] = ss / k1;
        co[k1] = -cc / k1;
    }
}

/* The Jorba-Zou step from the coefficients of y; safety = exp(-0.7 / (K - 1)) (`safety`). */
static double step(const double *c, int K, double tol, double safety)
{
    double h = 1e300;
    for (int k = K - 1; k <= K; k++) {
        double m = 0.0;
        for (int i = 0; i < 4; i++)
            m = max2(m, fabs(C(c, k, i)));
        if (m > 0.0)
            h = min2(h, pow(tol / m, 1.0 / k));
    }
    return h * safety;
}

/* The Jorba-Zou safety factor of order K. */
static double safety(int K) { return exp(-0.7 / (K - 1)); }

/* Component i's polynomial at tau (Horner), and its derivative. */
static double at(const double *c, int K, int i, double tau)
{
    double v = C(c, K, i);
    for (int k = K - 1; k >= 0; k--)
        v = v * tau + C(c, k, i);
    return v;
}

/* The four components' polynomials at tau into v (each as `at`, their Horner steps interleaved). */
static void at4(const double *c, int K, double tau, double *v)
{
    double v0 = C(c, K, 0), v1 = C(c, K, 1), v2 = C(c, K, 2), v3 = C(c, K, 3);
    for (int k = K - 1; k >= 0; k--) {
        v0 = v0 * tau + C(c, k, 0);
        v1 = v1 * tau + C(c, k, 1);
        v2 = v2 * tau + C(c, k, 2);
        v3 = v3 * tau + C(c, k, 3);
    }
    v[0] = v0;
    v[1] = v1;
    v[2] = v2;
    v[3] = v3;
}

static double slope(const double *c, int K, int i, double tau)
{
    double v = K * C(c, K, i);
    for (int k = K - 1; k > 0; k--)
        v = v * tau + k * C(c, k, i);
    return v;
}

/* Whether component i's polynomial keeps its sign on [0, h]: |c_0| > sum_k |c_k| |h|^k. */
static int clear(const double *c, int K, int i, double h)
{
    h = fabs(h);
    double v = fabs(C(c, K, i));
    for (int k = K - 1; k > 0; k--)
        v = v * h + fabs(C(c, k, i));
    return fabs(C(c, 0, i)) > v * h;
}

/* The zero of component i's polynomial between a and b (values of opposite signs there): Newton
 * kept inside the shrinking bracket, bisection where it would leave it. */
static double zero(const double *c, int K, int i, double a, double b)
{
    double fa = at(c, K, i, a);
    if (fa == 0.0)
        return a;
    double x = 0.5 * (a + b);
    for (int it = 0; it < 200; it++) {
        double f = at(c, K, i, x);
        if (f == 0.0)
            return x;
        if ((f > 0.0) == (fa > 0.0)) {
            a = x;
            fa = f;
        } else {
            b = x;
        }
        double dfx = slope(c, K, i, x);
        double xn = dfx != 0.0 ? x - f / dfx : 0.5 * (a + b);
        if (!(min2(a, b) < xn && xn < max2(a, b)))
            xn = 0.5 * (a + b);
        if (fabs(xn - x) <= 2e-16 * max2(1.0, fabs(x)) || a == b)
            return xn;
        x = xn;
    }
    return x;
}

/* p <- p/|p|, and its variation dp <- dp/n - p (p . dp)/n^3 (p before, n = |p|) when dy is given. */
static void normalise(double *y, double *dy)
{
    double n = hypot(y[2], y[3]);
    if (n > 0.0) {
        if (dy) {
            double pd = y[2] * dy[2] + y[3] * dy[3];
            double n3 = n * n * n;
            dy[2] = dy[2] / n - y[2] * pd / n3;
            dy[3] = dy[3] / n - y[3] * pd / n3;
        }
        y[2] /= n;
        y[3] /= n;
    }
}

/* An n x cols float64 table (rows = n) that is written as far as it reaches. */
typedef struct {
    double *v;
    Py_ssize_t rows, cols;
} Table;

#define T(t, r, j) ((t).v[(t).cols * (r) + (j)])

/* The integration of `extremal` (dy NULL: without variations; sample_t, samples: n_samples rows; marked
 * non-NULL: y, and dy with the variations, at the elapsed time mark, by the series of the step that
 * contains it, mark in (t, t + h]: the steps are the same as without). */
typedef struct {
    int n_sw, n_ev, steps;
    double u;
} Outcome;

static Outcome integrate(Series *w, double *y, double *dy, double kappa, double u_start, double duration,
                         double direction, double tol, Table switches, Table events, const double *sample_t,
                         Py_ssize_t n_samples, Table samples, double mark, double *marked)
{
    const int K = w->K;
    const double *c = w->c, *d = w->d;
    Outcome o = {0, 0, 0, 0.0};
    normalise(y, dy);
    double u = y[3] == 0.0 ? u_start : (y[3] > 0.0 ? 1.0 : -1.0);
    double t = 0.0;
    int in_arc = 0;
    Py_ssize_t n_sample = 0;
    const double shrink = safety(K);
    while (t < duration) {
        o.steps++;
        series(w, y, u, kappa, dy);
        double h = min2(step(c, K, tol, shrink), duration - t);
        double stop = direction * h;
        int switched = 0;
        double before = 0.0;
        for (int q = 1, last = clear(c, K, 3, stop) ? 0 : SUBSTEPS; q <= last; q++) {
            double tq = stop * q / SUBSTEPS;
            if (u * at(c, K, 3, tq) < 0.0) {
                stop = zero(c, K, 3, before, tq);
                switched = 1;
                break;
            }
            before = tq;
        }
        double w0 = C(c, 0, 1);
        before = 0.0;
        for (int q = 1, last = clear(c, K, 1, stop) ? 0 : SUBSTEPS; q <= last; q++) {
            double tq = stop * q / SUBSTEPS;
            double w1 = at(c, K, 1, tq);
            if ((w0 > 0.0 && w1 <= 0.0) || (w0 < 0.0 && w1 >= 0.0)) {
                double r = w1 != 0.0 ? zero(c, K, 1, before, tq) : tq;
                if (o.n_ev < events.rows) {
                    T(events, o.n_ev, 0) = t + fabs(r);
                    T(events, o.n_ev, 1) = at(c, K, 0, r);
                    T(events, o.n_ev, 2) = o.n_sw;
                    T(events, o.n_ev, 3) = in_arc;
                    T(events, o.n_ev, 4) = at(c, K, 2, r);
                    T(events, o.n_ev, 5) = at(c, K, 3, r);
                    if (d) {    /* omega(t_e) = 0: dt_e = -domega / omega', dtheta_e = dtheta */
                        double dt_e = -at(d, K, 1, r) / (kappa * u - sin(at(c, K, 0, r)));
                        T(events, o.n_ev, 6) = at(d, K, 0, r);
                        T(events, o.n_ev, 7) = direction * dt_e;
                    }
                }
                o.n_ev++;
                in_arc++;
            }
            if (w1 != 0.0)
                w0 = w1;
            before = tq;
        }
        while (n_sample < n_samples && sample_t[n_sample] <= t + fabs(stop)) {
            double tau = direction * (sample_t[n_sample] - t);
            T(samples, n_sample, 0) = at(c, K, 0, tau);
            T(samples, n_sample, 1) = at(c, K, 1, tau);
            T(samples, n_sample, 2) = o.n_sw;
            n_sample++;
        }
        if (marked && t < mark && mark <= t + fabs(stop)) {
            double tau = direction * (mark - t);
            at4(c, K, tau, marked);
            if (d)
                at4(d, K, tau, marked + 4);
        }
        at4(c, K, stop, y);
        if (d)
            at4(d, K, stop, dy);
        t += fabs(stop);
        if (switched) {
            /* p2(t_s) = 0: dt_s = dp2 / p1 (p2' = -p1); omega' jumps by kappa (u_new - u_old) */
            double dt_s = d ? dy[3] / y[2] : 0.0;
            y[3] = 0.0;
            if (d)
                dy[1] += kappa * (u - (-u)) * dt_s;
            if (o.n_sw < switches.rows) {
                T(switches, o.n_sw, 0) = t;
                for (int i = 0; i < 4; i++)
                    T(switches, o.n_sw, 1 + i) = y[i];
                if (d) {    /* and the state's variation just after the switch (at the fixed time t+) */
                    T(switches, o.n_sw, 5) = direction * dt_s;
                    T(switches, o.n_sw, 6) = dy[0];
                    T(switches, o.n_sw, 7) = dy[1];
                }
            }
            o.n_sw++;
            u = -u;
            in_arc = 0;
        }
        normalise(y, dy);
    }
    o.u = u;
    return o;
}

/* ---- the functions of the module ---- */

static int check_order(int K, double tol)
{
    if (K < 2) {
        PyErr_SetString(PyExc_ValueError, "the order K must be at least 2");
        return -1;
    }
    if (!(tol > 0.0)) {
        PyErr_SetString(PyExc_ValueError, "the tolerance must be positive");
        return -1;
    }
    return 0;
}

static Table table(double *v, Held *h)
{
    Table t = {v, LAST_SHAPE(h, 0), LAST_SHAPE(h, 1)};
    return t;
}

static const Py_ssize_t FOUR[] = {4}, TWO[] = {2}, ANY[] = {-1}, SWITCHES[] = {-1, 5}, EVENTS[] = {-1, 6},
                        SAMPLES[] = {-1, 3}, SWITCHES_VAR[] = {-1, 8}, EVENTS_VAR[] = {-1, 8},
                        EIGHT[] = {8};

/* The common end of extremal and extremal_variations: integrate (with the GIL released) in a series
 * of order K (with the variations where dy), free it, release the buffers, (n_sw, n_ev, u, steps). */
static PyObject *run(Held *h, int K, double *y, double *dy, double kappa, double u_start, double duration,
                     double direction, double tol, Table switches, Table events, const double *sample_t,
                     Py_ssize_t n_samples, Table samples, double mark, double *marked)
{
    Series w;
    if (series_alloc(&w, K, dy != NULL) < 0) {
        release(h);
        return NULL;
    }
    Outcome o;
    Py_BEGIN_ALLOW_THREADS
    o = integrate(&w, y, dy, kappa, u_start, duration, direction, tol, switches, events, sample_t, n_samples,
                  samples, mark, marked);
    Py_END_ALLOW_THREADS
    free(w.c);
    release(h);
    return Py_BuildValue("iidi", o.n_sw, o.n_ev, o.u, o.steps);
}

PyDoc_STRVAR(extremal_doc,
"extremal(y, kappa, u_start, duration, direction, tol, K, switches, events, sample_t, samples)\n"
"    -> (n_sw, n_ev, u, steps)\n\n"
"ocp.indirect.taylor.extremal, y (4) integrated in place.");

static PyObject *py_extremal(PyObject *self, PyObject *args)
{
    PyObject *oy, *osw, *oev, *ost, *osa;
    double kappa, u_start, duration, direction, tol;
    int K;
    if (!PyArg_ParseTuple(args, "OdddddiOOOO:extremal", &oy, &kappa, &u_start, &duration, &direction, &tol, &K,
                          &osw, &oev, &ost, &osa) || check_order(K, tol) < 0)
        return NULL;
    Held h = {.n = 0};
    double *y, *sample_t;
    Table switches, events, samples;
    Py_ssize_t n_samples;
    if (!(y = array(&h, oy, 1, 'd', 1, FOUR, "y")) || !(switches.v = array(&h, osw, 1, 'd', 2, SWITCHES, "switches")))
        goto fail;
    switches = table(switches.v, &h);
    if (!(events.v = array(&h, oev, 1, 'd', 2, EVENTS, "events")))
        goto fail;
    events = table(events.v, &h);
    if (!(sample_t = array(&h, ost, 0, 'd', 1, ANY, "sample_t")))
        goto fail;
    n_samples = LAST_SHAPE(&h, 0);
    if (!(samples.v = array(&h, osa, 1, 'd', 2, SAMPLES, "samples")))
        goto fail;
    samples = table(samples.v, &h);
    if (samples.rows < n_samples) {
        PyErr_SetString(PyExc_ValueError, "samples: a row for every sample time is needed");
        goto fail;
    }
    return run(&h, K, y, NULL, kappa, u_start, duration, direction, tol, switches, events, sample_t, n_samples,
               samples, 0.0, NULL);
fail:
    release(&h);
    return NULL;
}

PyDoc_STRVAR(variations_doc,
"extremal_variations(y, dy, kappa, u_start, duration, direction, tol, K, switches, events, mark, marked)\n"
"    -> (n_sw, n_ev, u, steps)\n\n"
"ocp.indirect.taylor.extremal_variations, y (4) and dy (4) integrated in place; marked (8, or None):\n"
"(y, dy) at the elapsed time mark.");

static PyObject *py_variations(PyObject *self, PyObject *args)
{
    PyObject *oy, *ody, *osw, *oev, *omk;
    double kappa, u_start, duration, direction, tol, mark;
    int K;
    if (!PyArg_ParseTuple(args, "OOdddddiOOdO:extremal_variations", &oy, &ody, &kappa, &u_start, &duration,
                          &direction, &tol, &K, &osw, &oev, &mark, &omk) || check_order(K, tol) < 0)
        return NULL;
    Held h = {.n = 0};
    double *y, *dy, *marked = NULL;
    Table switches, events, none = {NULL, 0, 3};
    if (!(y = array(&h, oy, 1, 'd', 1, FOUR, "y")) || !(dy = array(&h, ody, 1, 'd', 1, FOUR, "dy")) ||
        !(switches.v = array(&h, osw, 1, 'd', 2, SWITCHES_VAR, "switches")))
        goto fail;
    switches = table(switches.v, &h);
    if (!(events.v = array(&h, oev, 1, 'd', 2, EVENTS_VAR, "events")))
        goto fail;
    events = table(events.v, &h);
    if (omk != Py_None && !(marked = array(&h, omk, 1, 'd', 1, EIGHT, "marked")))
        goto fail;
    return run(&h, K, y, dy, kappa, u_start, duration, direction, tol, switches, events, NULL, 0, none, mark,
               marked);
fail:
    release(&h);
    return NULL;
}

PyDoc_STRVAR(bang_doc,
"bang(x, signs, durations, kappa, tol, K)\n\n"
"ocp.indirect.taylor.bang, x (2) integrated in place.");

static PyObject *py_bang(PyObject *self, PyObject *args)
{
    PyObject *ox, *osg, *odu;
    double kappa, tol;
    int K;
    if (!PyArg_ParseTuple(args, "OOOddi:bang", &ox, &osg, &odu, &kappa, &tol, &K) || check_order(K, tol) < 0)
        return NULL;
    Held h = {.n = 0};
    double *x, *signs, *durations;
    Py_ssize_t arcs;
    Series w = {.c = NULL};
    if (!(x = array(&h, ox, 1, 'd', 1, TWO, "x")) || !(signs = array(&h, osg, 0, 'd', 1, ANY, "signs")))
        goto fail;
    arcs = LAST_SHAPE(&h, 0);
    if (!(durations = array(&h, odu, 0, 'd', 1, ANY, "durations")))
        goto fail;
    if (LAST_SHAPE(&h, 0) != arcs) {
        PyErr_SetString(PyExc_ValueError, "durations: one for every sign is needed");
        goto fail;
    }
    if (series_alloc(&w, K, 0) < 0)
        goto fail;
    Py_BEGIN_ALLOW_THREADS
    double y[4] = {x[0], x[1], 0.0, 0.0};
    const double shrink = safety(K);
    for (Py_ssize_t a = 0; a < arcs; a++) {
        double t = 0.0;
        while (t < durations[a]) {
            series(&w, y, signs[a], kappa, NULL);
            double step_h = min2(step(w.c, K, tol, shrink), durations[a] - t);
            for (int i = 0; i < 2; i++)
                y[i] = at(w.c, K, i, step_h);
            t += step_h;
        }
    }
    x[0] = y[0];
    x[1] = y[1];
    Py_END_ALLOW_THREADS
    free(w.c);
    release(&h);
    Py_RETURN_NONE;
fail:
    release(&h);
    return NULL;
}

PyDoc_STRVAR(series_doc,
"series(y, u, kappa, K, c)\n\n"
"c[k, i]: the k-th Taylor coefficient (k = 0..K) of y_i, y = (theta, omega, p1, p2), under u.");

static PyObject *py_series(PyObject *self, PyObject *args)
{
    PyObject *oy, *oc;
    double u, kappa;
    int K;
    if (!PyArg_ParseTuple(args, "OddiO:series", &oy, &u, &kappa, &K, &oc) || check_order(K, 1.0) < 0)
        return NULL;
    Held h = {.n = 0};
    double *y, *c;
    Series w = {.c = NULL};
    Py_ssize_t shape[] = {K + 1, 4};
    if (!(y = array(&h, oy, 0, 'd', 1, FOUR, "y")) || !(c = array(&h, oc, 1, 'd', 2, shape, "c")) ||
        series_alloc(&w, K, 0) < 0)
        goto fail;
    series(&w, y, u, kappa, NULL);
    memcpy(c, w.c, sizeof(double) * 4 * (K + 1));
    free(w.c);
    release(&h);
    Py_RETURN_NONE;
fail:
    release(&h);
    return NULL;
}

static PyMethodDef methods[] = {
    {"extremal", py_extremal, METH_VARARGS, extremal_doc},
    {"extremal_variations", py_variations, METH_VARARGS, variations_doc},
    {"bang", py_bang, METH_VARARGS, bang_doc},
    {"series", py_series, METH_VARARGS, series_doc},
    {NULL, NULL, 0, NULL},
};

static struct PyModuleDef module = {
    PyModuleDef_HEAD_INIT, "_taylor",
    "The compiled Taylor integration of ocp.indirect.taylor (C: its mathematics is stated there).", -1, methods,
    NULL, NULL, NULL, NULL,
};

PyMODINIT_FUNC PyInit__taylor(void)
{
    PyObject *m = PyModule_Create(&module);
    if (m && PyModule_AddIntConstant(m, "SUBSTEPS", SUBSTEPS) < 0) {
        Py_DECREF(m);
        return NULL;
    }
    return m;
}
