/*
 * The per-arc arithmetic of runtime.stats.StatsCanon.arc_moves in C: for a
 * batch of arcs, each arc's sweep and radii (runtime.toolpath.arc_geometry),
 * its length (helix_length) and its time (runtime.stats.move_time), summed
 * in program order onto the totals so far, and the extreme points of those
 * that may reach beyond the extents box (runtime.toolpath.Arc.extreme_points).
 *
 * Optional, like the other extensions: runtime/stats.py holds the same steps
 * in Python (python_arc_sums), and runtime/toolpath.py takes this module's
 * hypot() -- the C library's -- where it is built, so that both give the
 * very same doubles (Python's math.hypot rounds differently in about one
 * case in a thousand). tests/test_stats.py holds the two to equal bits.
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <math.h>

#define TAU (2.0 * M_PI)
#define FULL_CIRCLE_CHORD 1e-9 /* runtime.toolpath.FULL_CIRCLE_CHORD */

/* Python's float ``%``: the remainder takes the sign of the divisor. */
static double py_mod(double x, double y) {
    double mod = fmod(x, y);
    if (mod != 0.0) {
        if ((y < 0.0) != (mod < 0.0)) {
            mod += y;
        }
    } else {
        mod = copysign(0.0, y);
    }
    return mod;
}

/* runtime.stats.move_time, step for step */
static double move_time(double length, double rate, double acceleration) {
    if (length <= 0.0) {
        return 0.0;
    }
    double speed = rate / 60.0;
    if (acceleration == 0.0 || isinf(acceleration)) {
        return length / speed;
    }
    double ramp = speed * speed / acceleration;
    if (length >= ramp) {
        return length / speed + speed / acceleration;
    }
    return 2.0 * sqrt(length / acceleration);
}

/* runtime.toolpath.Arc.extreme_points, step for step: h(theta) and its
 * slope, for a radius r0 at theta0 changing by k a radian. */
static double spiral_h(double theta, double theta0, double r0, double k) {
    return theta + atan2(r0 + k * (theta - theta0), k);
}

static double spiral_slope(double theta, double theta0, double r0, double k) {
    if (k == 0.0) {
        return 1.0;
    }
    double ratio = (r0 + k * (theta - theta0)) / k;
    return 1.0 + 1.0 / (1.0 + ratio * ratio);
}

/* runtime.toolpath._solve_increasing (Python's min and max keep the first
 * of equals; so do these comparisons). */
static double solve_increasing(double target, double low, double high, double theta0,
                               double r0, double k) {
    double theta = target - (spiral_h(low, theta0, r0, k) - low);
    if (low > theta) {
        theta = low;
    }
    if (high < theta) {
        theta = high;
    }
    for (int step = 0; step < 60; step++) {
        double value = spiral_h(theta, theta0, r0, k) - target;
        if (value == 0.0) {
            return theta;
        }
        if (value > 0.0) {
            high = theta;
        } else {
            low = theta;
        }
        double guess = theta - value / spiral_slope(theta, theta0, r0, k);
        if (!(low < guess && guess < high)) {
            guess = 0.5 * (low + high);
        }
        double scale = fabs(theta) > 1.0 ? fabs(theta) : 1.0;
        if (fabs(guess - theta) <= 1e-15 * scale) {
            return guess;
        }
        theta = guess;
    }
    return theta;
}

/* Python's ``a % 4`` of an integer-valued double: 0 to 3. */
static double mod4(double a) {
    double m = fmod(a, 4.0);
    return m < 0.0 ? m + 4.0 : m;
}

static int compare_doubles(const void *a, const void *b) {
    double x = *(const double *) a, y = *(const double *) b;
    return (x > y) - (x < y);
}

/* The extreme points of the arc about (c1, c2) (runtime.toolpath.Arc.
 * extreme_points but its ends, which the caller has added) into the box on
 * the plane's axes f and s: the other axes of those points lie between the
 * ends'. -1 where a multiple of a quarter turn is too large for a double to
 * count in ones (the caller leaves the batch to Python). */
