/*
 * arc_row(cells, at, recipe, motion_mode, cur, feed_rate, geometry): what
 * runtime.fast.arc_rows.ArcRows._arc_row answers, with its arithmetic in C.
 *
 * The Python loop over a run of arc rows spends most of its time in that
 * one function: reading the row's words, the centre of an R arc and the
 * radius checks of an I J K arc, about three microseconds a row. Here they
 * take a few hundred nanoseconds. The answer is the same object for object:
 * (motion, N, F or None, end point, centre's two coordinates), or None where
 * the general path must decide.
 *
 * The R centre is rs274's arc_data_r step for step, which C states more
 * directly than Python can: the angle plus or minus M_PI_2l is a long double
 * sum stored into a double (runtime/ops.py plus_half_pi emulates it), and
 * hypot, atan2, asin, cos and sin are the C library's, the ones rs274 calls.
 * The I J K checks keep the Python version's margin, so both versions step
 * aside on exactly the same rows whatever hypot's last bit.
 *
 * Optional: runtime/fast/arc_rows.py runs its Python version where this was
 * not built (setup.py), with identical results (tests/test_arc_row.py).
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <math.h>

#include "../plain_decimal.h"

/* runtime.codes: G2 and G3 are the ints 20 and 30 */
#define G_2 20
#define G_3 30

/* arc_rows._MARGIN and arcs._SEMICIRCLE_SLACK (rs274's TINY) */
#define MARGIN 1e-14
#define SEMICIRCLE_SLACK 1e-12

/* int(text) of a table cell (a row's G-code line): its digits read here
 * when it is one to eighteen ASCII digits, the usual case; else what int()
 * makes of it. A new reference, or NULL with an exception set. */
static PyObject *cell_int(PyObject *text) {
    if (PyUnicode_CheckExact(text) && PyUnicode_IS_ASCII(text)) {
        Py_ssize_t size = PyUnicode_GET_LENGTH(text);
        const char *s = (const char *) PyUnicode_DATA(text);
        long long value = 0;
        Py_ssize_t i = 0;
        while (i < size && i < 18 && s[i] >= '0' && s[i] <= '9') {
            value = value * 10 + (s[i++] - '0');
        }
        if (i == size && size > 0) {
            return PyLong_FromLongLong(value);
        }
    }
    return PyLong_FromUnicodeObject(text, 10);
}

/* float(text) of a table cell; -1 with an exception set on failure. */
static int cell_float(PyObject *cells, Py_ssize_t at, double *out) {
    if (at < 0 || at >= PyList_GET_SIZE(cells)) {
        PyErr_SetString(PyExc_IndexError, "row beyond the table");
        return -1;
    }
    PyObject *text = PyList_GET_ITEM(cells, at);
    if (PyUnicode_CheckExact(text) && PyUnicode_IS_ASCII(text)) {
        Py_ssize_t size = PyUnicode_GET_LENGTH(text);
        const char *s = (const char *) PyUnicode_DATA(text);
        char *end = NULL;
        if (plain_decimal(s, size, out)) {
            return 0;
        }
        if (size > 0 && s[0] != ' ' && s[size - 1] != ' ') {
            double value = PyOS_string_to_double(s, &end, NULL);
            if (end == s + size) {
                *out = value;
                return 0;
            }
            if (value == -1.0 && PyErr_Occurred()) {
                PyErr_Clear();
            }
        }
    }
    /* anything unusual: exactly what float() does */
    PyObject *number = PyFloat_FromString(text);
    if (number == NULL) {
        return -1;
    }
    *out = PyFloat_AS_DOUBLE(number);
    Py_DECREF(number);
    return 0;
}

static int tuple_ssize(PyObject *tuple, Py_ssize_t i, Py_ssize_t *out) {
    *out = PyLong_AsSsize_t(PyTuple_GET_ITEM(tuple, i));
    return (*out == -1 && PyErr_Occurred()) ? -1 : 0;
}

static int tuple_double(PyObject *tuple, Py_ssize_t i, double *out) {
    *out = PyFloat_AsDouble(PyTuple_GET_ITEM(tuple, i));
    return (*out == -1.0 && PyErr_Occurred()) ? -1 : 0;
}

static int list_double(PyObject *list, Py_ssize_t i, double *out) {
    if (i < 0 || i >= PyList_GET_SIZE(list)) {
        PyErr_SetString(PyExc_IndexError, "axis beyond the point");
        return -1;
    }
    *out = PyFloat_AsDouble(PyList_GET_ITEM(list, i));
    return (*out == -1.0 && PyErr_Occurred()) ? -1 : 0;
}

/* The centre of an R arc by arc_data_r's operations; 0 when R is too short
 * to reach the end point (the caller steps aside). */
