/* runtime._call_rows: a batch's canon calls made from its columns in C.
 *
 * A batch of moves reaches a back end as columns (runtime/canon.py, the
 * batch protocol); a canon that wants one call a move, the preview adapter
 * above all, then makes a Python call for each row of each column set. By
 * map, zip and starmap that costs, per row, an iterator step for every
 * column, an argument tuple and, for the preview's line codes, a tuple made
 * twice (tuple's constructor copies it into the subclass). call_rows reads
 * row k's arguments straight from the columns and hands them over as they
 * are (vectorcall: no tuple), and builds a line code in one allocation.
 *
 * runtime.canon.python_call_rows is its twin, held to it by
 * tests/test_call_rows.py. */

#define PY_SSIZE_T_CLEAN
#include <Python.h>

/* Columns of one call at most: arc_feed takes twelve. */
#define MOST_COLUMNS 16

typedef struct {
    PyObject *method;
    PyObject *columns[MOST_COLUMNS]; /* lists or tuples (references held) */
    Py_ssize_t width;
    PyTypeObject *kind; /* NULL: the values are the arguments */
    PyObject *mask;     /* list or tuple (held), or NULL: every row */
} step;

/* A column (or mask) as a list or a tuple, a new reference (a list or a
 * tuple as it is: PySequence_Fast), at least ``stop`` long or of one item
 * (which serves every row); NULL on error. */
static PyObject *column_of(PyObject *given, Py_ssize_t stop, const char *what) {
    PyObject *column = PySequence_Fast(given, "call_rows: a column must be a sequence");
    Py_ssize_t size = column ? PySequence_Fast_GET_SIZE(column) : 0;
    if (column && size < stop && size != 1) {
        PyErr_Format(PyExc_ValueError, "call_rows: a %s is shorter than the rows", what);
        Py_CLEAR(column);
    }
    return column;
}

static int read_step(PyObject *spec, step *s, Py_ssize_t stop) {
    if (!PyTuple_Check(spec) || PyTuple_GET_SIZE(spec) < 2 || PyTuple_GET_SIZE(spec) > 4) {
        PyErr_SetString(PyExc_TypeError,
                        "call_rows: a step is (method, columns[, kind[, mask]])");
        return -1;
    }
    Py_ssize_t size = PyTuple_GET_SIZE(spec);
    s->width = 0;
    s->mask = NULL;
    s->kind = NULL;
    s->method = PyTuple_GET_ITEM(spec, 0);
    PyObject *columns = PyTuple_GET_ITEM(spec, 1);
    if (!PyTuple_Check(columns) || PyTuple_GET_SIZE(columns) > MOST_COLUMNS) {
        PyErr_SetString(PyExc_TypeError, "call_rows: columns must be a tuple of at most 16");
        return -1;
    }
    for (Py_ssize_t j = 0; j < PyTuple_GET_SIZE(columns); j++) {
        s->columns[j] = column_of(PyTuple_GET_ITEM(columns, j), stop, "column");
        if (!s->columns[j]) {
            return -1;
        }
        s->width = j + 1;
    }
    if (size > 2 && PyTuple_GET_ITEM(spec, 2) != Py_None) {
        PyObject *kind = PyTuple_GET_ITEM(spec, 2);
        /* a tuple subclass adding no field: its items are its whole state */
        if (!PyType_Check(kind) || !PyType_IsSubtype((PyTypeObject *)kind, &PyTuple_Type) ||
            ((PyTypeObject *)kind)->tp_basicsize != PyTuple_Type.tp_basicsize ||
            ((PyTypeObject *)kind)->tp_dictoffset != 0) {
            PyErr_SetString(PyExc_TypeError,
                            "call_rows: kind must be a tuple subclass with no fields");
            return -1;
        }
        s->kind = (PyTypeObject *)kind;
    }
    if (size > 3 && PyTuple_GET_ITEM(spec, 3) != Py_None) {
        s->mask = column_of(PyTuple_GET_ITEM(spec, 3), stop, "mask");
        if (!s->mask) {
            return -1;
        }
    }
    return 0;
}

static void release_step(step *s) {
    for (Py_ssize_t j = 0; j < s->width; j++) {
        Py_DECREF(s->columns[j]);
    }
    Py_XDECREF(s->mask);
}

/* Row ``row``'s item of a column: its only item, for a column of one. */
static PyObject *item_at(PyObject *column, Py_ssize_t row) {
    return PySequence_Fast_ITEMS(column)[PySequence_Fast_GET_SIZE(column) == 1 ? 0 : row];
}

