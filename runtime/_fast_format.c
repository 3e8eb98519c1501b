/*
 * percent(template, args): the same string as Python's `template % args`,
 * for the few conversions trace lines use, made faster.
 *
 * A trace line is mostly "%.4f" numbers. Python formats each through its
 * general float-to-string machinery (about 150 ns a number); for an ordinary
 * number this finds the same digits in a few nanoseconds: the value times
 * 10000 as an exact sum of two doubles (fma), rounded once to the nearest
 * integer, ties to even -- which is what printf and Python both do with the
 * exact binary value.
 *
 * Conversions: %s (a str), %d (an int), both with a width and '-', %.4f (a
 * float) and %%. Anything else, and any argument that is not of the expected
 * type, hands the whole call to PyUnicode_Format, so the answer is always
 * exactly Python's.
 * Numbers that are not finite or are 1e11 or more in size are formatted by
 * Python's own routine, but for one difference on purpose: a NaN prints as
 * C's printf prints it, "-nan" when its sign bit is set (rs274's trace does:
 * an R 0 arc's centre), where Python always writes "nan".
 *
 * Optional, like runtime._libm_trig: runtime/canon.py uses str.__mod__
 * where this was not built.
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <math.h>
#include <stdint.h>
#include <string.h>

typedef struct {
    char *data;
    Py_ssize_t size, capacity;
    char inline_data[256];
} buffer;

static int reserve(buffer *b, Py_ssize_t more) {
    if (b->size + more <= b->capacity) {
        return 0;
    }
    Py_ssize_t capacity = (b->size + more) * 2;
    char *data;
    if (b->data == b->inline_data) {
        data = PyMem_Malloc(capacity);
        if (data) {
            memcpy(data, b->data, b->size);
        }
    } else {
        data = PyMem_Realloc(b->data, capacity);
    }
    if (!data) {
        PyErr_NoMemory();
        return -1;
    }
    b->data = data;
    b->capacity = capacity;
    return 0;
}

static inline int append(buffer *b, const char *text, Py_ssize_t length) {
    if (reserve(b, length) < 0) {
        return -1;
    }
    memcpy(b->data + b->size, text, length);
    b->size += length;
    return 0;
}

/* "00" to "99": two digits a division */
static const char two_digits[201] =
    "00010203040506070809101112131415161718192021222324252627282930313233343536373839"
    "40414243444546474849505152535455565758596061626364656667686970717273747576777879"
    "8081828384858687888990919293949596979899";

/* Digits of v (v >= 0) into the end of out; returns how many. */
static int digits_of(unsigned long long v, char *out_end) {
    char *end = out_end;
    while (v >= 100) {
        unsigned long long pair = v % 100;
        v /= 100;
        out_end -= 2;
        out_end[0] = two_digits[2 * pair];
        out_end[1] = two_digits[2 * pair + 1];
    }
    if (v >= 10) {
        out_end -= 2;
        out_end[0] = two_digits[2 * v];
        out_end[1] = two_digits[2 * v + 1];
    } else {
        *--out_end = (char) ('0' + v);
    }
    return (int) (end - out_end);
}

/* "%.4f" of x into b: 1 done, 0 not an ordinary number (caller falls back),
 * -1 error. */
static int four_decimals(buffer *b, double x) {
    if (!(fabs(x) < 1e11)) {  /* also nan */
        return 0;
    }
    /* x * 10000 == p + e exactly (|p| < 2**50, so e is exact too) */
    double p = x * 10000.0;
    double e = fma(x, 10000.0, -p);
    double n = nearbyint(p);  /* round half to even: the default mode */
    double d = p - n;         /* exact: p and n are multiples of ulp(p) <= 0.5 */
    /* The exact value is n + d + e with |e| <= ulp(p) / 2. Unless d is a
     * half, |d| + |e| < 0.5 and n is the answer. At d == +-0.5 nearbyint
     * chose the even neighbour; e says whether the exact value was past it. */
    if (d == 0.5 && e > 0.0) {
        n += 1.0;
    } else if (d == -0.5 && e < 0.0) {
        n -= 1.0;
    }
    unsigned long long v = (unsigned long long) fabs(n);
    char text[48];
    char *end = text + sizeof(text);
    char *start = end - 4;
    unsigned long long fraction = v % 10000;
    for (int k = 3; k >= 0; k--) {
        start[k] = (char) ('0' + fraction % 10);
        fraction /= 10;
    }
    *--start = '.';
    start -= digits_of(v / 10000, start);
    if (signbit(x)) {  /* printf and Python print -0.0000 too */
        *--start = '-';
    }
    return append(b, start, end - start) < 0 ? -1 : 1;
}

static int python_float(buffer *b, double x) {
    if (isnan(x)) {
        return append(b, signbit(x) ? "-nan" : "nan", signbit(x) ? 4 : 3) < 0 ? -1 : 1;
    }
    char *text = PyOS_double_to_string(x, 'f', 4, 0, NULL);
    if (!text) {
        return -1;
    }
    int result = append(b, text, (Py_ssize_t) strlen(text));
    PyMem_Free(text);
    return result;
}

/* The long long of an int argument: 1, or 0 where it is not an exact int
 * or too large (no exception left set). */
static inline int int_argument(PyObject *arg, long long *value) {
    if (!PyLong_CheckExact(arg)) {
        return 0;
    }
    int overflow;
    *value = PyLong_AsLongLongAndOverflow(arg, &overflow);
    if (overflow || (*value == -1 && PyErr_Occurred())) {
        PyErr_Clear();
        return 0;
    }
    return 1;
}

/* "%d" of value into b: 0, or -1 error. */
static inline int decimal(buffer *b, long long value) {
    char text[32];
    char *digits_end = text + sizeof(text);
    unsigned long long magnitude =
        value < 0 ? 0ULL - (unsigned long long) value : (unsigned long long) value;
    int size = digits_of(magnitude, digits_end);
    if (value < 0) {
        digits_end[-++size] = '-';
    }
    return append(b, digits_end - size, size);
}

/* "%.4f" of a float argument into b: 1 done, 0 not an exact float, -1 error. */
static inline int float_argument(buffer *b, PyObject *arg) {
    if (!PyFloat_CheckExact(arg)) {
        return 0;
    }
    double x = PyFloat_AS_DOUBLE(arg);
    int done = four_decimals(b, x);
    if (done == 0) {
        done = python_float(b, x);
    }
    return done < 0 ? -1 : 1;
}

/* What was written from b->data[before] on, padded with spaces to ``width``
 * (on the right for '-'): 0, or -1 error. */
static inline int pad(buffer *b, Py_ssize_t before, int width, int left) {
    Py_ssize_t size = b->size - before;
    if (size >= width) {
        return 0;
    }
    if (reserve(b, width - size) < 0) {
        return -1;
    }
    char *at = b->data + before;
    if (!left) {
        memmove(at + (width - size), at, size);
        memset(at, ' ', width - size);
    } else {
        memset(at + size, ' ', width - size);
    }
    b->size = before + width;
    return 0;
}