static int radius_centre(int clockwise, double s1, double s2, double e1, double e2,
                         double radius, double zero, double *c1, double *c2) {
    double abs_radius = fabs(radius);
    double mid1 = (e1 + s1) / 2.0;
    double mid2 = (e2 + s2) / 2.0;
    double half = hypot(mid1 - e1, mid2 - e2);
    if (half - abs_radius > zero) {
        return 0;
    }
    if (half / abs_radius > 1 - SEMICIRCLE_SLACK) {
        half = abs_radius;
    }
    double theta;
    if (clockwise == (radius > 0)) {
        theta = atan2(e2 - s2, e1 - s1) - M_PI_2l;
    } else {
        theta = atan2(e2 - s2, e1 - s1) + M_PI_2l;
    }
    double offset = abs_radius * cos(asin(half / abs_radius));
    *c1 = mid1 + offset * cos(theta);
    *c2 = mid2 + offset * sin(theta);
    return 1;
}

/* The parts of a recipe (motion, has_n, f_at, width, slots, r_at, i1, i2)
 * and of a geometry (p1, p2, p3, absolute, zero, spiral). */
typedef struct {
    PyObject *motion, *slots;
    int has_n;
    Py_ssize_t f_at, width, r_at, i1, i2;
} recipe_t;

typedef struct {
    Py_ssize_t p1, p2, p3;
    int absolute;
    double zero, spiral;
} geometry_t;

static int read_recipe(PyObject *recipe, recipe_t *r) {
    if (!PyTuple_CheckExact(recipe) || PyTuple_GET_SIZE(recipe) != 8) {
        PyErr_SetString(PyExc_TypeError, "arc_row: a recipe is a tuple of 8");
        return -1;
    }
    r->motion = PyTuple_GET_ITEM(recipe, 0);
    r->slots = PyTuple_GET_ITEM(recipe, 4);
    r->has_n = PyObject_IsTrue(PyTuple_GET_ITEM(recipe, 1));
    if (r->has_n < 0 || tuple_ssize(recipe, 2, &r->f_at) ||
        tuple_ssize(recipe, 3, &r->width) || tuple_ssize(recipe, 5, &r->r_at) ||
        tuple_ssize(recipe, 6, &r->i1) || tuple_ssize(recipe, 7, &r->i2)) {
        return -1;
    }
    return 0;
}

static int read_geometry(PyObject *geometry, geometry_t *g) {
    if (!PyTuple_CheckExact(geometry) || PyTuple_GET_SIZE(geometry) != 6) {
        PyErr_SetString(PyExc_TypeError, "arc_row: a geometry is a tuple of 6");
        return -1;
    }
    g->absolute = PyObject_IsTrue(PyTuple_GET_ITEM(geometry, 3));
    if (tuple_ssize(geometry, 0, &g->p1) || tuple_ssize(geometry, 1, &g->p2) ||
        tuple_ssize(geometry, 2, &g->p3) || g->absolute < 0 ||
        tuple_double(geometry, 4, &g->zero) || tuple_double(geometry, 5, &g->spiral)) {
        return -1;
    }
    return 0;
}

/* The current point with the row's axis words (slots of (value index, axis
 * index) from ``start``): a new list, or NULL with an exception set. */
static PyObject *end_point(PyObject *cells, Py_ssize_t start, PyObject *slots,
                           PyObject *cur) {
    if (!PyList_CheckExact(cur)) {
        PyErr_SetString(PyExc_TypeError, "arc_row: the point is a list");
        return NULL;
    }
    Py_ssize_t axes = PyList_GET_SIZE(cur);
    PyObject *point = PyList_GetSlice(cur, 0, axes);
    if (point == NULL) {
        return NULL;
    }
    if (!PyTuple_CheckExact(slots) && !PyList_CheckExact(slots)) {
        PyErr_SetString(PyExc_TypeError, "arc_row: slots are a tuple or a list");
        Py_DECREF(point);
        return NULL;
    }
    for (Py_ssize_t k = 0; k < PySequence_Fast_GET_SIZE(slots); k++) {
        PyObject *slot = PySequence_Fast_GET_ITEM(slots, k);
        Py_ssize_t i, axis;
        double value;
        if (!PyTuple_CheckExact(slot) || PyTuple_GET_SIZE(slot) != 2 ||
            tuple_ssize(slot, 0, &i) || tuple_ssize(slot, 1, &axis) ||
            cell_float(cells, start + i, &value)) {
            if (!PyErr_Occurred()) {
                PyErr_SetString(PyExc_TypeError, "arc_row: a slot is (index, axis)");
            }
            Py_DECREF(point);
            return NULL;
        }
        if (axis < 0 || axis >= axes) {
            PyErr_SetString(PyExc_IndexError, "axis beyond the point");
            Py_DECREF(point);
            return NULL;
        }
        PyObject *number = PyFloat_FromDouble(value);
        if (number == NULL) {
            Py_DECREF(point);
            return NULL;
        }
        PyObject *old = PyList_GET_ITEM(point, axis);
        PyList_SET_ITEM(point, axis, number);
        Py_DECREF(old);
    }
    return point;
}

