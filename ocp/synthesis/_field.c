/* The compiled kernels of ocp.synthesis.field (its docstrings state what they draw): a strip of
 * the field of extremals drawn into the grid as triangles on which the time-to-go is linear, and
 * the test of whether a wide strip may be optimal somewhere.
 *
 * IEEE double arithmetic in the order written (built with -ffp-contract=off, no fast-math), the
 * same operations as the numba kernels this module replaced, bit for bit: min and max of numbers
 * are Python's (the first argument kept unless the second is strictly smaller, or larger), those
 * of a 4-array numpy's (a NaN returned), round() half to even. */

#include "../_arrays.h"
#include <math.h>
#include <stdint.h>

static const double TWO_PI = 2 * 3.141592653589793;

static inline double min2(double a, double b) { return b < a ? b : a; }
static inline double max2(double a, double b) { return b > a ? b : a; }
static inline int64_t imin(int64_t a, int64_t b) { return b < a ? b : a; }
static inline int64_t imax(int64_t a, int64_t b) { return b > a ? b : a; }

/* numpy's max and min of 4 numbers: the first NaN if any. */
static double amax4(const double *v)
{
    double m = v[0];
    if (isnan(m))
        return m;
    for (int i = 1; i < 4; i++) {
        if (isnan(v[i]))
            return v[i];
        if (v[i] > m)
            m = v[i];
    }
    return m;
}

static double amin4(const double *v)
{
    double m = v[0];
    if (isnan(m))
        return m;
    for (int i = 1; i < 4; i++) {
        if (isnan(v[i]))
            return v[i];
        if (v[i] < m)
            m = v[i];
    }
    return m;
}

/* The grid (nx x ny cells from (x0, y0), steps dx, dy) and the arrays drawn into it: V (least time),
 * N (switch count), P (nx x ny x 2: the strip's interval of final costate angles), B (branch). */
typedef struct {
    double x0, dx, y0, dy;
    int64_t nx, ny;
    double *V, *P;
    int64_t *N, *B;
} Grid;

/* The triangle of vertices (theta, omega, s, n) a, b, c drawn into the grid (the least s kept). */
static void triangle(Grid *g, const double *a, const double *b, const double *c, const double *ident,
                     int64_t branch)
{
    double xmin = min2(min2(a[0], b[0]), c[0]), xmax = max2(max2(a[0], b[0]), c[0]);
    double ymin = min2(min2(a[1], b[1]), c[1]), ymax = max2(max2(a[1], b[1]), c[1]);
    int64_t i0 = imax(0, (int64_t)ceil((xmin - g->x0) / g->dx)), i1 = imin(g->nx - 1, (int64_t)floor((xmax - g->x0) / g->dx));
    int64_t j0 = imax(0, (int64_t)ceil((ymin - g->y0) / g->dy)), j1 = imin(g->ny - 1, (int64_t)floor((ymax - g->y0) / g->dy));
    double det = (b[1] - c[1]) * (a[0] - c[0]) + (c[0] - b[0]) * (a[1] - c[1]);
    if (det == 0.0)
        return;
    for (int64_t i = i0; i <= i1; i++) {
        double x = g->x0 + i * g->dx;
        for (int64_t j = j0; j <= j1; j++) {
            double y = g->y0 + j * g->dy;
            double l1 = ((b[1] - c[1]) * (x - c[0]) + (c[0] - b[0]) * (y - c[1])) / det;
            double l2 = ((c[1] - a[1]) * (x - c[0]) + (a[0] - c[0]) * (y - c[1])) / det;
            double l3 = 1.0 - l1 - l2;
            if (l1 < -1e-12 || l2 < -1e-12 || l3 < -1e-12)
                continue;
            double s = l1 * a[2] + l2 * b[2] + l3 * c[2];
            int64_t cell = i * g->ny + j;
            if (s < g->V[cell]) {
                g->V[cell] = s;
                g->N[cell] = (int64_t)((l1 >= l2 && l1 >= l3) ? a[3] : (l2 >= l3 ? b[3] : c[3]));
                g->P[2 * cell] = ident[0];
                g->P[2 * cell + 1] = ident[1];
                g->B[cell] = branch;
            }
        }
    }
}

/* The rows (theta, omega, arcs) of the two sampled extremals at time j: A's, C's. */
#define ROW(A, j) ((A) + 3 * (j))

