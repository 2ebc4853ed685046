# cython: language_level=3
"""Numbers of XML attributes, read once for every reader (URDF, its link contents, MJCF, SDF).

``numbers`` and ``number`` keep Python's ``float()`` semantics exactly (any spelling ``float()`` takes,
the same float for each) and refuse, naming the file, element and attribute, what is not a number,
NaN, infinity or a magnitude beyond MAX_ABS. Plain decimals, nearly every number in a robot file, are
read in C without a Python object per token; anything else goes through ``float()`` itself.
"""

from libc.string cimport memcpy
from cpython.object cimport PyObject

import math

from robkin.errors import InputError, quote

cdef extern from "Python.h":
    const char* PyUnicode_AsUTF8AndSize(object text, Py_ssize_t* size) except NULL
    double PyOS_string_to_double(const char* s, char** endptr, PyObject* overflow_exception) except? -1.0

from robkin.compiled.scanners.vocabulary import MAX_ABS  # the one bound on any number of a robot description (see there)

cdef double _MAX_ABS = MAX_ABS
cdef enum:
    _FAST_MAX = 16  # at most this many numbers are read by the fast path of ``numbers`` (MJCF: 6)


cdef inline bint _fast_char(char c) noexcept nogil:
    """A character of a plainly written decimal number (``float()`` reads these as C's strtod)."""
    return (c'0' <= c <= c'9') or c == c'.' or c == c'-' or c == c'+' or c == c'e' or c == c'E'


# exact powers of ten: every 10**k for k <= 22 is a float64 without rounding (5**22 < 2**53)
cdef double _POW10[23]
_POW10[0] = 1.0
for _k in range(1, 23):
    _POW10[_k] = _POW10[_k - 1] * 10.0


cdef Py_ssize_t _digit_run(const char* s, Py_ssize_t n, Py_ssize_t i, unsigned long long* m,
                           int* digits) noexcept nogil:
    """The digits from s[i] on appended to the integer m (leading zeros not counted in ``digits``);
    the index after them, or -1 past 17 significant digits (beyond them m could not stay exact)."""
    while i < n and c'0' <= s[i] <= c'9':
        if m[0] or s[i] != c'0':
            digits[0] += 1
            if digits[0] > 17:
                return -1
            m[0] = m[0] * 10 + <unsigned long long>(s[i] - c'0')
        i += 1
    return i


cdef bint _decimal(const char* s, Py_ssize_t n, double* out) noexcept nogil:
    """Clinger's fast path: a number [+-]digits[.digits][e[+-]digits] of at most 2**53 as an integer
    times 10**k, |k| <= 22, is that integer (exact) times or divided by 10**|k| (exact): one correctly
    rounded operation, so the float ``float()`` gives. False for anything else (taken by the slow path;
    also malformed text, which that path then refuses). ``PyOS_string_to_double`` gives the same values
    but sets the x87 control word on each call, which costs more than the whole conversion here."""
    cdef Py_ssize_t i = 0, j
    cdef unsigned long long m = 0
    cdef int digits = 0, exp10 = 0, e = 0, edigits = 0
    cdef bint negative = False, eneg = False, any_digit
    if i < n and (s[i] == c'+' or s[i] == c'-'):
        negative = s[i] == c'-'
        i += 1
    j = _digit_run(s, n, i, &m, &digits)
    if j < 0:
        return False
    any_digit, i = j > i, j
    if i < n and s[i] == c'.':
        i += 1
        j = _digit_run(s, n, i, &m, &digits)
        if j < 0:
            return False
        any_digit, exp10, i = any_digit or j > i, i - j, j
    if not any_digit:
        return False
    if i < n and (s[i] == c'e' or s[i] == c'E'):
        i += 1
        if i < n and (s[i] == c'+' or s[i] == c'-'):
            eneg = s[i] == c'-'
            i += 1
        while i < n and c'0' <= s[i] <= c'9':
            edigits += 1
            if edigits > 4:
                return False
            e = e * 10 + (s[i] - c'0')
            i += 1
        if not edigits:
            return False
        exp10 += -e if eneg else e
    if i != n or m > (1ULL << 53):
        return False
    if m == 0:
        out[0] = -0.0 if negative else 0.0
        return True
    if exp10 < -22 or exp10 > 22:
        return False
    out[0] = <double>m * _POW10[exp10] if exp10 >= 0 else <double>m / _POW10[-exp10]
    if negative:
        out[0] = -out[0]
    return True


