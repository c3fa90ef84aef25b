/* numpy arrays in the compiled kernels without numpy's headers: their buffers (PEP 3118), checked for
 * item type and shape. Included by ocp/indirect/_taylor.c and ocp/synthesis/_field.c. */

#ifndef OCP_ARRAYS_H
#define OCP_ARRAYS_H

#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <stdio.h>
#include <string.h>

/* The buffers held by one call, released together. */
typedef struct {
    Py_buffer b[12];
    int n;
} Held;

static void release(Held *h)
{
    while (h->n > 0)
        PyBuffer_Release(&h->b[--h->n]);
}

/* o's buffer as a C-contiguous array of `type` ('d': float64, 'q': int64, '?': bool) with `ndim`
 * dimensions, shape[i] where shape[i] >= 0 (any length where -1): its data, or NULL with the error
 * set. The buffer stays held (in h) until release(h). */
static void *array(Held *h, PyObject *o, int writable, char type, int ndim, const Py_ssize_t *shape,
                   const char *name)
{
    static const char *names[] = {"float64", "int64", "bool"};
    const char *tname = names[type == 'd' ? 0 : type == 'q' ? 1 : 2];
    Py_buffer *b = &h->b[h->n];
    int flags = PyBUF_C_CONTIGUOUS | PyBUF_FORMAT | (writable ? PyBUF_WRITABLE : 0);
    if (PyObject_GetBuffer(o, b, flags) < 0) {
        PyErr_Format(PyExc_TypeError, "%s: a C-contiguous%s %s array is needed", name, writable ? " writable" : "",
                     tname);
        return NULL;
    }
    h->n++;
    const char *f = b->format ? b->format : "B";
    if (*f == '@' || *f == '=' || *f == '<')
        f++;
    char got = f[0] == 'l' ? 'q' : f[0];
    int ok = f[0] != 0 && f[1] == 0 && got == type && b->itemsize == (type == '?' ? 1 : 8) && b->ndim == ndim;
    for (int i = 0; ok && i < ndim; i++)
        ok = shape[i] < 0 || b->shape[i] == shape[i];
    if (!ok) {
        char want[64] = "";
        for (int i = 0; i < ndim; i++) {
            char part[24];
            if (shape[i] < 0)
                snprintf(part, sizeof part, "%sn", i ? ", " : "");
            else
                snprintf(part, sizeof part, "%s%zd", i ? ", " : "", shape[i]);
            strncat(want, part, sizeof want - strlen(want) - 1);
        }
        PyErr_Format(PyExc_ValueError, "%s: a %s array of shape (%s%s) is needed", name, tname, want,
                     ndim == 1 ? "," : "");
        return NULL;
    }
    return b->buf;
}

/* The length of dimension i of the last array got. */
#define LAST_SHAPE(h, i) ((h)->b[(h)->n - 1].shape[i])

#endif