static int extremes_into_box(double *box, long f, long s, double c1, double c2,
                             double sweep, double r0, double r1, double theta0) {
    if (sweep == 0.0) {
        return 0;
    }
    double k = (r1 - r0) / sweep;
    if (!isfinite(k)) {
        return 0;
    }
    double low = theta0, high = theta0 + sweep;
    if (high < low) {
        double swap = low;
        low = high;
        high = swap;
    }
    double quarter = M_PI / 2;
    double first = ceil(spiral_h(low, theta0, r0, k) / quarter);
    double last = floor(spiral_h(high, theta0, r0, k) / quarter);
    if (!(fabs(first) < 4e15 && fabs(last) < 4e15)) {
        return -1;
    }
    if (last < first) {
        return 0;
    }
    double wanted[8];
    int count = 0;
    for (int direction = 0; direction < 4; direction++) {
        double m = first + mod4(direction - first);
        if (m <= last) {
            double far = m + floor((last - m) / 4.0) * 4.0;
            for (int twice = 0; twice < 2; twice++) {
                double value = twice ? far : m;
                int seen = 0;
                for (int i = 0; i < count; i++) {
                    seen |= wanted[i] == value;
                }
                if (!seen) {
                    wanted[count++] = value;
                }
            }
        }
    }
    qsort(wanted, count, sizeof(double), compare_doubles);
    for (int i = 0; i < count; i++) {
        double theta = solve_increasing(wanted[i] * quarter, low, high, theta0, r0, k);
        /* Arc.point((theta - theta0) / sweep) */
        double t = (theta - theta0) / sweep;
        double angle = theta0 + sweep * t;
        double radius = r0 + (r1 - r0) * t;
        double at_f = c1 + radius * cos(angle), at_s = c2 + radius * sin(angle);
        if (at_f < box[2 * f]) {
            box[2 * f] = at_f;
        }
        if (at_f > box[2 * f + 1]) {
            box[2 * f + 1] = at_f;
        }
        if (at_s < box[2 * s]) {
            box[2 * s] = at_s;
        }
        if (at_s > box[2 * s + 1]) {
            box[2 * s + 1] = at_s;
        }
    }
    return 0;
}

/* A point's X Y Z (``at``) into the box [low x, high x, low y, ...]. */
static void into_box(double *box, const double *at) {
    for (int i = 0; i < 3; i++) {
        if (at[i] < box[2 * i]) {
            box[2 * i] = at[i];
        }
        if (at[i] > box[2 * i + 1]) {
            box[2 * i + 1] = at[i];
        }
    }
}

/* A straight move's time (StatsCanon._straight) onto *time_sum, from its X
 * Y Z ``length`` and, when that is 0, its rotary travel from A B C ``was``
 * to ``now``: degrees at the same numeric rate; a move of no usable rate
 * counted in *untimed. */
static void time_straight(double length, const double *was, const double *now, double rate,
                          double acceleration, double *time_sum, Py_ssize_t *untimed) {
    if (length == 0.0) {
        for (int i = 0; i < 3; i++) {
            double turn = fabs(now[i] - was[i]);
            if (turn > length) {
                length = turn;
            }
        }
    }
    if (length != 0.0) {
        if (rate <= 0.0) {
            (*untimed)++;
        } else {
            *time_sum += move_time(length, rate, acceleration);
        }
    }
}

static int item_double(PyObject *list, Py_ssize_t k, double *out) {
    *out = PyFloat_AsDouble(PyList_GET_ITEM(list, k));
    return *out == -1.0 && PyErr_Occurred();
}

static PyObject *c_hypot(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    if (nargs != 2) {
        PyErr_SetString(PyExc_TypeError, "hypot takes 2 arguments");
        return NULL;
    }
    double a = PyFloat_AsDouble(args[0]), b = PyFloat_AsDouble(args[1]);
    if (PyErr_Occurred()) {
        return NULL;
    }
    return PyFloat_FromDouble(hypot(a, b));
}

/* Each value of ``column`` (a list of floats) into low..high. */
static int widen(PyObject *column, double *low, double *high) {
    Py_ssize_t count = PyList_GET_SIZE(column);
    for (Py_ssize_t k = 0; k < count; k++) {
        double value;
        if (item_double(column, k, &value)) {
            return -1;
        }
        if (value < *low) {
            *low = value;
        }
        if (value > *high) {
            *high = value;
        }
    }
    return 0;
}