/* 1 done, 0 fall back to PyUnicode_Format, -1 error. Where ``numbers`` is
 * given, an argument k with is_number[k] set is numbers[k] (a range's
 * item, never made an int object), for %d alone: any other conversion of
 * it falls back, the caller putting the int in the tuple first. */
static int render(buffer *b, const char *t, Py_ssize_t length, PyObject *args,
                  const long long *numbers, const char *is_number) {
    Py_ssize_t count = PyTuple_GET_SIZE(args), used = 0;
    const char *end = t + length;
    while (t < end) {
        const char *percent = memchr(t, '%', end - t);
        if (!percent) {
            if (append(b, t, end - t) < 0) {
                return -1;
            }
            break;
        }
        if (append(b, t, percent - t) < 0) {
            return -1;
        }
        t = percent + 1;
        if (t >= end) {
            return 0;
        }
        if (*t == '%') {
            if (append(b, "%", 1) < 0) {
                return -1;
            }
            t++;
            continue;
        }
        /* %[-][width][.precision]conversion */
        int left = 0, width = 0, precision = -1;
        if (t < end && *t == '-') {
            left = 1;
            t++;
        }
        if (t < end && *t == '0') {
            return 0;  /* zero padding */
        }
        while (t < end && *t >= '0' && *t <= '9' && width < 1000) {
            width = width * 10 + (*t++ - '0');
        }
        if (t < end && *t == '.') {
            precision = 0;
            t++;
            while (t < end && *t >= '0' && *t <= '9' && precision < 1000) {
                precision = precision * 10 + (*t++ - '0');
            }
        }
        if (t >= end || used >= count) {
            return 0;
        }
        char conversion = *t++;
        Py_ssize_t k = used++;
        int numeric = numbers != NULL && is_number[k];
        PyObject *arg = numeric ? NULL : PyTuple_GET_ITEM(args, k);
        Py_ssize_t before = b->size;
        if (numeric && !(conversion == 'd' && precision < 0)) {
            return 0;
        }
        if (conversion == 's' && precision < 0) {
            if (!PyUnicode_CheckExact(arg) || (width && !PyUnicode_IS_ASCII(arg))) {
                return 0;  /* padding counts characters, not bytes */
            }
            Py_ssize_t size;
            const char *text = PyUnicode_AsUTF8AndSize(arg, &size);
            if (!text || append(b, text, size) < 0) {
                return -1;
            }
        } else if (conversion == 'd' && precision < 0) {
            long long value;
            if (numeric) {
                value = numbers[k];
            } else if (!int_argument(arg, &value)) {
                return 0;
            }
            if (decimal(b, value) < 0) {
                return -1;
            }
        } else if (conversion == 'f' && precision == 4 && !left && !width) {
            int done = float_argument(b, arg);
            if (done <= 0) {
                return done;
            }
        } else {
            return 0;
        }
        if (pad(b, before, width, left) < 0) {
            return -1;
        }
    }
    return used == count;
}

static PyObject *percent(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    if (nargs != 2 || !PyUnicode_CheckExact(args[0]) || !PyTuple_CheckExact(args[1])) {
        PyErr_SetString(PyExc_TypeError, "percent(template: str, args: tuple)");
        return NULL;
    }
    Py_ssize_t length;
    const char *t = PyUnicode_AsUTF8AndSize(args[0], &length);
    if (!t) {
        return NULL;
    }
    buffer b;
    b.data = b.inline_data;
    b.size = 0;
    b.capacity = sizeof(b.inline_data);
    PyObject *result = NULL;
    int done = render(&b, t, length, args[1], NULL, NULL);
    if (done > 0) {
        result = PyUnicode_DecodeUTF8(b.data, b.size, NULL);
    } else if (done == 0) {
        result = PyUnicode_Format(args[0], args[1]);
    }
    if (b.data != b.inline_data) {
        PyMem_Free(b.data);
    }
    return result;
}


/*
 * percent_rows(template, columns): "".join(template % row for row in
 * zip(*columns)) -- a batch of trace lines, one per row of the columns (lists,
 * ranges...), made in one buffer: no tuple, call or string per line. A range
 * (the lines' numbers) is read as its start and step, its items never made
 * int objects.
 */

/* A column that is a range of modest numbers: its start, step and length
 * (1), or not (0; an error cleared). */
static int range_column(PyObject *column, long long *start, long long *step,
                        Py_ssize_t *length) {
    if (!PyRange_Check(column)) {
        return 0;
    }
    PyObject *first = PyObject_GetAttrString(column, "start");
    PyObject *stride = PyObject_GetAttrString(column, "step");
    Py_ssize_t size = PyObject_Size(column);
    int overflow_first = 1, overflow_stride = 1;
    if (first && stride && size >= 0) {
        *start = PyLong_AsLongLongAndOverflow(first, &overflow_first);
        *step = PyLong_AsLongLongAndOverflow(stride, &overflow_stride);
    }
    Py_XDECREF(first);
    Py_XDECREF(stride);
    PyErr_Clear();
    /* start + i * step stays far inside a long long */
    const long long most = 1LL << 40;
    if (overflow_first || overflow_stride || size < 0 || size > most ||
        *start > most || *start < -most || *step > most || *step < -most) {
        return 0;
    }
    *length = size;
    return 1;
}

/* A template read once for many rows (render_rows): the literal text before
 * each conversion and the conversion itself, so that a row is only copies
 * and numbers, not a new reading of the template. */
typedef struct {
    Py_ssize_t at, length;  /* the literal text before it, in the template */
    char conversion;        /* 'd', 's', 'f' (%.4f), or '%' (no argument) */
    int width, left;
} piece_t;

/* The pieces of template t (at most ``most``; the literal after the last
 * is t[*tail:]), or -1 where render() alone reads it (zero padding, other
 * precisions, other conversions, not ``count`` arguments). */
static Py_ssize_t read_template(const char *t, Py_ssize_t length, Py_ssize_t count,
                                piece_t *pieces, Py_ssize_t most, Py_ssize_t *tail) {
    Py_ssize_t n = 0, arguments = 0, at = 0;
    const char *end = t + length, *p = t;
    while (p < end) {
        const char *percent = memchr(p, '%', end - p);
        if (!percent) {
            break;
        }
        if (n == most || percent + 1 >= end) {
            return -1;
        }
        piece_t *piece = &pieces[n++];
        piece->at = at;
        piece->length = percent - (t + at);
        piece->width = piece->left = 0;
        p = percent + 1;
        if (*p == '%') {
            piece->conversion = '%';
            at = ++p - t;
            continue;
        }
        if (*p == '-') {
            piece->left = 1;
            p++;
        }
        if (p < end && *p == '0') {
            return -1;
        }
        while (p < end && *p >= '0' && *p <= '9' && piece->width < 1000) {
            piece->width = piece->width * 10 + (*p++ - '0');
        }
        int precision = -1;
        if (p < end && *p == '.') {
            precision = 0;
            p++;
            while (p < end && *p >= '0' && *p <= '9' && precision < 1000) {
                precision = precision * 10 + (*p++ - '0');
            }
        }
        if (p >= end) {
            return -1;
        }
        char conversion = *p++;
        if ((conversion == 's' || conversion == 'd') && precision < 0) {
            piece->conversion = conversion;
        } else if (conversion == 'f' && precision == 4 && !piece->left && !piece->width) {
            piece->conversion = 'f';
        } else {
            return -1;
        }
        arguments++;
        at = p - t;
    }
    if (arguments != count) {
        return -1;
    }
    *tail = at;
    return n;
}

