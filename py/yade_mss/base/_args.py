"""Typed checks of the public functions' own arguments: a bool is not a count, a string is not a number, a
resolution of 30.5 is not 30. Each raises TypeError (wrong kind) or ValueError (out of range) naming the
function, the argument and the value."""

import math
import numbers

import numpy as np


def _isBool(v):
    return isinstance(v, (bool, np.bool_))


INT_MAX = 2 ** 31 - 1  # counts, resolutions, masks: C++ ints
INT64_MAX = 2 ** 63 - 1  # labels, seeds


def integer(func, name, value, low=None, high=INT_MAX):
    """An int (or a float with an integral value, as 30.0), not a bool or a string, within [low, high] (by
    default at most INT_MAX, and never beyond 64 bits: Python's OverflowError is not a message)."""
    if _isBool(value) or isinstance(value, (str, bytes)) or not isinstance(value, numbers.Real):
        raise TypeError('%s: %s must be an integer, got %r' % (func, name, value))
    if isinstance(value, numbers.Integral):
        v = int(value)
    else:
        f = float(value)
        if not (math.isfinite(f) and f == int(f)):
            raise ValueError('%s: %s must be an integer, got %r' % (func, name, value))
        v = int(f)
    low = -INT64_MAX - 1 if low is None else low
    high = INT64_MAX if high is None else high
    if v < low or v > high:
        if v < low and high in (INT_MAX, INT64_MAX):
            rng = '>= %d' % low
        elif low == -INT64_MAX - 1:
            rng = '<= %d' % high
        else:
            rng = 'in [%d, %d]' % (low, high)
        raise ValueError('%s: %s must be %s, got %r' % (func, name, rng, value))
    return v


def number(func, name, value, low=None, high=None, finite=True, nan=False):
    """A real number (not a bool or a string), finite unless *finite* is False (NaN only with *nan*: for values
    whose range another layer checks with its own message), within [low, high]."""
    if _isBool(value) or isinstance(value, (str, bytes)) or not isinstance(value, numbers.Real):
        raise TypeError('%s: %s must be a number, got %r' % (func, name, value))
    v = float(value)
    if math.isnan(v) and nan:
        return v
    if math.isnan(v) or (finite and not math.isfinite(v)):
        raise ValueError('%s: %s must be a finite number, got %r' % (func, name, value))
    if (low is not None and v < low) or (high is not None and v > high):
        raise ValueError('%s: %s must be in [%s, %s], got %r' % (func, name, low, high, value))
    return v


def flag(func, name, value):
    """True or False (numpy's too), not 1 or 'yes'."""
    if not _isBool(value):
        raise TypeError('%s: %s must be True or False, got %r' % (func, name, value))
    return bool(value)


def vector(func, name, value, n=3):
    """*n* finite numbers (a list, tuple, numpy array or YADE Vector3) as a numpy array."""
    if isinstance(value, (str, bytes)):
        raise TypeError('%s: %s must be %d numbers, got the string %r' % (func, name, n, value))
    try:
        items = [value[i] for i in range(len(value))]
    except (TypeError, KeyError):
        raise TypeError('%s: %s must be %d numbers, got %r' % (func, name, n, value))
    if len(items) != n:
        raise ValueError('%s: %s must be %d numbers, got %d' % (func, name, n, len(items)))
    return np.array([number(func, name, x) for x in items])


def vector3(func, name, value):
    """Three finite numbers (a list, tuple, numpy array or YADE Vector3) as a numpy array."""
    return vector(func, name, value, 3)


def numberList(func, name, value, low=None, high=None):
    """A list of numbers (a list, tuple or 1-D array; not a string, not one number), each as :func:`number`."""
    if isinstance(value, (str, bytes, dict)) or not hasattr(value, '__iter__'):
        raise TypeError('%s: %s must be a list of numbers, got %r' % (func, name, value))
    return [number(func, name, x, low, high) for x in value]


def choice(func, name, value, allowed):
    """One of the strings *allowed*."""
    if not isinstance(value, str):
        raise TypeError('%s: %s must be one of %s, got %r' % (func, name, ', '.join(map(repr, allowed)), value))
    if value not in allowed:
        raise ValueError('%s: %s must be one of %s, got %r' % (func, name, ', '.join(map(repr, allowed)), value))
    return value


def optional(check, func, name, value, *args, **kw):
    """None, or *value* as *check* (one of the checkers above) takes it."""
    return None if value is None else check(func, name, value, *args, **kw)