static int store(PyObject *list, Py_ssize_t k, double value) {
    PyObject *number = PyFloat_FromDouble(value);
    return number == NULL ? -1 : PyList_SetItem(list, k, number);
}

/* The extents' three lists of six (Extents._xyz, _rest_low, _rest_high)
 * into C arrays, and back: 0, or -1 with an exception. */
static int read_extents(PyObject *box_list, PyObject *rest_low, PyObject *rest_high,
                        double *box, double *low, double *high) {
    for (int k = 0; k < 6; k++) {
        box[k] = PyFloat_AsDouble(PyList_GET_ITEM(box_list, k));
        low[k] = PyFloat_AsDouble(PyList_GET_ITEM(rest_low, k));
        high[k] = PyFloat_AsDouble(PyList_GET_ITEM(rest_high, k));
    }
    return PyErr_Occurred() ? -1 : 0;
}

static int write_extents(PyObject *box_list, PyObject *rest_low, PyObject *rest_high,
                         const double *box, const double *low, const double *high) {
    for (int k = 0; k < 6; k++) {
        if (store(box_list, k, box[k]) || store(rest_low, k, low[k]) ||
            store(rest_high, k, high[k])) {
            return -1;
        }
    }
    return 0;
}

/* arc_sums(s1, s2, sn, start_rest, first_end, second_end, first_axis,
 * second_axis, rotation, axis_end, rest, box, rest_low, rest_high, f, s, n,
 * length, feed_length, time, rate, acceleration): a batch of arcs from the
 * start's plane coordinates (s1, s2) and normal one (sn), given as columns
 * of arc_feed's arguments in millimetres (``rest``: the six columns of A B
 * C U V W; ``start_rest``: the start's six). A row of rotation 0 is a
 * straight feed to its end (Canon.contour_moves).
 *
 * Every end goes into the extents: ``box`` (Extents._xyz, [low x, high x,
 * low y, ...]; ``f``, ``s``, ``n`` are the plane's axis indexes in it) and
 * ``rest_low``/``rest_high`` are updated in place. Returns (length,
 * feed_length, time, untimed, straights): the arcs' and the straight
 * feeds' length totals and the time total with each move added in order,
 * the count of moves of no usable rate and the count of straight feeds. An
 * arc whose square of its larger radius about its centre is not inside the
 * box as it stands adds its extreme points to it, as StatsCanon.arc does.
 * None, having changed nothing, when a straight feed's length overflows or
 * an arc turns too many times to count its quarter turns (the Python side
 * does those). */