cdef Py_ssize_t _fast_numbers(str text, double* out, Py_ssize_t most) except -2:
    """How many numbers ``text`` holds, read into ``out``, when it is plain ASCII decimals separated by
    spaces and every one is within +-MAX_ABS; -1 otherwise (the caller then takes the general path,
    which gives the same values, or the message)."""
    cdef Py_ssize_t n, k = 0, i = 0, start
    cdef const char* s
    try:
        s = PyUnicode_AsUTF8AndSize(text, &n)
    except UnicodeError:  # a lone surrogate: float() refuses it, with the message
        return -1
    cdef char* end
    cdef char buf[64]
    cdef double v
    while True:
        while i < n and s[i] == c' ':
            i += 1
        if i == n:
            return k
        start = i
        while i < n and _fast_char(s[i]):
            i += 1
        if (i < n and s[i] != c' ') or i - start >= 64 or k == most:
            return -1
        if not _decimal(s + start, i - start, &v):
            memcpy(buf, s + start, i - start)
            buf[i - start] = 0
            try:
                v = PyOS_string_to_double(buf, &end, NULL)  # NULL: overflow gives +-inf, as float()
            except ValueError:
                return -1
            if end != buf + (i - start):
                return -1
        if not -_MAX_ABS <= v <= _MAX_ABS:
            return -1
        out[k] = v
        k += 1


cpdef tuple numbers(text, Py_ssize_t count, where, what, tuple default):
    """``count`` finite numbers of bounded size from an attribute's text (``default`` if absent);
    messages name ``where`` (file and element) and ``what`` (the attribute, if not in ``where``)."""
    cdef double out[_FAST_MAX]
    cdef Py_ssize_t i
    if text is None:
        return default
    if count <= _FAST_MAX and _fast_numbers(text, out, count) == count:
        if count == 3:  # the common case (xyz, rpy, axis, box size) without a list in between
            return (out[0], out[1], out[2])
        return tuple([out[i] for i in range(count)])
    try:
        values = tuple(map(float, text.split()))
    except ValueError:
        values = None
    if values is not None and len(values) == count:
        for v in values:
            if not -MAX_ABS <= v <= MAX_ABS:  # also false for NaN
                break
        else:
            return values
    # the messages, made only for a bad attribute
    at = where if what is None else f"{where}: {what}"
    wanted = "a number" if count == 1 else f"{count} numbers"
    if values is None:
        raise InputError(f"{at}: {quote(text)} is not {wanted}")
    if len(values) != count:
        raise InputError(f"{at}: {quote(text)} has {len(values)} numbers; expected {wanted}")
    for v in values:
        if not -MAX_ABS <= v <= MAX_ABS:
            break
    bad = "contains NaN or infinity" if not math.isfinite(v) else f"has a number beyond +-{MAX_ABS:g}"
    raise InputError(f"{at}: {quote(text)} {bad}; expected {count} finite numbers of a robot's size")


cpdef object number(text, where, what, bint infinite_ok=False):
    """One number from an attribute's text (finite unless ``infinite_ok``, and within +-MAX_ABS unless
    infinite), None if absent."""
    cdef double out[1]
    if text is None:
        return None
    if _fast_numbers(text, out, 1) == 1:  # float() too ignores surrounding spaces
        return out[0]
    try:
        v = float(text)
    except ValueError:
        raise InputError(f"{where}: {what}: {quote(text)} is not a number") from None
    if math.isnan(v) or not (infinite_ok or math.isfinite(v)):
        raise InputError(f"{where}: {what}: {quote(text)} is NaN or infinite; expected a finite number")
    if math.isfinite(v) and not -MAX_ABS <= v <= MAX_ABS:  # as ``numbers``: 1e308 is no mass, no limit
        raise InputError(f"{where}: {what}: {quote(text)} is beyond +-{MAX_ABS:g}; expected a finite number "
                         f"of a robot's size")
    return v