/* Row i of render_rows by the template's pieces: 1 done, 0 the row needs
 * render()'s or Python's reading (an argument of another type, a number
 * out of the ordinary), -1 error. Digits as render() writes them. */
static int render_pieces(buffer *b, const char *t, Py_ssize_t length, const piece_t *pieces,
                         Py_ssize_t n, Py_ssize_t tail, PyObject *const *columns,
                         const long long *numbers, const char *is_number, Py_ssize_t i,
                         int *ascii) {
    Py_ssize_t k = 0;  /* the argument */
    for (Py_ssize_t j = 0; j < n; j++) {
        const piece_t *piece = &pieces[j];
        if (append(b, t + piece->at, piece->length) < 0) {
            return -1;
        }
        if (piece->conversion == '%') {
            if (append(b, "%", 1) < 0) {
                return -1;
            }
            continue;
        }
        Py_ssize_t before = b->size;
        PyObject *arg = is_number[k] ? NULL : PySequence_Fast_GET_ITEM(columns[k], i);
        if (piece->conversion == 'd') {
            long long value;
            if (arg == NULL) {
                value = numbers[k];
            } else if (!int_argument(arg, &value)) {
                return 0;
            }
            if (decimal(b, value) < 0) {
                return -1;
            }
        } else if (piece->conversion == 's') {
            if (arg == NULL || !PyUnicode_CheckExact(arg)) {
                return 0;
            }
            if (!PyUnicode_IS_ASCII(arg)) {
                if (piece->width) {
                    return 0;  /* padding counts characters, not bytes */
                }
                *ascii = 0;
            }
            Py_ssize_t size;
            const char *text = PyUnicode_AsUTF8AndSize(arg, &size);
            if (!text || append(b, text, size) < 0) {
                return -1;
            }
        } else {
            int done = arg == NULL ? 0 : float_argument(b, arg);
            if (done <= 0) {
                return done;
            }
        }
        k++;
        if (pad(b, before, piece->width, piece->left) < 0) {
            return -1;
        }
    }
    return append(b, t + tail, length - tail) < 0 ? -1 : 1;
}

/* n bytes from src to dst (non-overlapping) where most copies are a few
 * bytes (a trace line's pieces): two fixed-size moves that may overlap, no
 * byte read outside either range, no call for the usual sizes. */
static inline void copy_short(char *dst, const char *src, Py_ssize_t n) {
    if (n >= 8 && n <= 16) {
        uint64_t head, tail;
        memcpy(&head, src, 8);
        memcpy(&tail, src + n - 8, 8);
        memcpy(dst, &head, 8);
        memcpy(dst + n - 8, &tail, 8);
    } else if (n >= 4 && n < 8) {
        uint32_t head, tail;
        memcpy(&head, src, 4);
        memcpy(&tail, src + n - 4, 4);
        memcpy(dst, &head, 4);
        memcpy(dst + n - 4, &tail, 4);
    } else if (n > 0 && n < 4) {
        dst[0] = src[0];
        dst[n / 2] = src[n / 2];
        dst[n - 1] = src[n - 1];
    } else if (n > 16) {
        memcpy(dst, src, n);
    }
}

/* render_pieces for a template of %s, %d and %% alone (every trace
 * template of rows): each row's arguments looked at once, its room made
 * once, then its text written without a check or a call a piece. 1 done,
 * 0 the row needs render_pieces (an argument not an ASCII str or an exact
 * int), -1 error. ``texts`` and ``sizes``: room for a row's arguments. */
static int render_short_pieces(buffer *b, const char *t, Py_ssize_t length,
                               const piece_t *pieces, Py_ssize_t n, Py_ssize_t tail,
                               Py_ssize_t literal, PyObject *const *columns,
                               const long long *numbers, const char *is_number,
                               Py_ssize_t i, const char **texts, Py_ssize_t *sizes,
                               long long *values) {
    Py_ssize_t room = literal, k = 0;
    for (Py_ssize_t j = 0; j < n; j++) {
        const piece_t *piece = &pieces[j];
        if (piece->conversion == '%') {
            continue;
        }
        if (piece->conversion == 's') {
            PyObject *arg = is_number[k] ? NULL : PySequence_Fast_GET_ITEM(columns[k], i);
            if (arg == NULL || !PyUnicode_CheckExact(arg) || !PyUnicode_IS_COMPACT_ASCII(arg)) {
                return 0;
            }
            texts[k] = (const char *) PyUnicode_DATA(arg);
            sizes[k] = PyUnicode_GET_LENGTH(arg);
        } else {
            if (is_number[k]) {
                values[k] = numbers[k];
            } else if (!int_argument(PySequence_Fast_GET_ITEM(columns[k], i), &values[k])) {
                return 0;
            }
            sizes[k] = 24;  /* a long long's digits and sign, at most */
        }
        room += (sizes[k] > piece->width ? sizes[k] : piece->width);
        k++;
    }
    if (reserve(b, room) < 0) {
        return -1;
    }
    char *out = b->data + b->size;
    k = 0;
    for (Py_ssize_t j = 0; j < n; j++) {
        const piece_t *piece = &pieces[j];
        copy_short(out, t + piece->at, piece->length);
        out += piece->length;
        if (piece->conversion == '%') {
            *out++ = '%';
            continue;
        }
        const char *text;
        Py_ssize_t size;
        char digits[32];
        if (piece->conversion == 's') {
            text = texts[k];
            size = sizes[k];
        } else {
            long long value = values[k];
            unsigned long long magnitude =
                value < 0 ? 0ULL - (unsigned long long) value : (unsigned long long) value;
            char *digits_end = digits + sizeof(digits);
            size = digits_of(magnitude, digits_end);
            if (value < 0) {
                digits_end[-++size] = '-';
            }
            text = digits_end - size;
        }
        k++;
        Py_ssize_t spaces = piece->width > size ? piece->width - size : 0;
        if (spaces && !piece->left) {
            memset(out, ' ', spaces);
            out += spaces;
        }
        copy_short(out, text, size);
        out += size;
        if (spaces && piece->left) {
            memset(out, ' ', spaces);
            out += spaces;
        }
    }
    copy_short(out, t + tail, length - tail);
    out += length - tail;
    b->size = out - b->data;
    return 1;
}