static PyObject *arc_sums(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    if (nargs != 22) {
        PyErr_SetString(PyExc_TypeError, "arc_sums takes 22 arguments");
        return NULL;
    }
    PyObject *start_rest = args[3];
    PyObject *columns[6] = {args[4], args[5], args[6], args[7], args[8], args[9]};
    PyObject *rest = args[10], *box_list = args[11];
    PyObject *rest_low = args[12], *rest_high = args[13];
    if (!PyTuple_CheckExact(start_rest) || PyTuple_GET_SIZE(start_rest) != 6) {
        PyErr_SetString(PyExc_TypeError, "arc_sums: the start's A B C U V W, a tuple");
        return NULL;
    }
    if (!PyList_CheckExact(box_list) || PyList_GET_SIZE(box_list) != 6 ||
        !PyList_CheckExact(rest_low) || PyList_GET_SIZE(rest_low) != 6 ||
        !PyList_CheckExact(rest_high) || PyList_GET_SIZE(rest_high) != 6 ||
        !PyList_CheckExact(rest) || PyList_GET_SIZE(rest) != 6) {
        PyErr_SetString(PyExc_TypeError, "arc_sums: the box and extents are lists of six");
        return NULL;
    }
    Py_ssize_t count = PyList_CheckExact(columns[0]) ? PyList_GET_SIZE(columns[0]) : -1;
    for (int k = 0; k < 12; k++) {
        PyObject *column = k < 6 ? columns[k] : PyList_GET_ITEM(rest, k - 6);
        if (!PyList_CheckExact(column) || PyList_GET_SIZE(column) != count) {
            PyErr_SetString(PyExc_TypeError, "arc_sums: columns are lists of one length");
            return NULL;
        }
    }
    double s1 = PyFloat_AsDouble(args[0]), s2 = PyFloat_AsDouble(args[1]);
    double sn = PyFloat_AsDouble(args[2]);
    long f = PyLong_AsLong(args[14]), s = PyLong_AsLong(args[15]);
    long n = PyLong_AsLong(args[16]);
    double length_sum = PyFloat_AsDouble(args[17]), feed_sum = PyFloat_AsDouble(args[18]);
    double time_sum = PyFloat_AsDouble(args[19]);
    double rate = PyFloat_AsDouble(args[20]), acceleration = PyFloat_AsDouble(args[21]);
    double turned[3]; /* A B C where the move begins */
    for (int k = 0; k < 3; k++) {
        turned[k] = PyFloat_AsDouble(PyTuple_GET_ITEM(start_rest, k));
    }
    double box[6], low[6], high[6];
    if (read_extents(box_list, rest_low, rest_high, box, low, high)) {
        return NULL;
    }
    if (f < 0 || f > 2 || s < 0 || s > 2 || n < 0 || n > 2) {
        PyErr_SetString(PyExc_ValueError, "arc_sums: plane axes are 0, 1 or 2");
        return NULL;
    }
    for (int k = 0; k < 6; k++) {
        if (widen(PyList_GET_ITEM(rest, k), &low[k], &high[k])) {
            return NULL;
        }
    }
    Py_ssize_t untimed = 0, straights = 0;
    for (Py_ssize_t k = 0; k < count; k++) {
        double e1, e2, c1, c2, en;
        if (item_double(columns[0], k, &e1) || item_double(columns[1], k, &e2) ||
            item_double(columns[2], k, &c1) || item_double(columns[3], k, &c2) ||
            item_double(columns[5], k, &en)) {
            return NULL;
        }
        long rotation = PyLong_AsLong(PyList_GET_ITEM(columns[4], k));
        if (rotation == -1 && PyErr_Occurred()) {
            return NULL;
        }
        double now[3]; /* A B C at the end */
        for (int i = 0; i < 3; i++) {
            if (item_double(PyList_GET_ITEM(rest, i), k, &now[i])) {
                return NULL;
            }
        }
        if (rotation == 0) {
            /* a straight feed: runtime.toolpath.distance over X Y Z, then
             * StatsCanon._straight's time */
            double at[3], d[3];
            at[f] = e1;
            at[s] = e2;
            at[n] = en;
            d[f] = e1 - s1;
            d[s] = e2 - s2;
            d[n] = en - sn;
            double length = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
            if (isinf(length)) {
                Py_RETURN_NONE; /* nothing stored yet */
            }
            into_box(box, at);
            feed_sum += length;
            straights++;
            time_straight(length, turned, now, rate, acceleration, &time_sum, &untimed);
            s1 = e1;
            s2 = e2;
            sn = en;
            for (int i = 0; i < 3; i++) {
                turned[i] = now[i];
            }
            continue;
        }
        /* arc_geometry */
        double theta0 = atan2(s2 - c2, s1 - c1);
        double theta1 = atan2(e2 - c2, e1 - c1);
        int closed = hypot(e1 - s1, e2 - s2) < FULL_CIRCLE_CHORD;
        double sweep;
        if (rotation >= 0) {
            sweep = py_mod(theta1 - theta0, TAU);
            if (closed || sweep == 0.0) {
                sweep = TAU;
            }
            sweep += TAU * (double) (rotation - 1 > 0 ? rotation - 1 : 0);
        } else {
            sweep = -py_mod(theta0 - theta1, TAU);
            if (closed || sweep == 0.0) {
                sweep = -TAU;
            }
            sweep -= TAU * (double) (-rotation - 1);
        }
        double r0 = hypot(s1 - c1, s2 - c2);
        double r1 = hypot(e1 - c1, e2 - c2);
        /* the end into the box (Extents.add), then Extents.encloses with the
         * larger radius: a box that only grows and holds no point off the
         * path, so an arc inside it is inside the final one */
        double at[3];
        at[f] = e1;
        at[s] = e2;
        at[n] = en;
        into_box(box, at);
        double radius = r0 > r1 ? r0 : r1;
        if (!(box[2 * f] <= c1 - radius && c1 + radius <= box[2 * f + 1] &&
              box[2 * s] <= c2 - radius && c2 + radius <= box[2 * s + 1])) {
            if (extremes_into_box(box, f, s, c1, c2, sweep, r0, r1, theta0)) {
                Py_RETURN_NONE; /* nothing stored yet */
            }
        }
        /* helix_length, then StatsCanon._time */
        double length = hypot(fabs(sweep) * (r0 + r1) / 2.0, en - sn);
        length_sum += length;
        if (length != 0.0) {
            if (rate <= 0.0) {
                untimed++;
            } else {
                time_sum += move_time(length, rate, acceleration);
            }
        }
        s1 = e1;
        s2 = e2;
        sn = en;
        for (int i = 0; i < 3; i++) {
            turned[i] = now[i];
        }
    }
    if (write_extents(box_list, rest_low, rest_high, box, low, high)) {
        return NULL;
    }
    return Py_BuildValue("(dddnn)", length_sum, feed_sum, time_sum, untimed, straights);
}