/* The arc of the row whose words begin at ``start``, from ``cur``, in
 * motion ``code``: its end point in *point and its centre in c, 1; 0 where
 * the general path must decide (nothing made); -1 on an exception. */
static int arc_of_row(PyObject *cells, Py_ssize_t start, const recipe_t *r,
                      const geometry_t *g, int code, PyObject *cur, PyObject **point,
                      double *c1, double *c2) {
    double s1, s2, e1, e2;
    if (list_double(cur, g->p1, &s1) || list_double(cur, g->p2, &s2)) {
        return -1;
    }
    PyObject *end = end_point(cells, start, r->slots, cur);
    if (end == NULL) {
        return -1;
    }
    if (list_double(end, g->p1, &e1) || list_double(end, g->p2, &e2)) {
        Py_DECREF(end);
        return -1;
    }
    if (r->r_at < 0) {
        double v1 = 0.0, v2 = 0.0;
        if ((r->i1 >= 0 && cell_float(cells, start + r->i1, &v1)) ||
            (r->i2 >= 0 && cell_float(cells, start + r->i2, &v2))) {
            Py_DECREF(end);
            return -1;
        }
        if (g->absolute) {
            *c1 = v1;
            *c2 = v2;
        } else {
            *c1 = s1 + v1;
            *c2 = s2 + v2;
        }
        double r1 = hypot(*c1 - s1, *c2 - s2);
        double r2 = hypot(*c1 - e1, *c2 - e2);
        if (r1 < r2) {
            double swap = r1;
            r1 = r2;
            r2 = swap;
        }
        /* written as the Python version's test, NaN included */
        if (!(r2 * (1 - MARGIN) >= g->zero && (r1 - r2) + r1 * MARGIN <= g->spiral)) {
            Py_DECREF(end);
            return 0;
        }
    } else {
        double radius;
        if (cell_float(cells, start + r->r_at, &radius)) {
            Py_DECREF(end);
            return -1;
        }
        /* R 0 and an end at the start: rs274 fails or divides by zero */
        if (radius == 0.0 || (e1 == s1 && e2 == s2) ||
            !radius_centre(code == G_2, s1, s2, e1, e2, radius, g->zero, c1, c2)) {
            Py_DECREF(end);
            return 0;
        }
    }
    *point = end;
    return 1;
}

/* The code of a motion object (an int), -1 for anything else. */
static long motion_code(PyObject *motion) {
    if (!PyLong_CheckExact(motion)) {
        return -1;
    }
    long code = PyLong_AsLong(motion);
    if (code == -1 && PyErr_Occurred()) {
        PyErr_Clear();
    }
    return code;
}

static PyObject *arc_row(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    if (nargs != 7) {
        PyErr_SetString(PyExc_TypeError, "arc_row takes 7 arguments");
        return NULL;
    }
    PyObject *cells = args[0], *motion_mode = args[3], *cur = args[4];
    recipe_t r;
    geometry_t g;
    if (!PyList_CheckExact(cells) || read_recipe(args[2], &r) ||
        read_geometry(args[6], &g)) {
        if (!PyErr_Occurred()) {
            PyErr_SetString(PyExc_TypeError, "arc_row: the cells are a list");
        }
        return NULL;
    }
    Py_ssize_t at = PyLong_AsSsize_t(args[1]);
    if (at == -1 && PyErr_Occurred()) {
        return NULL;
    }
    double feed_rate = PyFloat_AsDouble(args[5]);
    if (feed_rate == -1.0 && PyErr_Occurred()) {
        return NULL;
    }
    PyObject *motion = r.motion == Py_None ? motion_mode : r.motion;
    long code = motion_code(motion);
    if (r.motion == Py_None && code != G_2 && code != G_3) {
        Py_RETURN_NONE; /* modal: an arc only in G2 or G3 */
    }
    PyObject *n = Py_None;
    Py_ssize_t start = at + 2;
    if (r.has_n) {
        if (at + 2 >= PyList_GET_SIZE(cells)) {
            PyErr_SetString(PyExc_IndexError, "row beyond the table");
            return NULL;
        }
        n = PyList_GET_ITEM(cells, at + 2);
        start = at + 3;
    }
    double f = 0.0;
    if (r.f_at >= 0) {
        if (cell_float(cells, start + r.f_at, &f)) {
            return NULL;
        }
        if (f <= 0.0) { /* negative or zero: errors the general path raises */
            Py_RETURN_NONE;
        }
    } else if (feed_rate == 0.0) {
        Py_RETURN_NONE;
    }
    PyObject *point = NULL;
    double c1, c2;
    int made = arc_of_row(cells, start, &r, &g, code, cur, &point, &c1, &c2);
    if (made <= 0) {
        if (made < 0) {
            return NULL;
        }
        Py_RETURN_NONE;
    }
    PyObject *f_object = Py_None;
    if (r.f_at >= 0) {
        f_object = PyFloat_FromDouble(f);
        if (f_object == NULL) {
            Py_DECREF(point);
            return NULL;
        }
    } else {
        Py_INCREF(f_object);
    }
    return Py_BuildValue("(OONNdd)", motion, n, f_object, point, c1, c2);
}