static int64_t strip(Grid *g, const double *A, const double *C, const double *ts, Py_ssize_t n, const double *ident,
                     int circle, double max_cells, char *wide)
{
    double x1 = g->x0 + g->dx * (g->nx - 1);
    int64_t count = 0;
    for (Py_ssize_t j = 0; j < n - 1; j++) {
        const double *p = ROW(A, j), *q = ROW(C, j), *r = ROW(C, j + 1), *s_ = ROW(A, j + 1);
        double spread = max2(max2(max2(fabs(p[0] - q[0]) / g->dx, fabs(p[1] - q[1]) / g->dy),
                                  fabs(s_[0] - r[0]) / g->dx), fabs(s_[1] - r[1]) / g->dy);
        wide[j] = spread > max_cells;
        if (wide[j]) {
            count++;
            continue;
        }
        double va[4] = {p[0], p[1], ts[j], p[2]}, vb[4] = {q[0], q[1], ts[j], q[2]};
        double vc[4] = {r[0], r[1], ts[j + 1], r[2]}, vd[4] = {s_[0], s_[1], ts[j + 1], s_[2]};
        double lo = min2(min2(min2(p[0], q[0]), r[0]), s_[0]), hi = max2(max2(max2(p[0], q[0]), r[0]), s_[0]);
        int64_t k0 = 0, k1 = 0;
        if (circle) {
            k0 = (int64_t)ceil((g->x0 - hi) / TWO_PI);
            k1 = (int64_t)floor((x1 - lo) / TWO_PI);
        }
        for (int64_t k = k0; k <= k1; k++) {
            double sh = TWO_PI * k;
            va[0] = p[0] + sh;
            vb[0] = q[0] + sh;
            vc[0] = r[0] + sh;
            vd[0] = s_[0] + sh;
            triangle(g, va, vb, vc, ident, k);
            triangle(g, va, vc, vd, ident, k);
        }
    }
    return count;
}

static int undominated(const Grid *g, const double *ra, const double *rb, const double *ts, Py_ssize_t n_wide,
                       const char *wide, int circle, double dominated)
{
    double x0 = g->x0, dx = g->dx, y0 = g->y0, dy = g->dy;
    double x1 = x0 + dx * (g->nx - 1), y1 = y0 + dy * (g->ny - 1);
    for (Py_ssize_t j = 0; j < n_wide; j++) {
        if (!wide[j])
            continue;
        const double *rows[4] = {ROW(ra, j), ROW(rb, j), ROW(ra, j + 1), ROW(rb, j + 1)};
        double xs[4], ys[4];
        for (int c = 0; c < 4; c++) {
            xs[c] = rows[c][0];
            ys[c] = rows[c][1];
        }
        if (amax4(ys) >= y0 && amin4(ys) <= y1) {    /* it overlaps the grid's rows */
            if (amin4(ys) < y0 || amax4(ys) > y1)
                return 1;
            double lo = amin4(xs), hi = amax4(xs);
            int64_t k0 = 0, k1 = 0;
            if (circle) {
                k0 = (int64_t)ceil((x0 - hi) / TWO_PI);
                k1 = (int64_t)floor((x1 - lo) / TWO_PI);
            }
            for (int64_t k = k0; k <= k1; k++)
                if (lo + TWO_PI * k < x0 || hi + TWO_PI * k > x1)
                    return 1;
        }
        for (int c = 0; c < 4; c++) {
            const double *row = rows[c];
            double t = c < 2 ? ts[j] : ts[j + 1];
            int64_t jj = (int64_t)rint((row[1] - y0) / dy);
            if (jj < 0 || jj >= g->ny)
                continue;
            int64_t k0 = 0, k1 = 0;
            if (circle) {
                k0 = (int64_t)ceil((x0 - row[0]) / TWO_PI);
                k1 = (int64_t)floor((x0 + dx * (g->nx - 1) - row[0]) / TWO_PI);
            }
            for (int64_t k = k0; k <= k1; k++) {
                int64_t i = (int64_t)rint((row[0] + TWO_PI * k - x0) / dx);
                if (0 <= i && i < g->nx && !(g->V[i * g->ny + jj] < t - dominated))
                    return 1;
            }
        }
    }
    return 0;
}

static const Py_ssize_t FOUR[] = {4}, TWO[] = {2}, ANY[] = {-1}, ROWS[] = {-1, 3};

/* The grid from V (its shape) and `grid` = (x0, dx, y0, dy); N, P, B when given (else NULL). */
static int get_grid(Held *h, Grid *g, PyObject *oV, PyObject *oN, PyObject *oP, PyObject *oB, PyObject *ogrid)
{
    Py_ssize_t cells[2] = {-1, -1};
    double *grid;
    if (!(g->V = array(h, oV, oN != NULL, 'd', 2, cells, "V")))
        return -1;
    g->nx = cells[0] = LAST_SHAPE(h, 0);
    g->ny = cells[1] = LAST_SHAPE(h, 1);
    Py_ssize_t angles[3] = {cells[0], cells[1], 2};
    if (oN && (!(g->N = array(h, oN, 1, 'q', 2, cells, "N")) || !(g->P = array(h, oP, 1, 'd', 3, angles, "P")) ||
               !(g->B = array(h, oB, 1, 'q', 2, cells, "B"))))
        return -1;
    if (!(grid = array(h, ogrid, 0, 'd', 1, FOUR, "grid")))
        return -1;
    g->x0 = grid[0];
    g->dx = grid[1];
    g->y0 = grid[2];
    g->dy = grid[3];
    return 0;
}