/* The text of ``rows`` rows of ``count`` conversions: conversion k of row i
 * is the number starts[k] + i * steps[k] where is_number[k] is set, else
 * item i of columns[k] (borrowed: each a PySequence_Fast of at least
 * ``rows`` items). */
static PyObject *render_rows(PyObject *template, Py_ssize_t count, Py_ssize_t rows,
                             PyObject *const *columns, const long long *starts,
                             const long long *steps, const char *is_number) {
    Py_ssize_t length;
    const char *t = PyUnicode_AsUTF8AndSize(template, &length);
    if (!t) {
        return NULL;
    }
    Py_ssize_t slots = count ? count : 1;
    long long *numbers = PyMem_Calloc(slots, sizeof(long long));
    PyObject *row = PyTuple_New(count);
    PyObject *result = NULL;
    piece_t *pieces = NULL;
    const char **texts = NULL;
    Py_ssize_t *sizes = NULL;
    long long *values = NULL;
    buffer b;
    b.data = b.inline_data;
    b.size = 0;
    b.capacity = sizeof(b.inline_data);
    if (!numbers || !row) {
        PyErr_NoMemory();
        goto done;
    }
    for (Py_ssize_t c = 0; c < count; c++) {
        Py_INCREF(Py_None);  /* (a number's slot, until a fallback needs the int) */
        PyTuple_SET_ITEM(row, c, Py_None);
    }
    /* whether the text is all ASCII: the template and every str in it (the
     * rest render writes is digits, signs and points) */
    int ascii = PyUnicode_IS_ASCII(template);
    /* room for every row at once, about: the buffer is not copied as it
     * grows (a batch's text is hundreds of kilobytes) */
    if (rows > 1 && reserve(&b, Py_MIN(rows, 1 << 16) * (length + 12 * count)) < 0) {
        goto done;
    }
    /* the template read once, where render_pieces can make its rows */
    Py_ssize_t most = 2 * slots + 8, tail = 0, n = -1;
    pieces = rows > 1 ? PyMem_Malloc(most * sizeof(piece_t)) : NULL;
    if (pieces) {
        n = read_template(t, length, count, pieces, most, &tail);
    }
    /* a template of %s, %d and %% alone: render_short_pieces, with room
     * for one row's arguments and the length of its literal text */
    int short_pieces = n >= 0;
    Py_ssize_t literal = n >= 0 ? length - tail : 0;
    for (Py_ssize_t j = 0; j < n; j++) {
        literal += pieces[j].length + (pieces[j].conversion == '%');
        short_pieces = short_pieces && pieces[j].conversion != 'f';
    }
    if (short_pieces && count) {
        texts = PyMem_Malloc(count * sizeof(const char *));
        sizes = PyMem_Malloc(count * sizeof(Py_ssize_t));
        values = PyMem_Malloc(count * sizeof(long long));
        if (!texts || !sizes || !values) {
            PyErr_NoMemory();
            goto done;
        }
    }
    for (Py_ssize_t i = 0; i < rows; i++) {
        if (n >= 0) {
            for (Py_ssize_t c = 0; c < count; c++) {
                if (is_number[c]) {
                    numbers[c] = starts[c] + (long long) i * steps[c];
                }
            }
            Py_ssize_t before = b.size;
            int made = 0;
            if (short_pieces) {
                made = render_short_pieces(&b, t, length, pieces, n, tail, literal, columns,
                                           numbers, is_number, i, texts, sizes, values);
            }
            if (made == 0) {
                b.size = before;
                made = render_pieces(&b, t, length, pieces, n, tail, columns, numbers,
                                     is_number, i, &ascii);
            }
            if (made < 0) {
                goto done;
            }
            if (made) {
                continue;
            }
            b.size = before;  /* this row as below */
        }
        for (Py_ssize_t c = 0; c < count; c++) {
            if (is_number[c]) {
                numbers[c] = starts[c] + (long long) i * steps[c];
                continue;
            }
            PyObject *item = PySequence_Fast_GET_ITEM(columns[c], i);
            if (PyUnicode_Check(item) && !PyUnicode_IS_ASCII(item)) {
                ascii = 0;
            }
            Py_INCREF(item);
            Py_XDECREF(PyTuple_GET_ITEM(row, c));
            PyTuple_SET_ITEM(row, c, item);
        }
        Py_ssize_t before = b.size;
        int rendered = render(&b, t, length, row, numbers, is_number);
        if (rendered < 0) {
            goto done;
        }
        if (rendered == 0) {  /* Python's own formatting, for this line */
            b.size = before;
            for (Py_ssize_t c = 0; c < count; c++) {
                if (is_number[c]) {
                    PyObject *item = PyLong_FromLongLong(numbers[c]);
                    if (!item) {
                        goto done;
                    }
                    Py_XDECREF(PyTuple_GET_ITEM(row, c));
                    PyTuple_SET_ITEM(row, c, item);
                }
            }
            PyObject *line = PyUnicode_Format(template, row);
            if (!line) {
                goto done;
            }
            ascii = ascii && PyUnicode_IS_ASCII(line);
            Py_ssize_t size;
            const char *text = PyUnicode_AsUTF8AndSize(line, &size);
            int failed = !text || append(&b, text, size) < 0;
            Py_DECREF(line);
            if (failed) {
                goto done;
            }
        }
    }
    if (ascii) {  /* the usual case: copied, not decoded */
        result = PyUnicode_New(b.size, 127);
        if (result) {
            memcpy(PyUnicode_DATA(result), b.data, b.size);
        }
    } else {
        result = PyUnicode_DecodeUTF8(b.data, b.size, NULL);
    }
done:
    PyMem_Free(pieces);
    PyMem_Free(texts);
    PyMem_Free(sizes);
    PyMem_Free(values);
    PyMem_Free(numbers);
    Py_XDECREF(row);
    if (b.data != b.inline_data) {
        PyMem_Free(b.data);
    }
    return result;
}