/* _Pending.columns, borrowed from the pending object's list (read again
 * after each hand-over, which starts new lists): the held arcs' G-code lines,
 * then arc_feed's twelve arguments, one list each, and for a canon that
 * takes N numbers with its batches (``numbers``, else NULL) each row's N. */
#define HELD_COLUMNS 13

/* The XY plane's name, as select_plane takes it (made once). */
static PyObject *plane_xy = NULL;
typedef struct {
    PyObject *column[HELD_COLUMNS];
    PyObject *numbers;
    /* _Pending.planes: the held rows restating G17, for a canon taking
     * planes with its batches (else NULL) */
    PyObject *planes;
} held_t;

static int read_held(PyObject *pending, held_t *held) {
    PyObject *columns = PyObject_GetAttrString(pending, "columns");
    if (columns == NULL) {
        return -1;
    }
    Py_ssize_t size = PyList_CheckExact(columns) ? PyList_GET_SIZE(columns) : 0;
    int bad = size != HELD_COLUMNS && size != HELD_COLUMNS + 1;
    for (Py_ssize_t k = 0; !bad && k < size; k++) {
        bad = !PyList_CheckExact(PyList_GET_ITEM(columns, k));
        if (k < HELD_COLUMNS) {
            held->column[k] = PyList_GET_ITEM(columns, k);
        }
    }
    held->numbers = !bad && size > HELD_COLUMNS ? PyList_GET_ITEM(columns, HELD_COLUMNS) : NULL;
    Py_DECREF(columns); /* (pending keeps it) */
    if (bad) {
        PyErr_SetString(PyExc_TypeError, "rows: the held arcs are thirteen or fourteen lists");
        return -1;
    }
    PyObject *planes = PyObject_GetAttrString(pending, "planes");
    if (planes == NULL) {
        return -1;
    }
    held->planes = PyList_CheckExact(planes) ? planes : NULL;
    Py_DECREF(planes); /* (pending keeps it, or it is None) */
    return 0;
}

/* Append to the held columns what _Pending.hold keeps of an arc: its G-code
 * line (the int of ``line``, a cell), arc_feed's twelve arguments and, for
 * a canon taking numbers, the row's N ``n``. A new reference to None, or
 * NULL with an exception set. */
static PyObject *hold(held_t *held, PyObject *line, PyObject **call, PyObject *n) {
    PyObject *number = cell_int(line);
    if (number == NULL) {
        return NULL;
    }
    int failed = PyList_Append(held->column[0], number);
    Py_DECREF(number);
    for (int k = 0; !failed && k < 12; k++) {
        failed = PyList_Append(held->column[k + 1], call[k]);
    }
    if (!failed && held->numbers != NULL) {
        failed = PyList_Append(held->numbers, n);
    }
    if (failed) {
        return NULL;
    }
    Py_RETURN_NONE;
}

/* The row about to be held restates G17: its index among the held rows
 * appended to _Pending.planes. 0, or -1 with an exception. */
static int mark_plane(held_t *held) {
    PyObject *index = PyLong_FromSsize_t(PyList_GET_SIZE(held->column[0]));
    int failed = index == NULL || PyList_Append(held->planes, index) < 0;
    Py_XDECREF(index);
    return failed ? -1 : 0;
}

/* straight_row: the end point of a plain straight move (the straight
 * table's (motion, has_n, f_at, width, slots)) without N or F, or NULL with
 * *stop set where the loop must stop (no exception) */
#define G_0 0
#define G_1 10
#define STRETCH 8 /* arc_rows._BATCH: a stretch printed_rows writes at once */

/* straight_moves(feed, [line], [x], ..., [w]): a straight row as a batch of
 * one, for a canon that takes its plain rows in batches (the preview's,
 * flatten's: runtime.fast.rows.BatchesOnly). A new reference, or NULL. */
static PyObject *one_row_batch(PyObject *straight_moves, int feed, PyObject *line,
                               PyObject *point) {
    PyObject *call[11] = {NULL};
    call[0] = feed ? Py_True : Py_False;
    PyObject *result = NULL;
    PyObject *number = cell_int(line);
    if (number != NULL) {
        call[1] = PyList_New(1);
        if (call[1] != NULL) {
            PyList_SET_ITEM(call[1], 0, number);
            number = NULL;
        }
    }
    Py_XDECREF(number);
    int made = call[1] != NULL;
    for (int k = 0; made && k < 9; k++) {
        call[2 + k] = PyList_New(1);
        if (call[2 + k] == NULL) {
            made = 0;
            break;
        }
        PyObject *value = PyList_GET_ITEM(point, k);
        Py_INCREF(value);
        PyList_SET_ITEM(call[2 + k], 0, value);
    }
    if (made) {
        result = PyObject_Vectorcall(straight_moves, call, 11, NULL);
    }
    for (int k = 1; k < 11; k++) {
        Py_XDECREF(call[k]);
    }
    return result;
}

