/*
 * plain_decimal(s, size, &value): a table cell such as "-12.3450" as a
 * double, exactly as float() reads it, without the general decimal reader
 * (about ten times quicker). Shared by runtime/_libm_trig.c (a column of
 * cells) and runtime/fast/_arc_row.c (an arc row's words).
 *
 * A plain decimal, [+-]digits[.digits] as CAM programs write numbers, whose
 * digits make an integer n of at most 2**53 with k <= 22 of them after the
 * point: n and 10**k are both exact doubles, so n / 10**k is one correctly
 * rounded division, the correctly rounded value of the decimal, which is
 * what float() returns (Clinger's fast path). Returns 1 with *value set, or
 * 0 for anything else (spaces, underscores, exponents, inf, nan, more
 * digits): the caller then asks float().
 */
#ifndef NGC2PY_PLAIN_DECIMAL_H
#define NGC2PY_PLAIN_DECIMAL_H

static const double plain_decimal_powers[] = {
    1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,  1e10, 1e11,
    1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22,
};

static int plain_decimal(const char *s, Py_ssize_t size, double *value) {
    const char *c = s, *end = s + size;
    int negative = 0, point = 0, digits = 0, decimals = 0;
    unsigned long long n = 0;
    if (c < end && (*c == '-' || *c == '+')) {
        negative = *c == '-';
        c++;
    }
    for (; c < end; c++) {
        if (*c >= '0' && *c <= '9') {
            if (n > 900719925474099ULL) { /* n * 10 + 9 could pass 2**53 */
                return 0;
            }
            n = n * 10 + (unsigned long long) (*c - '0');
            digits++;
            decimals += point;
        } else if (*c == '.' && !point) {
            point = 1;
        } else {
            return 0;
        }
    }
    if (!digits || decimals > 22 || n > (1ULL << 53)) {
        return 0;
    }
    double x = (double) n / plain_decimal_powers[decimals];
    *value = negative ? -x : x;
    return 1;
}

#endif