static PyObject *percent_rows(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    if (nargs != 2 || !PyUnicode_CheckExact(args[0])) {
        PyErr_SetString(PyExc_TypeError, "percent_rows(template: str, columns)");
        return NULL;
    }
    PyObject *given = PySequence_Fast(args[1], "percent_rows(): columns must be a sequence");
    if (!given) {
        return NULL;
    }
    Py_ssize_t count = PySequence_Fast_GET_SIZE(given), rows = PY_SSIZE_T_MAX;
    Py_ssize_t slots = count ? count : 1;
    PyObject **columns = PyMem_Calloc(slots, sizeof(PyObject *));
    long long *starts = PyMem_Calloc(slots, sizeof(long long));
    long long *steps = PyMem_Calloc(slots, sizeof(long long));
    char *is_number = PyMem_Calloc(slots, 1);
    PyObject *result = NULL;
    if (!columns || !starts || !steps || !is_number) {
        PyErr_NoMemory();
        goto done;
    }
    for (Py_ssize_t c = 0; c < count; c++) {
        PyObject *column = PySequence_Fast_GET_ITEM(given, c);
        Py_ssize_t size;
        if (range_column(column, &starts[c], &steps[c], &size)) {
            is_number[c] = 1;
        } else {
            columns[c] = PySequence_Fast(column, "percent_rows(): each column must be a sequence");
            if (!columns[c]) {
                goto done;
            }
            size = PySequence_Fast_GET_SIZE(columns[c]);
        }
        if (size < rows) {
            rows = size;  /* zip: the shortest */
        }
    }
    if (!count) {
        rows = 0;
    }
    result = render_rows(args[0], count, rows, columns, starts, steps, is_number);
done:
    if (columns) {
        for (Py_ssize_t c = 0; c < count; c++) {
            Py_XDECREF(columns[c]);
        }
        PyMem_Free(columns);
    }
    PyMem_Free(starts);
    PyMem_Free(steps);
    PyMem_Free(is_number);
    Py_DECREF(given);
    return result;
}

/*
 * numbered_rows(template, first, lines, rows, layout, columns): the text of
 * ``rows`` rows of a template of ``lines`` trace lines (a canned cycle's
 * hole), the lines numbered on from ``first``. Conversion k of the template
 * is, by layout[k]: below ``lines``, the number of that line of the row
 * (first + row * lines + layout[k]); else item ``row`` of
 * columns[layout[k] - lines]. The same text as percent_rows with a range
 * for each line number, without making those ranges.
 */
static PyObject *numbered_rows(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    if (nargs != 6 || !PyUnicode_CheckExact(args[0]) || !PyTuple_CheckExact(args[4])) {
        PyErr_SetString(PyExc_TypeError,
                        "numbered_rows(template: str, first, lines, rows, layout: tuple, columns)");
        return NULL;
    }
    long long first = PyLong_AsLongLong(args[1]);
    Py_ssize_t lines = PyLong_AsSsize_t(args[2]);
    Py_ssize_t rows = PyLong_AsSsize_t(args[3]);
    if (PyErr_Occurred()) {
        return NULL;
    }
    const long long most = 1LL << 40;  /* every number stays far inside a long long */
    if (lines < 1 || rows < 0 || rows > most || lines > most || first > most || first < -most) {
        PyErr_SetString(PyExc_ValueError, "numbered_rows(): lines, rows or first out of range");
        return NULL;
    }
    PyObject *given = PySequence_Fast(args[5], "numbered_rows(): columns must be a sequence");
    if (!given) {
        return NULL;
    }
    Py_ssize_t groups = PySequence_Fast_GET_SIZE(given);
    Py_ssize_t count = PyTuple_GET_SIZE(args[4]), slots = count ? count : 1;
    PyObject **fast = PyMem_Calloc(groups ? groups : 1, sizeof(PyObject *));
    PyObject **columns = PyMem_Calloc(slots, sizeof(PyObject *));
    long long *starts = PyMem_Calloc(slots, sizeof(long long));
    long long *steps = PyMem_Calloc(slots, sizeof(long long));
    char *is_number = PyMem_Calloc(slots, 1);
    PyObject *result = NULL;
    if (!fast || !columns || !starts || !steps || !is_number) {
        PyErr_NoMemory();
        goto done;
    }
    for (Py_ssize_t g = 0; g < groups; g++) {
        fast[g] = PySequence_Fast(PySequence_Fast_GET_ITEM(given, g),
                                  "numbered_rows(): each column must be a sequence");
        if (!fast[g]) {
            goto done;
        }
    }
    for (Py_ssize_t k = 0; k < count; k++) {
        Py_ssize_t at = PyLong_AsSsize_t(PyTuple_GET_ITEM(args[4], k));
        if (at == -1 && PyErr_Occurred()) {
            goto done;
        }
        if (at < 0 || at >= lines + groups) {
            PyErr_SetString(PyExc_ValueError, "numbered_rows(): a layout entry out of range");
            goto done;
        }
        if (at < lines) {
            is_number[k] = 1;
            starts[k] = first + at;
            steps[k] = lines;
        } else {
            columns[k] = fast[at - lines];
            if (PySequence_Fast_GET_SIZE(columns[k]) < rows) {
                PyErr_SetString(PyExc_ValueError, "numbered_rows(): a column shorter than rows");
                goto done;
            }
        }
    }
    result = render_rows(args[0], count, rows, columns, starts, steps, is_number);
done:
    if (fast) {
        for (Py_ssize_t g = 0; g < groups; g++) {
            Py_XDECREF(fast[g]);
        }
        PyMem_Free(fast);
    }
    PyMem_Free(columns);
    PyMem_Free(starts);
    PyMem_Free(steps);
    PyMem_Free(is_number);
    Py_DECREF(given);
    return result;
}

/*
 * TraceLines: runtime.canon.TraceCanon's base where this was built, with
 * its commonest calls in C, and _emit, which numbers and queues the line of
 * any call whose text TraceCanon makes in Python. The state stays visible to TraceCanon's
 * Python methods as attributes: _count, _drain_at, _column, _pending (the
 * list of lines waiting), _a/_b/_c (the rotary axes last printed) and _abc
 * (their text). Each call appends one line to _pending and calls
 * self._drain() when _count reaches _drain_at; anything unusual about the
 * arguments (not floats, not str) goes through PyUnicode_Format, as the
 * Python versions (runtime.canon.PythonTraceLines) do.
 */
#include <structmember.h>

typedef struct {
    PyObject_HEAD
    Py_ssize_t count, drain_at;
    PyObject *column, *pending, *a, *b, *c, *abc;
} TraceLines;

static int trace_traverse(TraceLines *self, visitproc visit, void *arg) {
    Py_VISIT(self->column);
    Py_VISIT(self->pending);
    Py_VISIT(self->a);
    Py_VISIT(self->b);
    Py_VISIT(self->c);
    Py_VISIT(self->abc);
    return 0;
}

static int trace_clear(TraceLines *self) {
    Py_CLEAR(self->column);
    Py_CLEAR(self->pending);
    Py_CLEAR(self->a);
    Py_CLEAR(self->b);
    Py_CLEAR(self->c);
    Py_CLEAR(self->abc);
    return 0;
}

static void trace_dealloc(TraceLines *self) {
    /* A static type: a subclass's dealloc (TraceCanon's) releases its own
     * type after this. */
    PyObject_GC_UnTrack(self);
    trace_clear(self);
    Py_TYPE(self)->tp_free((PyObject *) self);
}