/* straight_sums(start, columns, rate, acceleration, box, rest_low,
 * rest_high, length, time): a run of straight moves from ``start`` (nine
 * values) through the points of ``columns`` (nine lists of floats, X .. W,
 * in millimetres), as runtime.stats.python_straight_sums adds them up: each
 * move's length over X Y Z (runtime.toolpath.distance: the square root of
 * the sum of the three squares, in that order) onto ``length``, its time
 * (move_time, of its rotary travel when X Y Z stand still) onto ``time``,
 * and every point into the extents (``box`` and ``rest_low``/``rest_high``,
 * updated in place). Returns (length, time, untimed); or None, having
 * changed nothing, when a length overflows (coordinates beyond 1e150: the
 * Python side measures those moves another way). */
static PyObject *straight_sums(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    if (nargs != 9) {
        PyErr_SetString(PyExc_TypeError, "straight_sums takes 9 arguments");
        return NULL;
    }
    PyObject *start = args[0], *columns = args[1];
    PyObject *box_list = args[4], *rest_low = args[5], *rest_high = args[6];
    if (!PyTuple_CheckExact(start) || PyTuple_GET_SIZE(start) != 9 ||
        !PyList_CheckExact(columns) || PyList_GET_SIZE(columns) != 9) {
        PyErr_SetString(PyExc_TypeError, "straight_sums: a start of nine, nine columns");
        return NULL;
    }
    if (!PyList_CheckExact(box_list) || PyList_GET_SIZE(box_list) != 6 ||
        !PyList_CheckExact(rest_low) || PyList_GET_SIZE(rest_low) != 6 ||
        !PyList_CheckExact(rest_high) || PyList_GET_SIZE(rest_high) != 6) {
        PyErr_SetString(PyExc_TypeError, "straight_sums: the box and extents are lists of six");
        return NULL;
    }
    PyObject *column[9];
    Py_ssize_t count = -1;
    for (int i = 0; i < 9; i++) {
        column[i] = PyList_GET_ITEM(columns, i);
        if (!PyList_CheckExact(column[i]) ||
            (count >= 0 && PyList_GET_SIZE(column[i]) != count)) {
            PyErr_SetString(PyExc_TypeError, "straight_sums: columns are lists of one length");
            return NULL;
        }
        count = PyList_GET_SIZE(column[i]);
    }
    double was[9];
    for (int i = 0; i < 9; i++) {
        was[i] = PyFloat_AsDouble(PyTuple_GET_ITEM(start, i));
    }
    double rate = PyFloat_AsDouble(args[2]), acceleration = PyFloat_AsDouble(args[3]);
    double length_sum = PyFloat_AsDouble(args[7]), time_sum = PyFloat_AsDouble(args[8]);
    double box[6], low[6], high[6];
    if (read_extents(box_list, rest_low, rest_high, box, low, high)) {
        return NULL;
    }
    Py_ssize_t untimed = 0;
    for (Py_ssize_t k = 0; k < count; k++) {
        double at[9];
        for (int i = 0; i < 9; i++) {
            if (item_double(column[i], k, &at[i])) {
                return NULL;
            }
        }
        into_box(box, at);
        for (int i = 0; i < 6; i++) {
            if (at[3 + i] < low[i]) {
                low[i] = at[3 + i];
            }
            if (at[3 + i] > high[i]) {
                high[i] = at[3 + i];
            }
        }
        double dx = at[0] - was[0], dy = at[1] - was[1], dz = at[2] - was[2];
        double length = sqrt(dx * dx + dy * dy + dz * dz);
        if (isinf(length)) {
            Py_RETURN_NONE; /* nothing stored yet */
        }
        length_sum += length;
        time_straight(length, was + 3, at + 3, rate, acceleration, &time_sum, &untimed);
        for (int i = 0; i < 9; i++) {
            was[i] = at[i];
        }
    }
    if (write_extents(box_list, rest_low, rest_high, box, low, high)) {
        return NULL;
    }
    return Py_BuildValue("(ddn)", length_sum, time_sum, untimed);
}