/* One call of one row; 0, or -1 with the error set. */
static int call_one(step *s, Py_ssize_t row) {
    PyObject *args[MOST_COLUMNS];
    PyObject *result;
    /* held while the call runs: a method could change a list it knows */
    for (Py_ssize_t j = 0; j < s->width; j++) {
        args[j] = item_at(s->columns[j], row);
        Py_INCREF(args[j]);
    }
    if (s->kind) {
        PyObject *made = s->kind->tp_alloc(s->kind, s->width);
        if (!made) {
            for (Py_ssize_t j = 0; j < s->width; j++) {
                Py_DECREF(args[j]);
            }
            return -1;
        }
        for (Py_ssize_t j = 0; j < s->width; j++) {
            PyTuple_SET_ITEM(made, j, args[j]); /* (the reference taken above) */
        }
        result = PyObject_CallOneArg(s->method, made);
        Py_DECREF(made);
    } else {
        result = PyObject_Vectorcall(s->method, args, s->width, NULL);
        for (Py_ssize_t j = 0; j < s->width; j++) {
            Py_DECREF(args[j]);
        }
    }
    if (!result) {
        return -1;
    }
    Py_DECREF(result);
    return 0;
}

static PyObject *call_rows(PyObject *self, PyObject *const *argv, Py_ssize_t argc) {
    if (argc != 3) {
        PyErr_SetString(PyExc_TypeError, "call_rows(start, stop, steps)");
        return NULL;
    }
    Py_ssize_t start = PyLong_AsSsize_t(argv[0]);
    Py_ssize_t stop = PyLong_AsSsize_t(argv[1]);
    if ((start == -1 || stop == -1) && PyErr_Occurred()) {
        return NULL;
    }
    if (start < 0 || stop < start) {
        PyErr_SetString(PyExc_ValueError, "call_rows: 0 <= start <= stop");
        return NULL;
    }
    /* the steps tuple keeps every column alive; its tuples cannot change */
    PyObject *specs = PySequence_Tuple(argv[2]);
    if (!specs) {
        return NULL;
    }
    Py_ssize_t count = PyTuple_GET_SIZE(specs);
    step *steps = PyMem_Calloc(count ? count : 1, sizeof(step));
    if (!steps) {
        Py_DECREF(specs);
        return PyErr_NoMemory();
    }
    PyObject *answer = NULL;
    for (Py_ssize_t k = 0; k < count; k++) {
        if (read_step(PyTuple_GET_ITEM(specs, k), &steps[k], stop) < 0) {
            goto done;
        }
    }
    for (Py_ssize_t row = start; row < stop; row++) {
        for (Py_ssize_t k = 0; k < count; k++) {
            step *s = &steps[k];
            if (s->mask) {
                int on = PyObject_IsTrue(item_at(s->mask, row));
                if (on < 0) {
                    goto done;
                }
                if (!on) {
                    continue;
                }
            }
            /* a method may shorten a list it was given: read it again */
            for (Py_ssize_t j = 0; j < s->width; j++) {
                Py_ssize_t size = PySequence_Fast_GET_SIZE(s->columns[j]);
                if (size <= row && size != 1) {
                    PyErr_SetString(PyExc_RuntimeError, "call_rows: a column changed size");
                    goto done;
                }
            }
            if (s->mask && PySequence_Fast_GET_SIZE(s->mask) <= row &&
                PySequence_Fast_GET_SIZE(s->mask) != 1) {
                PyErr_SetString(PyExc_RuntimeError, "call_rows: a mask changed size");
                goto done;
            }
            if (call_one(s, row) < 0) {
                if (PyErr_ExceptionMatches(PyExc_StopIteration)) {
                    /* as the Python twin says it: a StopIteration must not
                     * pass for the end of a batch */
                    PyObject *type, *value, *trace;
                    PyErr_Fetch(&type, &value, &trace);
                    Py_XDECREF(type);
                    Py_XDECREF(value);
                    Py_XDECREF(trace);
                    PyErr_SetString(PyExc_RuntimeError,
                                    "a canon method raised StopIteration");
                }
                goto done;
            }
        }
    }
    Py_INCREF(Py_None);
    answer = Py_None;
done:
    for (Py_ssize_t k = 0; k < count; k++) {
        release_step(&steps[k]);
    }
    PyMem_Free(steps);
    Py_DECREF(specs);
    return answer;
}

static PyMethodDef methods[] = {
    {"call_rows", (PyCFunction)(void (*)(void))call_rows, METH_FASTCALL,
     "call_rows(start, stop, steps): for each row from start to stop, each "
     "step's call (see runtime.canon.python_call_rows)."},
    {NULL, NULL, 0, NULL},
};

static struct PyModuleDef module = {
    PyModuleDef_HEAD_INIT, "runtime._call_rows",
    "A batch's canon calls made from its columns (runtime/canon.py).", -1, methods,
};

PyMODINIT_FUNC PyInit__call_rows(void) { return PyModule_Create(&module); }