/* template % args as a new str (the fast path, or Python's own). */
static PyObject *formatted(const char *template, PyObject *args) {
    buffer b;
    b.data = b.inline_data;
    b.size = 0;
    b.capacity = sizeof(b.inline_data);
    PyObject *result = NULL;
    int done = render(&b, template, (Py_ssize_t) strlen(template), args, NULL, NULL);
    if (done > 0) {
        result = PyUnicode_DecodeUTF8(b.data, b.size, NULL);
    } else if (done == 0) {
        PyObject *text = PyUnicode_FromString(template);
        if (text) {
            result = PyUnicode_Format(text, args);
            Py_DECREF(text);
        }
    }
    if (b.data != b.inline_data) {
        PyMem_Free(b.data);
    }
    return result;
}

/* Append the line, count it, drain when due. Steals `line`. */
static PyObject *add_line(TraceLines *self, PyObject *line) {
    if (!line) {
        return NULL;
    }
    if (!self->pending || !PyList_Check(self->pending)) {
        Py_DECREF(line);
        PyErr_SetString(PyExc_TypeError, "TraceLines._pending must be a list");
        return NULL;
    }
    int failed = PyList_Append(self->pending, line);
    Py_DECREF(line);
    if (failed) {
        return NULL;
    }
    if (self->count >= self->drain_at) {
        return PyObject_CallMethod((PyObject *) self, "_drain", NULL);
    }
    Py_RETURN_NONE;
}

static PyObject *column_of(TraceLines *self) {
    return self->column ? self->column : Py_None;
}

static PyObject *straight(TraceLines *self, PyObject *const *args, Py_ssize_t nargs,
                          const char *template) {
    if (nargs != 9) {
        PyErr_SetString(PyExc_TypeError, "a straight move takes the nine axes");
        return NULL;
    }
    PyObject *a = args[3], *b = args[4], *c = args[5];
    self->count++;
    if (a != self->a || b != self->b || c != self->c || !self->abc) {
        PyObject *abc_args = PyTuple_Pack(3, a, b, c);
        if (!abc_args) {
            return NULL;
        }
        PyObject *abc = formatted("%.4f, %.4f, %.4f", abc_args);
        Py_DECREF(abc_args);
        if (!abc) {
            return NULL;
        }
        Py_INCREF(a);
        Py_INCREF(b);
        Py_INCREF(c);
        Py_XSETREF(self->a, a);
        Py_XSETREF(self->b, b);
        Py_XSETREF(self->c, c);
        Py_XSETREF(self->abc, abc);
    }
    PyObject *count = PyLong_FromSsize_t(self->count);
    if (!count) {
        return NULL;
    }
    PyObject *line_args = PyTuple_Pack(6, count, column_of(self), args[0], args[1], args[2],
                                       self->abc);
    Py_DECREF(count);
    if (!line_args) {
        return NULL;
    }
    PyObject *line = formatted(template, line_args);
    Py_DECREF(line_args);
    return add_line(self, line);
}

static PyObject *straight_feed(TraceLines *self, PyObject *const *args, Py_ssize_t nargs) {
    return straight(self, args, nargs, "%5d %sSTRAIGHT_FEED(%.4f, %.4f, %.4f, %s)\n");
}

static PyObject *straight_traverse(TraceLines *self, PyObject *const *args, Py_ssize_t nargs) {
    return straight(self, args, nargs, "%5d %sSTRAIGHT_TRAVERSE(%.4f, %.4f, %.4f, %s)\n");
}

static PyObject *arc_feed(TraceLines *self, PyObject *const *args, Py_ssize_t nargs) {
    if (nargs != 12) {
        PyErr_SetString(PyExc_TypeError, "arc_feed takes twelve arguments");
        return NULL;
    }
    self->count++;
    PyObject *count = PyLong_FromSsize_t(self->count);
    if (!count) {
        return NULL;
    }
    PyObject *line_args = PyTuple_Pack(11, count, column_of(self), args[0], args[1], args[2],
                                       args[3], args[4], args[5], args[6], args[7], args[8]);
    Py_DECREF(count);
    if (!line_args) {
        return NULL;
    }
    PyObject *line = formatted(
        "%5d %sARC_FEED(%.4f, %.4f, %.4f, %.4f, %d, %.4f, %.4f, %.4f, %.4f)\n", line_args);
    Py_DECREF(line_args);
    return add_line(self, line);
}

/* The next line counted, and (its number, the N column, value) for its
 * template; NULL with an exception. */
static PyObject *next_line_args(TraceLines *self, PyObject *value) {
    self->count++;
    PyObject *count = PyLong_FromSsize_t(self->count);
    if (!count) {
        return NULL;
    }
    PyObject *line_args = PyTuple_Pack(3, count, column_of(self), value);
    Py_DECREF(count);
    return line_args;
}

static PyObject *set_feed_rate(TraceLines *self, PyObject *rate) {
    PyObject *line_args = next_line_args(self, rate);
    if (!line_args) {
        return NULL;
    }
    PyObject *line = formatted("%5d %sSET_FEED_RATE(%.4f)\n", line_args);
    Py_DECREF(line_args);
    return add_line(self, line);
}

/* _emit(text): a line of any call (its text made by TraceCanon's Python
 * method), numbered and with the N column, as the Python twin makes it. */
static PyObject *emit(TraceLines *self, PyObject *text) {
    PyObject *line_args = next_line_args(self, text);
    if (!line_args) {
        return NULL;
    }
    PyObject *line;
    PyObject *column = column_of(self);
    if (PyUnicode_CheckExact(text) && PyUnicode_IS_ASCII(text) &&
        (column == Py_None || (PyUnicode_CheckExact(column) && PyUnicode_IS_ASCII(column)))) {
        line = formatted("%5d %s%s\n", line_args);
    } else {
        /* any other text (a comment's undecodable bytes, kept as lone
         * surrogates, have no UTF-8): Python's own % */
        PyObject *template = PyUnicode_FromString("%5d %s%s\n");
        line = template ? PyUnicode_Format(template, line_args) : NULL;
        Py_XDECREF(template);
    }
    Py_DECREF(line_args);
    return add_line(self, line);
}

static PyMethodDef trace_methods[] = {
    {"_emit", (PyCFunction) emit, METH_O, NULL},
    {"straight_feed", (PyCFunction) (void (*)(void)) straight_feed, METH_FASTCALL, NULL},
    {"straight_traverse", (PyCFunction) (void (*)(void)) straight_traverse, METH_FASTCALL, NULL},
    {"arc_feed", (PyCFunction) (void (*)(void)) arc_feed, METH_FASTCALL, NULL},
    {"set_feed_rate", (PyCFunction) set_feed_rate, METH_O, NULL},
    {NULL, NULL, 0, NULL},
};

