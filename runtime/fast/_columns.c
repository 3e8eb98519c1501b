/*
 * divided(column, divisor): [value / divisor for value in column], in C.
 *
 * A batch's columns of lengths go to a preview in inches (ngc2py/preview.py
 * divides each by 25.4): a comprehension spends about 60 ns a value in the
 * interpreter, this about 10. A float is divided as a double, as Python
 * divides floats; anything else by Python's own division, so the list is
 * the comprehension's, value for value.
 *
 * Optional: ngc2py/preview.py runs the comprehension where this was not
 * built (setup.py).
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>

static PyObject *divided(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    if (nargs != 2 || !PyFloat_CheckExact(args[1])) {
        PyErr_SetString(PyExc_TypeError, "divided(column, divisor: float)");
        return NULL;
    }
    PyObject *items = PySequence_Fast(args[0], "divided(): the column must be a sequence");
    if (items == NULL) {
        return NULL;
    }
    PyObject *divisor = args[1];
    double k = PyFloat_AS_DOUBLE(divisor);
    Py_ssize_t count = PySequence_Fast_GET_SIZE(items);
    PyObject *out = PyList_New(count);
    if (out == NULL) {
        Py_DECREF(items);
        return NULL;
    }
    for (Py_ssize_t i = 0; i < count; i++) {
        PyObject *item = PySequence_Fast_GET_ITEM(items, i);
        PyObject *value = PyFloat_CheckExact(item)
                              ? PyFloat_FromDouble(PyFloat_AS_DOUBLE(item) / k)
                              : PyNumber_TrueDivide(item, divisor);
        if (value == NULL) {
            Py_DECREF(out);
            Py_DECREF(items);
            return NULL;
        }
        PyList_SET_ITEM(out, i, value);
    }
    Py_DECREF(items);
    return out;
}

static PyMethodDef methods[] = {
    {"divided", (PyCFunction) (void (*)(void)) divided, METH_FASTCALL,
     "divided(column, divisor): [value / divisor for value in column]"},
    {NULL, NULL, 0, NULL},
};

static struct PyModuleDef module = {
    PyModuleDef_HEAD_INIT, "runtime.fast._columns",
    "Column arithmetic of batches in C (see ngc2py/preview.py).", -1, methods,
};

PyMODINIT_FUNC PyInit__columns(void) {
    return PyModule_Create(&module);
}