/* distances(x0, y0, z0, x1, y1, z1): for each k, the length over X Y Z from
 * (x0[k], y0[k], z0[k]) to (x1[k], y1[k], z1[k]) as runtime.toolpath.distance
 * works it out (six lists of floats of one length): a list; or None when a
 * length overflows (the Python side measures those). */
static PyObject *distances(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    if (nargs != 6) {
        PyErr_SetString(PyExc_TypeError, "distances takes 6 arguments");
        return NULL;
    }
    Py_ssize_t count = -1;
    for (int i = 0; i < 6; i++) {
        if (!PyList_CheckExact(args[i]) ||
            (count >= 0 && PyList_GET_SIZE(args[i]) != count)) {
            PyErr_SetString(PyExc_TypeError, "distances: six lists of one length");
            return NULL;
        }
        count = PyList_GET_SIZE(args[i]);
    }
    PyObject *lengths = PyList_New(count);
    if (lengths == NULL) {
        return NULL;
    }
    for (Py_ssize_t k = 0; k < count; k++) {
        double v[6];
        for (int i = 0; i < 6; i++) {
            if (item_double(args[i], k, &v[i])) {
                Py_DECREF(lengths);
                return NULL;
            }
        }
        double dx = v[3] - v[0], dy = v[4] - v[1], dz = v[5] - v[2];
        double length = sqrt(dx * dx + dy * dy + dz * dz);
        if (isinf(length)) {
            Py_DECREF(lengths);
            Py_RETURN_NONE;
        }
        PyObject *number = PyFloat_FromDouble(length);
        if (number == NULL) {
            Py_DECREF(lengths);
            return NULL;
        }
        PyList_SET_ITEM(lengths, k, number);
    }
    return lengths;
}

/* hole_sums(lengths, timed, kinds, rates, acceleration, sums): holes
 * drilled alike (runtime.stats.StatsCanon.hole_moves), as
 * runtime.stats.python_hole_sums adds them up. ``lengths`` and ``timed``
 * are a column each of a hole's moves (lists of floats, one a hole: the
 * move's length, and the travel it is timed by), ``kinds`` a 0 (rapid) or
 * 1 (feed) each, ``rates`` the two rates, ``sums`` the (rapid length, feed
 * length, time) so far. Hole by hole, move by move: the length onto its
 * kind's total, the move's time onto the time. Returns the three totals and
 * the count of moves of no usable rate. */