/* Before a row's own calls in a run holding arcs: the machine's line set
 * to the row's (``line_machine``, when the canon reads it), then the held
 * arcs handed to the canon (pending.flush()). 0, or -1 with an exception. */
static int hand_over(PyObject *pending, held_t *held, PyObject *line_machine,
                     PyObject *line) {
    if (line_machine != NULL) {
        PyObject *number = cell_int(line);
        int failed = number == NULL || PyObject_SetAttrString(line_machine, "line", number) < 0;
        Py_XDECREF(number);
        if (failed) {
            return -1;
        }
    }
    if (PyList_GET_SIZE(held->column[0]) == 0) {
        return 0;
    }
    PyObject *result = PyObject_CallMethod(pending, "flush", NULL);
    if (result == NULL) {
        return -1;
    }
    Py_DECREF(result);
    return read_held(pending, held);
}

/* rows(cells, at, end, known, straight, geometry, state, arc_feed,
 * straight_feed, straight_traverse, set_block_number, set_feed_rate,
 * select_plane, plane_arcs[, pending, explicit_only, machine,
 * straight_moves, contours]): ArcRows.run's loop for the rows of a
 * contour (arcs and the plain lines between them), for a canon that takes
 * each move as a call (the trace): their N and F words too, as the Python
 * loop makes them. ``known`` maps a row's shape cell to its arc recipe
 * (None: not an arc), ``straight`` to its straight move; a shape in
 * neither, or a row the general path must decide, ends the loop.
 *
 * With ``pending`` (arc_rows._Pending, for a canon that takes arcs in
 * batches), each arc is appended to pending.columns as _Pending.hold keeps it
 * (pending.start set where a batch begins), and the held arcs go to the
 * canon (pending.flush()) before any other call: a straight row's, or an N
 * or F word's. For a canon that takes N numbers with its batches (the
 * pending's fourteenth column), an arc or contour line without F is held
 * with its N instead, which hands nothing over. ``machine`` (None: the canon does not read lines) gets the
 * line of each row whose calls are made here, before they are made, as the
 * Python loop sets it. ``set_block_number`` None: the canon ignores N
 * numbers (none is called, and an N hands no held arcs over). With
 * ``explicit_only`` (a BatchesOnly machine) only arcs without F (and N,
 * unless the canon ignores it) in an explicit G2/G3 are taken and, given
 * ``straight_moves`` (else None), the plain straight rows without N or F
 * between them, each as a batch of one (as runtime.fast.rows would hand it
 * over: the canon sees its line as a batch's). With ``contours`` (a canon
 * taking Canon.contour_moves), a plain G1 row without N or F is held too,
 * as a row of rotation 0, instead of cutting the batch.
 *
 * An arc whose shape cell is in ``plane_arcs`` (a set: ``G17 G2 ...``, the
 * plane restated, in the XY plane) makes select_plane("XY") between its F
 * and its motion, as Machine.plain_arc does; held arcs go to the canon
 * before it, and a BatchesOnly machine's loop stops at such a row.
 * ``select_plane`` None: the canon's is the protocol's no-op (not called,
 * and no held arcs handed over for it).
 *
 * ``state`` is ArcRows.run's list [point, motion, row, N, feed rate, F
 * given, ...]: on return, even with an exception from a canon call, it holds
 * what the rows done leave, and row is where the last row looked at begins
 * (the Python loop's ``row``; unchanged when there was none). Returns where
 * it stopped. */
