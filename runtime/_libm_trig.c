/*
 * SIN, COS and TAN of an angle in degrees, computed exactly as rs274 computes
 * them: the degrees times M_PIl, divided by 180, in x87 long double, handed
 * to the C library's long double function, and the result stored into a
 * double (interp_execute.cc: cos((d * M_PIl) / 180.0) on a long double).
 *
 * Optional: runtime/x87.py does the same through ctypes (about 1.5 us a
 * call, most of it forming the long double radians in Python) where this
 * extension was not built; it is about ten times faster. Either way the
 * answers are checked against runtime/ops.py's integer emulation before
 * they are used.
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <math.h>

typedef long double (*libm_function)(long double);

static PyObject *in_degrees(PyObject *arg, libm_function function) {
    double degrees = PyFloat_AsDouble(arg);
    if (degrees == -1.0 && PyErr_Occurred()) {
        return NULL;
    }
    return PyFloat_FromDouble((double) function(((long double) degrees * M_PIl) / 180.0));
}

static PyObject *sin_degrees(PyObject *self, PyObject *arg) { return in_degrees(arg, sinl); }
static PyObject *cos_degrees(PyObject *self, PyObject *arg) { return in_degrees(arg, cosl); }
static PyObject *tan_degrees(PyObject *self, PyObject *arg) { return in_degrees(arg, tanl); }

static PyMethodDef methods[] = {
    {"sin", sin_degrees, METH_O, "sinl((d * M_PIl) / 180.0) stored into a double"},
    {"cos", cos_degrees, METH_O, "cosl((d * M_PIl) / 180.0) stored into a double"},
    {"tan", tan_degrees, METH_O, "tanl((d * M_PIl) / 180.0) stored into a double"},
    {NULL, NULL, 0, NULL},
};

static struct PyModuleDef module = {
    PyModuleDef_HEAD_INIT, "_libm_trig", "rs274's SIN, COS and TAN of degrees.", -1, methods,
};

PyMODINIT_FUNC PyInit__libm_trig(void) { return PyModule_Create(&module); }