static PyMemberDef trace_members[] = {
    {"_count", T_PYSSIZET, offsetof(TraceLines, count), 0, NULL},
    {"_drain_at", T_PYSSIZET, offsetof(TraceLines, drain_at), 0, NULL},
    {"_column", T_OBJECT, offsetof(TraceLines, column), 0, NULL},
    {"_pending", T_OBJECT, offsetof(TraceLines, pending), 0, NULL},
    {"_a", T_OBJECT, offsetof(TraceLines, a), 0, NULL},
    {"_b", T_OBJECT, offsetof(TraceLines, b), 0, NULL},
    {"_c", T_OBJECT, offsetof(TraceLines, c), 0, NULL},
    {"_abc", T_OBJECT, offsetof(TraceLines, abc), 0, NULL},
    {NULL, 0, 0, 0, NULL},
};

static PyTypeObject TraceLinesType = {
    PyVarObject_HEAD_INIT(NULL, 0)
    .tp_name = "runtime._fast_format.TraceLines",
    .tp_basicsize = sizeof(TraceLines),
    .tp_flags = Py_TPFLAGS_DEFAULT | Py_TPFLAGS_BASETYPE | Py_TPFLAGS_HAVE_GC,
    .tp_doc = "TraceCanon's state and its commonest calls, in C.",
    .tp_new = PyType_GenericNew,
    .tp_dealloc = (destructor) trace_dealloc,
    .tp_traverse = (traverseproc) trace_traverse,
    .tp_clear = (inquiry) trace_clear,
    .tp_methods = trace_methods,
    .tp_members = trace_members,
};

/*
 * words(prefix, values): [prefix + text of each value], where a value's text
 * is Python's repr of it without the ".0" of an integral one (what
 * ngc2py.flatten.number writes for ordinary numbers); None, at once, where
 * a value is not a float, not finite, 1e15 or more in size, or would be
 * written with an exponent: the caller then uses number() itself.
 */
/* Python's repr of x without an integral's ".0" into out (room for 32), when
 * x has at most four decimals: x == n / 10000 for an integer n, |x| < 1e11.
 * Then that decimal reads back as x (the division, like reading the text,
 * rounds correctly once), and no shorter one does: the 1e-4 grid is finer
 * than the doubles near x, so two of its decimals never read back alike.
 * Returns the length, or 0 where x is not such a number. */
static int grid_text(double x, char *out) {
    if (!(fabs(x) < 1e11)) {
        return 0;
    }
    double n = nearbyint(x * 10000.0);
    if (n / 10000.0 != x) {
        return 0;
    }
    unsigned long long v = (unsigned long long) fabs(n);
    char text[40];
    char *end = text + sizeof(text), *start = end;
    unsigned long long fraction = v % 10000;
    if (fraction) {
        int places = 4;
        while (fraction % 10 == 0) {
            fraction /= 10;
            places--;
        }
        for (int k = 0; k < places; k++) {
            *--start = (char) ('0' + fraction % 10);
            fraction /= 10;
        }
        *--start = '.';
    }
    start -= digits_of(v / 10000, start);
    if (signbit(x)) {  /* -0.0 too: repr writes "-0.0" */
        *--start = '-';
    }
    int length = (int) (end - start);
    memcpy(out, start, (size_t) length);
    return length;
}

/* The text ngc2py.flatten.number writes for an ordinary value into out
 * (room for 40): its length, or 0 where number() itself must decide (not
 * finite, 1e15 or more, an exponent in its digits). */
static Py_ssize_t number_text(double v, char *out) {
    if (!isfinite(v) || fabs(v) >= 1e15) {
        return 0;
    }
    Py_ssize_t length = grid_text(v, out);
    if (length) {
        return length;
    }
    char *text = PyOS_double_to_string(v, 'r', 0, 0, NULL);
    if (!text) {
        PyErr_Clear();
        return 0;
    }
    length = (Py_ssize_t) strlen(text);
    if (strchr(text, 'e') || length >= 40) {
        length = 0;
    } else {
        memcpy(out, text, (size_t) length);
    }
    PyMem_Free(text);
    return length;
}

static PyObject *words(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    if (nargs != 2 || !PyUnicode_Check(args[0]) || !PyList_Check(args[1])) {
        PyErr_SetString(PyExc_TypeError, "words(prefix: str, values: list)");
        return NULL;
    }
    PyObject *prefix = args[0], *values = args[1];
    if (!PyUnicode_IS_ASCII(prefix)) {
        Py_RETURN_NONE;
    }
    Py_ssize_t plen = PyUnicode_GET_LENGTH(prefix);
    const char *pdata = (const char *) PyUnicode_1BYTE_DATA(prefix);
    Py_ssize_t count = PyList_GET_SIZE(values);
    PyObject *out = PyList_New(count);
    if (!out) {
        return NULL;
    }
    for (Py_ssize_t i = 0; i < count; i++) {
        PyObject *item = PyList_GET_ITEM(values, i);
        char text[40];
        Py_ssize_t tlen = 0;
        if (PyFloat_CheckExact(item)) {
            tlen = number_text(PyFloat_AS_DOUBLE(item), text);
        }
        if (!tlen) {  /* not a float, or number()'s to write */
            Py_DECREF(out);
            Py_RETURN_NONE;
        }
        PyObject *word = PyUnicode_New(plen + tlen, 127);
        if (word) {
            memcpy(PyUnicode_1BYTE_DATA(word), pdata, (size_t) plen);
            memcpy(PyUnicode_1BYTE_DATA(word) + plen, text, (size_t) tlen);
        }
        if (!word) {
            Py_DECREF(out);
            return NULL;
        }
        PyList_SET_ITEM(out, i, word);
    }
    return out;
}

/*
 * move_text(code, args, pos): ngc2py.flatten's text of a straight move (the
 * code, then a word for each of X Y Z A B C that differs from pos: not the
 * very same float, or not equal, or a zero of the other sign; X alone when
 * none does), pos[:6] then set to args[:6]. None, pos untouched, where a
 * value is not a float or its digits are number()'s to write.
 */
/* " " + letter + number() of v at text[*length]: 1, or 0 where number()
 * must write it (text unchanged). */
static int add_word(char *text, Py_ssize_t *length, char letter, double v) {
    Py_ssize_t size = number_text(v, text + *length + 2);
    if (!size) {
        return 0;
    }
    text[*length] = ' ';
    text[*length + 1] = letter;
    *length += 2 + size;
    return 1;
}