static PyObject *rows(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    if (nargs != 14 && nargs != 19) {
        PyErr_SetString(PyExc_TypeError, "rows takes 14 or 19 arguments");
        return NULL;
    }
    PyObject *pending = nargs == 19 ? args[14] : NULL;
    int explicit_only = nargs == 19 ? PyObject_IsTrue(args[15]) : 0;
    PyObject *line_machine = nargs == 19 && args[16] != Py_None ? args[16] : NULL;
    PyObject *straight_moves = nargs == 19 && args[17] != Py_None ? args[17] : NULL;
    int contours = nargs == 19 ? PyObject_IsTrue(args[18]) : 0;
    PyObject *select_plane = args[12], *plane_arcs = args[13];
    if (!PyAnySet_Check(plane_arcs)) {
        PyErr_SetString(PyExc_TypeError, "rows: plane_arcs is a set");
        return NULL;
    }
    int any_plane_arcs = PySet_GET_SIZE(plane_arcs) > 0;
    if (explicit_only < 0 || contours < 0) {
        return NULL;
    }
    held_t columns, *held = NULL;
    if (pending != NULL) {
        if (read_held(pending, &columns)) {
            return NULL;
        }
        held = &columns;
    }
    PyObject *cells = args[0], *known = args[3], *straight = args[4];
    PyObject *state = args[6];
    PyObject *arc_feed = args[7], *straight_feed = args[8], *straight_traverse = args[9];
    PyObject *set_block_number = args[10], *set_feed_rate = args[11];
    /* None: the canon ignores N numbers (its set_block_number is the
     * protocol's no-op), so an N neither is called nor hands held arcs over */
    int ignores_n = set_block_number == Py_None;
    geometry_t g;
    if (!PyList_CheckExact(cells) || !PyDict_CheckExact(known) ||
        !PyDict_CheckExact(straight) || !PyList_CheckExact(state) ||
        PyList_GET_SIZE(state) < 6 || read_geometry(args[5], &g)) {
        if (!PyErr_Occurred()) {
            PyErr_SetString(PyExc_TypeError, "rows: unexpected argument types");
        }
        return NULL;
    }
    Py_ssize_t at = PyLong_AsSsize_t(args[1]);
    Py_ssize_t end = PyLong_AsSsize_t(args[2]);
    double feed_rate = PyFloat_AsDouble(PyList_GET_ITEM(state, 4));
    int feed_given = PyObject_IsTrue(PyList_GET_ITEM(state, 5));
    if (PyErr_Occurred() || feed_given < 0) {
        return NULL;
    }
    if (end > PyList_GET_SIZE(cells)) {
        end = PyList_GET_SIZE(cells);
    }
    PyObject *cur = PyList_GET_ITEM(state, 0);
    PyObject *motion_mode = PyList_GET_ITEM(state, 1);
    PyObject *block_n = PyList_GET_ITEM(state, 3);
    Py_INCREF(cur);
    Py_INCREF(motion_mode);
    Py_INCREF(block_n);
    Py_ssize_t row = -1;
    int failed = 0, feed_changed = 0;
    PyObject *call[12];
    while (at + 1 < end) {
        row = at;
        PyObject *key = PyList_GET_ITEM(cells, at + 1);
        PyObject *recipe = PyDict_GetItemWithError(known, key);
        PyObject *point = NULL, *motion, *line = NULL;
        recipe_t r;
        Py_ssize_t has_n, f_at, width;
        long code;
        if (recipe == NULL) {
            failed = PyErr_Occurred() != NULL;
            break; /* (no recipe yet: the Python loop makes it) */
        }
        if (recipe == Py_None) {
            if (explicit_only && straight_moves == NULL) {
                break; /* the general path: the canon sees its line begin */
            }
            /* a plain straight move between arcs (ArcRows._straight_row) */
            line = PyDict_GetItemWithError(straight, key);
            if (line == NULL || !PyTuple_CheckExact(line) || PyTuple_GET_SIZE(line) != 5) {
                failed = PyErr_Occurred() != NULL;
                break;
            }
            if (tuple_ssize(line, 1, &has_n) || tuple_ssize(line, 2, &f_at) ||
                tuple_ssize(line, 3, &width)) {
                failed = 1;
                break;
            }
            Py_ssize_t stride = 2 + width;
            if (end - at >= stride * STRETCH) {
                int same = PyObject_RichCompareBool(
                    PyList_GET_ITEM(cells, at + 1 + stride * (STRETCH - 1)), key, Py_EQ);
                if (same) {
                    failed = same < 0;
                    break; /* a stretch for runtime.fast.printed_rows */
                }
            }
            motion = PyTuple_GET_ITEM(line, 0);
        } else {
            if (read_recipe(recipe, &r)) {
                failed = 1;
                break;
            }
            has_n = r.has_n;
            f_at = r.f_at;
            width = r.width;
            if (explicit_only && r.motion == Py_None) {
                break;
            }
            motion = r.motion;
        }
        if (at + 2 + width > end || (has_n && width < 1)) {
            break;
        }
        if (motion == Py_None) {
            motion = motion_mode;
        }
        code = motion_code(motion);
        /* an arc restating the plane: SELECT_PLANE before its motion */
        int selects = 0, told_plane = 0;
        if (line == NULL && any_plane_arcs) {
            selects = PySet_Contains(plane_arcs, key);
            if (selects < 0) {
                failed = 1;
                break;
            }
            if (selects && held != NULL && held->planes != NULL) {
                /* held, the canon told: its SELECT_PLANE after the line begins */
                told_plane = 1;
            } else if (selects && explicit_only) {
                break; /* (the canon sees its line begin: the general path) */
            }
            /* (None: a no-op) */
            selects = selects && select_plane != Py_None && !told_plane;
        }
        /* held with its N, for a canon that takes numbers with its batches:
         * an arc, or a contour's plain G1 line, without an F (whose call
         * comes after the N) */
        int numbered = held != NULL && held->numbers != NULL && f_at < 0 &&
                       (line == NULL || (contours && code == G_1));
        if (explicit_only && ((has_n && !ignores_n && !numbered) || f_at >= 0)) {
            break;
        }
        PyObject *n = has_n ? PyList_GET_ITEM(cells, at + 2) : Py_None;
        Py_ssize_t start = at + 2 + (has_n ? 1 : 0);
        double f = 0.0;
        if (f_at >= 0 && cell_float(cells, start + f_at, &f)) {
            failed = 1;
            break;
        }
        double c1 = 0.0, c2 = 0.0;
        if (line != NULL) {
            double rate = f_at >= 0 ? f : feed_rate;
            if (!((code == G_1 && rate > 0.0) || (code == G_0 && !(f_at >= 0 && f < 0.0)))) {
                break;
            }
            point = end_point(cells, start, PyTuple_GET_ITEM(line, 4), cur);
            if (point == NULL) {
                failed = 1;
                break;
            }
        } else {
            if (code != G_2 && code != G_3) {
                break;
            }
            if (f_at >= 0 ? f <= 0.0 : feed_rate == 0.0) {
                break; /* no feed, or a negative one: errors */
            }
            int made = arc_of_row(cells, start, &r, &g, code, cur, &point, &c1, &c2);
            if (made <= 0) {
                failed = made < 0;
                break;
            }
        }
        if (PyList_GET_SIZE(point) != 9) {
            Py_DECREF(point);
            PyErr_SetString(PyExc_TypeError, "rows: a point of nine axes");
            failed = 1;
            break;
        }
        /* the calls: N, F, then the move (as the Python loop makes them) */
        int other = n == block_n ? 0 : PyObject_RichCompareBool(n, block_n, Py_NE);
        PyObject *result = NULL;
        /* a contour's straight feed, held with its arcs */
        int n_call = other != 0 && !ignores_n && !numbered; /* (other < 0: an error) */
        int held_line = contours && held != NULL && line != NULL && code == G_1 &&
                        !n_call && f_at < 0;
        if (held != NULL && ((line != NULL && !held_line) || n_call || f_at >= 0 || selects)) {
            /* calls of this row's own: the held arcs go to the canon first */
            if (other < 0 || hand_over(pending, held, line_machine, PyList_GET_ITEM(cells, at))) {
                Py_DECREF(point);
                failed = 1;
                break;
            }
        }
        if (other > 0) {
            if (ignores_n || numbered) {
                Py_INCREF(Py_None);
                result = Py_None;
            } else {
                result = PyObject_CallOneArg(set_block_number, n);
            }
            if (result != NULL) {
                Py_DECREF(result);
                Py_INCREF(n);
                Py_SETREF(block_n, n);
            }
        }
        if (other < 0 || (other > 0 && result == NULL)) {
            Py_DECREF(point);
            failed = 1;
            break;
        }
        if (f_at >= 0) {
            feed_rate = f; /* (before the call, as the Python loop does) */
            feed_given = feed_changed = 1;
            PyObject *rate = PyFloat_FromDouble(f);
            result = rate == NULL ? NULL : PyObject_CallOneArg(set_feed_rate, rate);
            Py_XDECREF(rate);
            if (result == NULL) {
                Py_DECREF(point);
                failed = 1;
                break;
            }
            Py_DECREF(result);
        }
        if (selects) {
            result = PyObject_CallOneArg(select_plane, plane_xy);
            if (result == NULL) {
                Py_DECREF(point);
                failed = 1;
                break;
            }
            Py_DECREF(result);
        }
        if (line != NULL && !held_line && explicit_only) {
            result = one_row_batch(straight_moves, code == G_1, PyList_GET_ITEM(cells, at), point);
        } else if (line != NULL && !held_line) {
            result = PyObject_Vectorcall(code == G_1 ? straight_feed : straight_traverse,
                                         &PyList_GET_ITEM(point, 0), 9, NULL);
        } else {
            /* an arc (a contour's line held with them: rotation 0, no centre) */
            PyObject *centre1 = PyFloat_FromDouble(c1);
            PyObject *centre2 = PyFloat_FromDouble(c2);
            PyObject *rotation = PyLong_FromLong(held_line ? 0 : code == G_2 ? -1 : 1);
            result = NULL;
            if (centre1 && centre2 && rotation) {
                call[0] = PyList_GET_ITEM(point, g.p1);
                call[1] = PyList_GET_ITEM(point, g.p2);
                call[2] = centre1;
                call[3] = centre2;
                call[4] = rotation;
                call[5] = PyList_GET_ITEM(point, g.p3);
                for (int k = 3; k < 9; k++) {
                    call[3 + k] = PyList_GET_ITEM(point, k);
                }
                if (held == NULL) {
                    result = PyObject_Vectorcall(arc_feed, call, 12, NULL);
                } else if (PyList_GET_SIZE(held->column[0]) == 0 &&
                           PyObject_SetAttrString(pending, "start", cur) < 0) {
                    result = NULL; /* (where the batch begins) */
                } else if (told_plane && mark_plane(held)) {
                    result = NULL;
                } else {
                    result = hold(held, PyList_GET_ITEM(cells, at), call, n);
                }
            }
            Py_XDECREF(centre1);
            Py_XDECREF(centre2);
            Py_XDECREF(rotation);
        }
        if (result == NULL) {
            Py_DECREF(point);
            failed = 1;
            break;
        }
        Py_DECREF(result);
        Py_SETREF(cur, point);
        Py_INCREF(motion);
        Py_SETREF(motion_mode, motion);
        at += 2 + width;
    }
    /* what was done, exception or not */
    PyObject *type, *value, *traceback;
    PyErr_Fetch(&type, &value, &traceback);
    PyList_SetItem(state, 0, cur);
    PyList_SetItem(state, 1, motion_mode);
    PyList_SetItem(state, 3, block_n);
    int lost = 0;
    if (row >= 0) {
        PyObject *done = PyLong_FromSsize_t(row);
        lost |= done == NULL || PyList_SetItem(state, 2, done) < 0;
    }
    if (feed_changed) {
        PyObject *rate = PyFloat_FromDouble(feed_rate);
        lost |= rate == NULL || PyList_SetItem(state, 4, rate) < 0;
        Py_INCREF(Py_True);
        PyList_SetItem(state, 5, Py_True);
    }
    if (lost) {
        Py_XDECREF(type);
        Py_XDECREF(value);
        Py_XDECREF(traceback);
        return NULL;
    }
    if (failed) {
        PyErr_Restore(type, value, traceback);
        return NULL;
    }
    return PyLong_FromSsize_t(at);
}

