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
 *
 * It also holds the column helpers the batches use: floats() (a table's
 * cells read), divided() (the preview's columns in inches) and
 * radius_bounds() (a batch of arcs checked).
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <math.h>

#include "plain_decimal.h"

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

/*
 * What generated code calls for SIN, COS and TAN (through runtime.ops): the
 * operand checked as rs274 checks it, and the library checked once, at the
 * first call, by runtime.ops (a Python call per SIN would cost more than the
 * sine). configure() hands over the two Python functions involved:
 * nonfinite(d) raises rs274's error for an inf/nan operand; first_use()
 * returns None when the library may be used, else the (sin, cos, tan) to use
 * instead.
 */
static PyObject *nonfinite = NULL, *first_use = NULL, *instead = NULL;
static int checked = 0;

static PyObject *configure(PyObject *self, PyObject *args) {
    PyObject *on_nonfinite, *on_first_use;
    if (!PyArg_ParseTuple(args, "OO", &on_nonfinite, &on_first_use)) {
        return NULL;
    }
    Py_INCREF(on_nonfinite);
    Py_INCREF(on_first_use);
    Py_XSETREF(nonfinite, on_nonfinite);
    Py_XSETREF(first_use, on_first_use);
    Py_CLEAR(instead);
    checked = 0;
    Py_RETURN_NONE;
}

static PyObject *checked_degrees(PyObject *arg, libm_function function, int which) {
    double degrees = PyFloat_AsDouble(arg);
    if (degrees == -1.0 && PyErr_Occurred()) {
        return NULL;
    }
    if (!isfinite(degrees)) {
        if (nonfinite == NULL) {
            PyErr_SetString(PyExc_ArithmeticError, "not a finite number");
            return NULL;
        }
        return PyObject_CallOneArg(nonfinite, arg);
    }
    if (!checked) {
        checked = 1; /* first: the check itself calls the library */
        if (first_use != NULL) {
            PyObject *answer = PyObject_CallNoArgs(first_use);
            if (answer == NULL) {
                checked = 0;
                return NULL;
            }
            if (answer == Py_None) {
                Py_DECREF(answer);
            } else {
                Py_XSETREF(instead, answer);
            }
        }
    }
    if (instead != NULL) {
        PyObject *fallback = PySequence_GetItem(instead, which);
        if (fallback == NULL) {
            return NULL;
        }
        PyObject *result = PyObject_CallOneArg(fallback, arg);
        Py_DECREF(fallback);
        return result;
    }
    return PyFloat_FromDouble((double) function(((long double) degrees * M_PIl) / 180.0));
}

static PyObject *checked_sin(PyObject *self, PyObject *arg) { return checked_degrees(arg, sinl, 0); }
static PyObject *checked_cos(PyObject *self, PyObject *arg) { return checked_degrees(arg, cosl, 1); }
static PyObject *checked_tan(PyObject *self, PyObject *arg) { return checked_degrees(arg, tanl, 2); }

/* rs274's MOD: C's fmod, made non-negative by adding |b| (NaN for an
 * infinite a or a zero b, as fmod gives). */
static PyObject *mod(PyObject *self, PyObject *const *args, Py_ssize_t count) {
    if (count != 2) {
        PyErr_SetString(PyExc_TypeError, "mod() takes two numbers");
        return NULL;
    }
    double a = PyFloat_AsDouble(args[0]);
    if (a == -1.0 && PyErr_Occurred()) {
        return NULL;
    }
    double b = PyFloat_AsDouble(args[1]);
    if (b == -1.0 && PyErr_Occurred()) {
        return NULL;
    }
    double result = fmod(a, b);
    if (result < 0.0) {
        result += fabs(b);
    }
    return PyFloat_FromDouble(result);
}

/* finite(x): x itself when it is a finite float (generated code wraps most
 * brackets in it); anything else goes to runtime.ops.finite, which raises
 * rs274's error (or answers for a type it accepts). */
static PyObject *finite_or_raise(PyObject *self, PyObject *arg) {
    if (PyFloat_CheckExact(arg) && isfinite(PyFloat_AS_DOUBLE(arg))) {
        Py_INCREF(arg);
        return arg;
    }
    if (nonfinite == NULL) {
        PyErr_SetString(PyExc_ArithmeticError, "not a finite number");
        return NULL;
    }
    return PyObject_CallOneArg(nonfinite, arg);
}

/* A cell of a column read by runtime/plain_decimal.h's quick path, where it
 * is a plain decimal in ASCII. */
static int quick_cell(PyObject *text, double *value) {
    return PyUnicode_CheckExact(text) && PyUnicode_IS_ASCII(text) &&
           plain_decimal((const char *) PyUnicode_DATA(text), PyUnicode_GET_LENGTH(text),
                         value);
}

/* [convert(item, context) for item in arg]: a column made a list in C, the
 * loop that floats() and divided() share. */
static PyObject *mapped_list(PyObject *arg, const char *message,
                             PyObject *(*convert)(PyObject *, PyObject *),
                             PyObject *context) {
    PyObject *items = PySequence_Fast(arg, message);
    if (items == NULL) {
        return NULL;
    }
    Py_ssize_t count = PySequence_Fast_GET_SIZE(items);
    PyObject *result = PyList_New(count);
    if (result == NULL) {
        Py_DECREF(items);
        return NULL;
    }
    PyObject **item = PySequence_Fast_ITEMS(items);
    for (Py_ssize_t i = 0; i < count; i++) {
        PyObject *value = convert(item[i], context);
        if (value == NULL) {
            Py_DECREF(items);
            Py_DECREF(result);
            return NULL;
        }
        PyList_SET_ITEM(result, i, value);
    }
    Py_DECREF(items);
    return result;
}

static PyObject *cell_value(PyObject *text, PyObject *unused) {
    double x;
    return quick_cell(text, &x) ? PyFloat_FromDouble(x) : PyFloat_FromString(text);
}

/* floats(strs): [float(s) for s in strs], for a list of str (a column of a
 * data table); anything else raises as float() would. */
static PyObject *floats(PyObject *self, PyObject *arg) {
    return mapped_list(arg, "floats() takes a sequence", cell_value, NULL);
}

/* A float divided as a double, as Python divides floats; anything else by
 * Python's own division: the comprehension's quotient, value for value. */
static PyObject *quotient(PyObject *value, PyObject *divisor) {
    if (PyFloat_CheckExact(value)) {
        return PyFloat_FromDouble(PyFloat_AS_DOUBLE(value) / PyFloat_AS_DOUBLE(divisor));
    }
    return PyNumber_TrueDivide(value, divisor);
}

/* divided(column, divisor): [value / divisor for value in column]. The
 * preview's columns of lengths in inches (ngc2py/preview.py divides each by
 * 25.4): a comprehension spends about 60 ns a value in the interpreter,
 * this about 10. */
static PyObject *divided(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    if (nargs != 2 || !PyFloat_CheckExact(args[1])) {
        PyErr_SetString(PyExc_TypeError, "divided(column, divisor: float)");
        return NULL;
    }
    return mapped_list(args[0], "divided(): the column must be a sequence", quotient,
                       args[1]);
}

/* radius_bounds(c1, c2, s1, s2, e1, e2): for the arcs of centres (c1, c2),
 * starts (s1, s2) and ends (e1, e2), six lists of floats of one length, the
 * smallest radius, the largest, and the largest difference between an arc's
 * start and end radius -- hypot() of the C library, as rs274 takes them --
 * or None when a value is not a finite float (the caller then leaves the
 * arcs to the general path). */
static PyObject *radius_bounds(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    if (nargs != 6) {
        PyErr_SetString(PyExc_TypeError, "radius_bounds() takes six lists");
        return NULL;
    }
    Py_ssize_t count = -1;
    for (int k = 0; k < 6; k++) {
        if (!PyList_CheckExact(args[k])) {
            PyErr_SetString(PyExc_TypeError, "radius_bounds() takes six lists");
            return NULL;
        }
        if (count < 0) {
            count = PyList_GET_SIZE(args[k]);
        } else if (PyList_GET_SIZE(args[k]) != count) {
            PyErr_SetString(PyExc_ValueError, "radius_bounds(): lists of one length");
            return NULL;
        }
    }
    if (count <= 0) {
        Py_RETURN_NONE;
    }
    double smallest = HUGE_VAL, largest = 0.0, difference = 0.0;
    for (Py_ssize_t i = 0; i < count; i++) {
        double v[6];
        for (int k = 0; k < 6; k++) {
            PyObject *item = PyList_GET_ITEM(args[k], i);
            if (!PyFloat_CheckExact(item)) {
                Py_RETURN_NONE;
            }
            v[k] = PyFloat_AS_DOUBLE(item);
        }
        double r1 = hypot(v[0] - v[2], v[1] - v[3]);
        double r2 = hypot(v[0] - v[4], v[1] - v[5]);
        if (!isfinite(r1) || !isfinite(r2)) {
            Py_RETURN_NONE;
        }
        smallest = fmin(smallest, fmin(r1, r2));
        largest = fmax(largest, fmax(r1, r2));
        difference = fmax(difference, fabs(r1 - r2));
    }
    return Py_BuildValue("(ddd)", smallest, largest, difference);
}

static PyMethodDef methods[] = {
    {"sin", sin_degrees, METH_O, "sinl((d * M_PIl) / 180.0) stored into a double"},
    {"cos", cos_degrees, METH_O, "cosl((d * M_PIl) / 180.0) stored into a double"},
    {"tan", tan_degrees, METH_O, "tanl((d * M_PIl) / 180.0) stored into a double"},
    {"configure", configure, METH_VARARGS, "configure(nonfinite, first_use)"},
    {"checked_sin", checked_sin, METH_O, "SIN[d]: the operand and the library checked"},
    {"checked_cos", checked_cos, METH_O, "COS[d]: the operand and the library checked"},
    {"checked_tan", checked_tan, METH_O, "TAN[d]: the operand and the library checked"},
    {"mod", (PyCFunction) (void (*)(void)) mod, METH_FASTCALL, "rs274's MOD"},
    {"finite", finite_or_raise, METH_O, "x when it is a finite float, else runtime.ops.finite(x)"},
    {"floats", floats, METH_O, "[float(s) for s in strs]"},
    {"divided", (PyCFunction) (void (*)(void)) divided, METH_FASTCALL,
     "divided(column, divisor): [value / divisor for value in column]"},
    {"radius_bounds", (PyCFunction) (void (*)(void)) radius_bounds, METH_FASTCALL,
     "(smallest radius, largest, largest start-end difference) of arcs, or None"},
    {NULL, NULL, 0, NULL},
};

static struct PyModuleDef module = {
    PyModuleDef_HEAD_INIT, "_libm_trig", "rs274's SIN, COS and TAN of degrees.", -1, methods,
};

PyMODINIT_FUNC PyInit__libm_trig(void) { return PyModule_Create(&module); }