static PyObject *move_text(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    if (nargs != 3 || !PyUnicode_Check(args[0]) || !PyList_Check(args[2])) {
        PyErr_SetString(PyExc_TypeError, "move_text(code: str, args, pos: list)");
        return NULL;
    }
    PyObject *code = args[0], *pos = args[2];
    PyObject *given = PySequence_Fast(args[1], "move_text(): args must be a sequence");
    if (!given) {
        return NULL;
    }
    static const char letters[] = "XYZABC";
    char text[6 * 42 + 64];
    Py_ssize_t length = PyUnicode_GET_LENGTH(code);
    if (!PyUnicode_IS_ASCII(code) || length > 60 || PySequence_Fast_GET_SIZE(given) < 6 ||
        PyList_GET_SIZE(pos) < 6) {
        goto done;
    }
    memcpy(text, PyUnicode_1BYTE_DATA(code), (size_t) length);
    Py_ssize_t bare = length;
    for (int k = 0; k < 6; k++) {
        PyObject *value = PySequence_Fast_GET_ITEM(given, k), *was = PyList_GET_ITEM(pos, k);
        if (!PyFloat_CheckExact(value) || !PyFloat_CheckExact(was)) {
            goto done;
        }
        double v = PyFloat_AS_DOUBLE(value), w = PyFloat_AS_DOUBLE(was);
        if (value == was || (v == w && (v != 0.0 || signbit(v) == signbit(w)))) {
            continue;
        }
        if (!add_word(text, &length, letters[k], v)) {
            goto done;
        }
    }
    /* a move to where it is: still one axis word */
    if (length == bare &&
        !add_word(text, &length, 'X', PyFloat_AS_DOUBLE(PySequence_Fast_GET_ITEM(given, 0)))) {
        goto done;
    }
    PyObject *result = PyUnicode_New(length, 127);
    if (!result) {
        Py_DECREF(given);
        return NULL;
    }
    memcpy(PyUnicode_1BYTE_DATA(result), text, (size_t) length);
    for (int k = 0; k < 6; k++) {
        PyObject *value = PySequence_Fast_GET_ITEM(given, k);
        Py_INCREF(value);
        PyList_SetItem(pos, k, value);  /* steals the reference */
    }
    Py_DECREF(given);
    return result;
done:  /* number()'s to write, or not floats: None, pos untouched */
    Py_DECREF(given);
    Py_RETURN_NONE;
}

/*
 * short_offsets(starts, centres): for each arc, centre - start, or that
 * rounded to four decimals (nearbyint(x * 10000) / 10000, as the Python
 * twin in ngc2py/flatten.py rounds) where adding it to the start gives the
 * very centre back; None where a value is not a float.
 */
static PyObject *short_offsets(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    if (nargs != 2 || !PyList_Check(args[0]) || !PyList_Check(args[1]) ||
        PyList_GET_SIZE(args[0]) != PyList_GET_SIZE(args[1])) {
        PyErr_SetString(PyExc_TypeError, "short_offsets(starts: list, centres: list)");
        return NULL;
    }
    Py_ssize_t count = PyList_GET_SIZE(args[0]);
    PyObject *out = PyList_New(count);
    if (!out) {
        return NULL;
    }
    for (Py_ssize_t i = 0; i < count; i++) {
        PyObject *s = PyList_GET_ITEM(args[0], i), *c = PyList_GET_ITEM(args[1], i);
        if (!PyFloat_CheckExact(s) || !PyFloat_CheckExact(c)) {
            Py_DECREF(out);
            Py_RETURN_NONE;
        }
        double start = PyFloat_AS_DOUBLE(s), centre = PyFloat_AS_DOUBLE(c);
        double exact = centre - start;
        double shorter = nearbyint(exact * 10000.0) / 10000.0;
        PyObject *value = PyFloat_FromDouble(start + shorter == centre ? shorter : exact);
        if (!value) {
            Py_DECREF(out);
            return NULL;
        }
        PyList_SET_ITEM(out, i, value);
    }
    return out;
}

/* float_bits(values, start, stop): array("d", values[start:stop]).tobytes()
 * for a list, without the slice and the array: flatten looks at 230
 * parameters so after every block (FlattenCanon._parameter_changes). */
static PyObject *float_bits(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    if (nargs != 3 || !PyList_CheckExact(args[0])) {
        PyErr_SetString(PyExc_TypeError, "float_bits(values: list, start, stop)");
        return NULL;
    }
    Py_ssize_t start = PyLong_AsSsize_t(args[1]), stop = PyLong_AsSsize_t(args[2]);
    if (PyErr_Occurred()) {
        return NULL;
    }
    /* as a slice reads them (negative from the end, clipped) */
    PySlice_AdjustIndices(PyList_GET_SIZE(args[0]), &start, &stop, 1);
    if (stop < start) {
        stop = start;
    }
    PyObject *out = PyBytes_FromStringAndSize(NULL, (stop - start) * (Py_ssize_t) sizeof(double));
    if (!out) {
        return NULL;
    }
    char *at = PyBytes_AS_STRING(out);
    for (Py_ssize_t i = start; i < stop; i++) {
        PyObject *item = PyList_GET_ITEM(args[0], i);
        double x = PyFloat_CheckExact(item) ? PyFloat_AS_DOUBLE(item) : PyFloat_AsDouble(item);
        if (x == -1.0 && PyErr_Occurred()) {
            Py_DECREF(out);
            return NULL;
        }
        memcpy(at, &x, sizeof(double));
        at += sizeof(double);
    }
    return out;
}

static PyMethodDef methods[] = {
    {"move_text", (PyCFunction) (void (*)(void)) move_text, METH_FASTCALL,
     "move_text(code, args, pos): flatten's text of a straight move, or None."},
    {"float_bits", (PyCFunction) (void (*)(void)) float_bits, METH_FASTCALL,
     "float_bits(values, start, stop): array('d', values[start:stop]).tobytes()."},
    {"percent", (PyCFunction) (void (*)(void)) percent, METH_FASTCALL,
     "percent(template, args): template % args, faster for %s, %d and %.4f."},
    {"percent_rows", (PyCFunction) (void (*)(void)) percent_rows, METH_FASTCALL,
     "percent_rows(template, columns): ''.join(template % row for row in zip(*columns))"},
    {"numbered_rows", (PyCFunction) (void (*)(void)) numbered_rows, METH_FASTCALL,
     "numbered_rows(template, first, lines, rows, layout, columns): rows of numbered trace lines"},
    {"words", (PyCFunction) (void (*)(void)) words, METH_FASTCALL,
     "words(prefix, values): [prefix + the shortest decimal of each float], or None."},
    {"short_offsets", (PyCFunction) (void (*)(void)) short_offsets, METH_FASTCALL,
     "short_offsets(starts, centres): each centre - start, four decimals where they do."},
    {NULL, NULL, 0, NULL},
};

static struct PyModuleDef module = {
    PyModuleDef_HEAD_INIT, "_fast_format",
    "Trace lines formatted as Python's % operator formats them, faster.", -1, methods,
};

PyMODINIT_FUNC PyInit__fast_format(void) {
    if (PyType_Ready(&TraceLinesType) < 0) {
        return NULL;
    }
    PyObject *m = PyModule_Create(&module);
    if (!m) {
        return NULL;
    }
    Py_INCREF(&TraceLinesType);
    if (PyModule_AddObject(m, "TraceLines", (PyObject *) &TraceLinesType) < 0) {
        Py_DECREF(&TraceLinesType);
        Py_DECREF(m);
        return NULL;
    }
    return m;
}