/* cell_value(text): float(text) as the rows read a cell (for the tests). */
static PyObject *cell_value(PyObject *self, PyObject *text) {
    PyObject *cells = PyList_New(1);
    if (cells == NULL) {
        return NULL;
    }
    Py_INCREF(text);
    PyList_SET_ITEM(cells, 0, text);
    double value;
    int failed = cell_float(cells, 0, &value);
    Py_DECREF(cells);
    return failed ? NULL : PyFloat_FromDouble(value);
}

/* radius_centre(clockwise, s1, s2, e1, e2, radius, zero): the C above for
 * Machine.plain_arc's R arcs (arc_rows.radius_centre): (c1, c2), or None
 * when R is too short. */
static PyObject *radius_centre_py(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    if (nargs != 7) {
        PyErr_SetString(PyExc_TypeError, "radius_centre(clockwise, s1, s2, e1, e2, radius, zero)");
        return NULL;
    }
    int clockwise = PyObject_IsTrue(args[0]);
    double v[6];
    for (int k = 0; k < 6; k++) {
        v[k] = PyFloat_AsDouble(args[k + 1]);
        if (v[k] == -1.0 && PyErr_Occurred()) {
            return NULL;
        }
    }
    if (clockwise < 0) {
        return NULL;
    }
    double c1, c2;
    if (!radius_centre(clockwise, v[0], v[1], v[2], v[3], v[4], v[5], &c1, &c2)) {
        Py_RETURN_NONE;
    }
    return Py_BuildValue("(dd)", c1, c2);
}

static PyMethodDef methods[] = {
    {"radius_centre", (PyCFunction) (void (*)(void)) radius_centre_py, METH_FASTCALL,
     "radius_centre(clockwise, s1, s2, e1, e2, radius, zero): (c1, c2) or None"},
    {"cell_value", (PyCFunction) cell_value, METH_O,
     "float(text) as the rows read a table's cell"},
    {"arc_row", (PyCFunction) (void (*)(void)) arc_row, METH_FASTCALL,
     "ArcRows._arc_row's answer: (motion, N, F, end point, c1, c2) or None"},
    {"rows", (PyCFunction) (void (*)(void)) rows, METH_FASTCALL,
     "ArcRows.run's loop for a contour's rows, for the trace or held arcs"},
    {NULL, NULL, 0, NULL},
};

static struct PyModuleDef module = {
    PyModuleDef_HEAD_INIT, "runtime.fast._arc_row",
    "The arc row loop's arithmetic in C (see runtime/fast/arc_rows.py).", -1, methods,
};

PyMODINIT_FUNC PyInit__arc_row(void) {
    plane_xy = PyUnicode_InternFromString("XY");
    if (plane_xy == NULL) {
        return NULL;
    }
    return PyModule_Create(&module);
}
