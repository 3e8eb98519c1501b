/* ngc2py._rowtext: the fast lane's two passes over a CAM file's bytes in C.
 *
 * line_templates() makes each line's template (ngc2py/rowrun.py), which a
 * regular expression split and three whole-text passes made before.
 *
 * rowtable.py makes a run's table rows with a score of whole-text bytes
 * operations; a 100k-line CAM file pays some 150 ms for them on its first
 * conversion. printed_rows() makes the same text in one pass over the run's
 * bytes, for the usual run: every value written plainly (a sign, at most
 * eleven integer digits without a leading zero, at most four decimals),
 * which the trace prints as its own digits padded to four decimals. Any
 * other run gets None and takes rowtable.py's way, which decides it value
 * by value.
 *
 * tests/test_rowrun.py holds each to the Python it stands for. */

#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <string.h>

typedef struct {
    char *data;
    Py_ssize_t size, capacity;
} buffer;

static int grow(buffer *b, Py_ssize_t more) {
    if (b->size + more <= b->capacity) {
        return 0;
    }
    Py_ssize_t capacity = (b->size + more) * 2;
    char *data = PyMem_Realloc(b->data, capacity);
    if (!data) {
        PyErr_NoMemory();
        return -1;
    }
    b->data = data;
    b->capacity = capacity;
    return 0;
}

static int is_blank(char c) { return c == ' ' || c == '\t'; }
static int is_digit(char c) { return c >= '0' && c <= '9'; }
static int is_letter(char c) {
    return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z');
}

/* The next character of the line that is not a blank (blanks are read as
 * nothing, wherever they are: rs274 drops them before reading). */
static const char *skip_blanks(const char *p, const char *end) {
    while (p < end && is_blank(*p)) {
        p++;
    }
    return p;
}

/* One value at p: its printed text appended to out (at most 24 bytes,
 * reserved by the caller); returns where it ends, or NULL when the value
 * is not plain (the caller gives up). */
static const char *plain_value(const char *p, const char *end, char *out, int *written) {
    char whole[16], decimals[8];
    int n_whole = 0, n_decimals = 0, negative = 0, point = 0;
    p = skip_blanks(p, end);
    if (p < end && (*p == '+' || *p == '-')) {
        negative = *p == '-';
        p = skip_blanks(p + 1, end);
    }
    while (p < end) {
        char c = *p;
        if (is_digit(c)) {
            if (point) {
                if (n_decimals == 4) {
                    return NULL;
                }
                decimals[n_decimals++] = c;
            } else {
                if (n_whole == 11) {
                    return NULL;
                }
                whole[n_whole++] = c;
            }
        } else if (c == '.' && !point) {
            point = 1;
        } else if (!is_blank(c)) {
            break;
        }
        p++;
    }
    if (n_whole + n_decimals == 0 || (n_whole > 1 && whole[0] == '0')) {
        return NULL;  /* no digit; a leading zero */
    }
    int k = 0;
    out[k++] = ' ';
    if (negative) {
        out[k++] = '-';
    }
    if (n_whole == 0) {
        out[k++] = '0';
    }
    memcpy(out + k, whole, n_whole);
    k += n_whole;
    out[k++] = '.';
    memcpy(out + k, decimals, n_decimals);
    k += n_decimals;
    while (n_decimals++ < 4) {
        out[k++] = '0';
    }
    *written = k;
    return p;
}

/* printed_rows(data, kinds, shapes, first): the table rows of a run whose
 * lines are ``data`` (each ending in a newline), line i of kind kinds[i],
 * kind k written as shape shapes[k], the first line numbered ``first``:
 * ``line shape [N digits] values`` joined by newlines, or None. */