static PyObject *hole_sums(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    if (nargs != 6) {
        PyErr_SetString(PyExc_TypeError, "hole_sums takes 6 arguments");
        return NULL;
    }
    PyObject *lengths = args[0], *timed = args[1], *kinds = args[2];
    if (!PyList_CheckExact(lengths) || !PyList_CheckExact(timed) ||
        !PyList_CheckExact(kinds) || PyList_GET_SIZE(timed) != PyList_GET_SIZE(lengths) ||
        PyList_GET_SIZE(kinds) != PyList_GET_SIZE(lengths)) {
        PyErr_SetString(PyExc_TypeError, "hole_sums: as many columns and kinds as moves");
        return NULL;
    }
    Py_ssize_t moves = PyList_GET_SIZE(lengths), count = -1;
    int *kind_of = PyMem_New(int, moves ? moves : 1); /* read once, not a hole each */
    if (kind_of == NULL) {
        return PyErr_NoMemory();
    }
    for (Py_ssize_t j = 0; j < moves; j++) {
        PyObject *length = PyList_GET_ITEM(lengths, j), *time = PyList_GET_ITEM(timed, j);
        if (!PyList_CheckExact(length) || !PyList_CheckExact(time) ||
            PyList_GET_SIZE(time) != PyList_GET_SIZE(length) ||
            (count >= 0 && PyList_GET_SIZE(length) != count)) {
            PyErr_SetString(PyExc_TypeError, "hole_sums: columns are lists of one length");
            PyMem_Free(kind_of);
            return NULL;
        }
        count = PyList_GET_SIZE(length);
        long kind = PyLong_AsLong(PyList_GET_ITEM(kinds, j));
        if (kind != 0 && kind != 1) {
            if (!PyErr_Occurred()) {
                PyErr_SetString(PyExc_ValueError, "hole_sums: a kind is 0 or 1");
            }
            PyMem_Free(kind_of);
            return NULL;
        }
        kind_of[j] = (int) kind;
    }
    double rate[2], sum[2], time_sum, acceleration = PyFloat_AsDouble(args[4]);
    if (!PyArg_ParseTuple(args[3], "dd", &rate[0], &rate[1]) ||
        !PyArg_ParseTuple(args[5], "ddd", &sum[0], &sum[1], &time_sum) ||
        (acceleration == -1.0 && PyErr_Occurred())) {
        PyMem_Free(kind_of);
        return NULL;
    }
    Py_ssize_t untimed = 0;
    for (Py_ssize_t k = 0; k < count; k++) {
        for (Py_ssize_t j = 0; j < moves; j++) {
            int kind = kind_of[j];
            double length, travel;
            if (item_double(PyList_GET_ITEM(lengths, j), k, &length) ||
                item_double(PyList_GET_ITEM(timed, j), k, &travel)) {
                PyMem_Free(kind_of);
                return NULL;
            }
            sum[kind] += length;
            if (rate[kind] <= 0.0) {
                untimed += travel != 0.0;
            } else {
                time_sum += move_time(travel, rate[kind], acceleration);
            }
        }
    }
    PyMem_Free(kind_of);
    return Py_BuildValue("(dddn)", sum[0], sum[1], time_sum, untimed);
}

static PyMethodDef methods[] = {
    {"hypot", (PyCFunction) (void (*)(void)) c_hypot, METH_FASTCALL,
     "The C library's hypot(a, b)."},
    {"distances", (PyCFunction) (void (*)(void)) distances, METH_FASTCALL,
     "The X Y Z lengths between the points of two triples of columns."},
    {"straight_sums", (PyCFunction) (void (*)(void)) straight_sums, METH_FASTCALL,
     "Lengths, times and extents of a run of straight moves."},
    {"hole_sums", (PyCFunction) (void (*)(void)) hole_sums, METH_FASTCALL,
     "A batch of holes' lengths and times added in order."},
    {"arc_sums", (PyCFunction) (void (*)(void)) arc_sums, METH_FASTCALL,
     "A batch of arcs' lengths and times added in order, their extremes in the box"},
    {NULL, NULL, 0, NULL},
};

static struct PyModuleDef module = {
    PyModuleDef_HEAD_INIT, "runtime._arc_stats",
    "StatsCanon.arc_moves' per-arc arithmetic in C (see runtime/stats.py).", -1, methods,
};

PyMODINIT_FUNC PyInit__arc_stats(void) {
    return PyModule_Create(&module);
}