/* The two extremals' rows (at least one a time of ts) and ts. */
static int get_rows(Held *h, PyObject *oa, PyObject *ob, PyObject *ots, double **a, double **b, double **ts,
                    Py_ssize_t *n)
{
    if (!(*ts = array(h, ots, 0, 'd', 1, ANY, "ts")))
        return -1;
    *n = LAST_SHAPE(h, 0);
    if (!(*a = array(h, oa, 0, 'd', 2, ROWS, "rows")) || LAST_SHAPE(h, 0) < *n ||
        !(*b = array(h, ob, 0, 'd', 2, ROWS, "rows")) || LAST_SHAPE(h, 0) < *n) {
        if (!PyErr_Occurred())
            PyErr_SetString(PyExc_ValueError, "rows: one for every time of ts is needed");
        return -1;
    }
    return 0;
}

PyDoc_STRVAR(strip_doc,
"strip(V, N, P, B, grid, A, C, ts, ident, circle, max_cells, wide) -> count\n\n"
"ocp.synthesis.field._strip.");

static PyObject *py_strip(PyObject *self, PyObject *args)
{
    PyObject *oV, *oN, *oP, *oB, *ogrid, *oA, *oC, *ots, *oident, *owide;
    int circle;
    double max_cells;
    if (!PyArg_ParseTuple(args, "OOOOOOOOOpdO:strip", &oV, &oN, &oP, &oB, &ogrid, &oA, &oC, &ots, &oident, &circle,
                          &max_cells, &owide))
        return NULL;
    Held h = {.n = 0};
    Grid g;
    double *A, *C, *ts, *ident;
    char *wide;
    Py_ssize_t n;
    if (get_grid(&h, &g, oV, oN, oP, oB, ogrid) < 0 || get_rows(&h, oA, oC, ots, &A, &C, &ts, &n) < 0 ||
        !(ident = array(&h, oident, 0, 'd', 1, TWO, "ident")) || !(wide = array(&h, owide, 1, '?', 1, ANY, "wide")))
        goto fail;
    if (LAST_SHAPE(&h, 0) < n - 1) {
        PyErr_SetString(PyExc_ValueError, "wide: one for every interval of ts is needed");
        goto fail;
    }
    int64_t count;
    Py_BEGIN_ALLOW_THREADS
    count = strip(&g, A, C, ts, n, ident, circle, max_cells, wide);
    Py_END_ALLOW_THREADS
    release(&h);
    return PyLong_FromLongLong(count);
fail:
    release(&h);
    return NULL;
}

PyDoc_STRVAR(undominated_doc,
"undominated(V, grid, ra, rb, ts, wide, circle, dominated) -> bool\n\n"
"ocp.synthesis.field._undominated.");

static PyObject *py_undominated(PyObject *self, PyObject *args)
{
    PyObject *oV, *ogrid, *ora, *orb, *ots, *owide;
    int circle;
    double dominated;
    if (!PyArg_ParseTuple(args, "OOOOOOpd:undominated", &oV, &ogrid, &ora, &orb, &ots, &owide, &circle, &dominated))
        return NULL;
    Held h = {.n = 0};
    Grid g;
    double *ra, *rb, *ts;
    char *wide;
    Py_ssize_t n;
    if (get_grid(&h, &g, oV, NULL, NULL, NULL, ogrid) < 0 || get_rows(&h, ora, orb, ots, &ra, &rb, &ts, &n) < 0 ||
        !(wide = array(&h, owide, 0, '?', 1, ANY, "wide")))
        goto fail;
    Py_ssize_t n_wide = LAST_SHAPE(&h, 0);
    if (n_wide > n - 1) {
        PyErr_SetString(PyExc_ValueError, "wide: at most one for every interval of ts");
        goto fail;
    }
    int found;
    Py_BEGIN_ALLOW_THREADS
    found = undominated(&g, ra, rb, ts, n_wide, wide, circle, dominated);
    Py_END_ALLOW_THREADS
    release(&h);
    return PyBool_FromLong(found);
fail:
    release(&h);
    return NULL;
}

static PyMethodDef methods[] = {
    {"strip", py_strip, METH_VARARGS, strip_doc},
    {"undominated", py_undominated, METH_VARARGS, undominated_doc},
    {NULL, NULL, 0, NULL},
};

static struct PyModuleDef module = {
    PyModuleDef_HEAD_INIT, "_field", "The compiled kernels of ocp.synthesis.field (C).", -1, methods,
    NULL, NULL, NULL, NULL,
};

PyMODINIT_FUNC PyInit__field(void) { return PyModule_Create(&module); }