static PyObject *printed_rows(PyObject *self, PyObject *args) {
    Py_buffer view;
    PyObject *kinds, *shapes;
    long long first;
    if (!PyArg_ParseTuple(args, "y*OOL", &view, &kinds, &shapes, &first)) {
        return NULL;
    }
    PyObject *result = NULL;
    PyObject *kind_list = PySequence_Fast(kinds, "kinds must be a sequence");
    PyObject *shape_list = kind_list ? PySequence_Fast(shapes, "shapes must be a sequence") : NULL;
    buffer b = {NULL, 0, 0};
    if (!shape_list) {
        goto done;
    }
    const char *p = view.buf, *end = p + view.len;
    Py_ssize_t rows = PySequence_Fast_GET_SIZE(kind_list);
    Py_ssize_t n_shapes = PySequence_Fast_GET_SIZE(shape_list);
    if (grow(&b, view.len + view.len / 2 + 64) < 0) {
        goto done;
    }
    for (Py_ssize_t i = 0; i < rows; i++) {
        const char *line_end = memchr(p, '\n', end - p);
        if (!line_end) {
            goto give_up;
        }
        Py_ssize_t kind = PyLong_AsSsize_t(PySequence_Fast_GET_ITEM(kind_list, i));
        if (kind < 0 || kind >= n_shapes) {
            if (PyErr_Occurred()) {
                goto done;
            }
            goto give_up;
        }
        long shape = PyLong_AsLong(PySequence_Fast_GET_ITEM(shape_list, kind));
        if (shape < 0) {
            if (PyErr_Occurred()) {
                goto done;
            }
            goto give_up;
        }
        /* a value of two bytes (X1) prints as seven ( 1.0000) */
        if (grow(&b, 4 * (line_end - p) + 64) < 0) {
            goto done;
        }
        b.size += sprintf(b.data + b.size, "%lld %ld", first + i, shape);
        Py_ssize_t values_at = b.size;  /* where the N digits go, if any */
        while (1) {
            p = skip_blanks(p, line_end);
            if (p == line_end) {
                break;
            }
            char letter = *p++;
            if (!is_letter(letter)) {
                goto give_up;
            }
            if (letter == 'G' || letter == 'g' || letter == 'M' || letter == 'm') {
                /* a code: the row's shape says it */
                while (p < line_end && (is_digit(*p) || *p == '.' || *p == '+' ||
                                        *p == '-' || is_blank(*p))) {
                    p++;
                }
                continue;
            }
            if (letter == 'N' || letter == 'n') {
                /* its digits as written, before the values */
                char digits[64];
                int count = 0;
                p = skip_blanks(p, line_end);
                while (p < line_end && (is_digit(*p) || is_blank(*p))) {
                    if (is_digit(*p)) {
                        if (count == (int) sizeof(digits)) {
                            goto give_up;
                        }
                        digits[count++] = *p;
                    }
                    p++;
                }
                if (!count || (p < line_end && !is_letter(*p))) {
                    goto give_up;
                }
                memmove(b.data + values_at + 1 + count, b.data + values_at,
                        b.size - values_at);
                b.data[values_at] = ' ';
                memcpy(b.data + values_at + 1, digits, count);
                b.size += 1 + count;
                continue;
            }
            int written = 0;
            p = plain_value(p, line_end, b.data + b.size, &written);
            if (!p || (p < line_end && !is_letter(*p))) {
                goto give_up;
            }
            b.size += written;
        }
        b.data[b.size++] = '\n';
        p = line_end + 1;
    }
    if (p != end) {
        goto give_up;
    }
    if (b.size) {
        b.size--;  /* no newline after the last row */
    }
    result = PyUnicode_New(b.size, 127);
    if (result) {
        memcpy(PyUnicode_DATA(result), b.data, b.size);
    }
    goto done;
give_up:
    result = Py_NewRef(Py_None);
done:
    PyBuffer_Release(&view);
    Py_XDECREF(kind_list);
    Py_XDECREF(shape_list);
    PyMem_Free(b.data);
    return result;
}

/* line_templates(region): each line's template (ngc2py/rowrun.py): its
 * bytes with every digit made 0 but in the values of G, M, H, L and T words
 * (a letter, a sign, then digits and points, kept apart as rowrun._KEEP
 * writes them); a list of bytes, one per line of the region (which ends
 * with a newline). */
static PyObject *line_templates(PyObject *self, PyObject *arg) {
    Py_buffer view;
    if (PyObject_GetBuffer(arg, &view, PyBUF_SIMPLE) < 0) {
        return NULL;
    }
    PyObject *result = PyList_New(0);
    char *line = NULL;
    Py_ssize_t room = 0;
    const char *p = view.buf, *end = p + view.len;
    while (result && p < end) {
        const char *stop = memchr(p, '\n', end - p);
        if (!stop) {
            break;  /* (after the last newline: not a line) */
        }
        Py_ssize_t length = stop - p;
        if (length > room) {
            char *more = PyMem_Realloc(line, length);
            if (!more) {
                PyErr_NoMemory();
                Py_CLEAR(result);
                break;
            }
            line = more;
            room = length;
        }
        int kept = 0;  /* inside a checked word's value */
        for (Py_ssize_t i = 0; i < length; i++) {
            char c = p[i];
            if (kept && ((c >= '0' && c <= '9') || c == '.')) {
                /* moved out of the way of the zeros (rowrun._KEEP) */
                line[i] = (char) (c == '.' ? 0x8A : 0x80 + (c - '0'));
                kept = 2;
                continue;
            }
            if (kept == 1 && (c == '+' || c == '-')) {
                line[i] = c;
                kept = 2;
                continue;
            }
            kept = 0;
            switch (c) {
            case 'G': case 'g': case 'M': case 'm': case 'H': case 'h':
            case 'L': case 'l': case 'T': case 't':
                kept = 1;
                line[i] = c;
                break;
            case '1': case '2': case '3': case '4': case '5':
            case '6': case '7': case '8': case '9':
                line[i] = '0';
                break;
            default:
                line[i] = c;
            }
        }
        PyObject *template = PyBytes_FromStringAndSize(line, length);
        if (!template || PyList_Append(result, template) < 0) {
            Py_CLEAR(result);
        }
        Py_XDECREF(template);
        p = stop + 1;
    }
    PyMem_Free(line);
    PyBuffer_Release(&view);
    return result;
}

static PyMethodDef methods[] = {
    {"line_templates", line_templates, METH_O,
     "line_templates(region) -> list of bytes: each line's template "
     "(see ngc2py/rowrun.py)."},
    {"printed_rows", printed_rows, METH_VARARGS,
     "printed_rows(data, kinds, shapes, first) -> str or None: a row run's "
     "table text, values as the trace prints them (see ngc2py/rowtable.py)."},
    {NULL, NULL, 0, NULL},
};

static struct PyModuleDef module = {
    PyModuleDef_HEAD_INIT, "ngc2py._rowtext",
    "The fast lane's passes over a CAM file's bytes (ngc2py/rowrun.py, "
    "ngc2py/rowtable.py).", -1, methods,
};

PyMODINIT_FUNC PyInit__rowtext(void) { return PyModule_Create(&module); }
