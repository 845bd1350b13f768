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


def vector3(func, name, value):
    """Three finite numbers (a list, tuple, numpy array or YADE Vector3) as a numpy array."""
    if isinstance(value, (str, bytes)):
        raise TypeError('%s: %s must be 3 numbers, got the string %r' % (func, name, value))
    try:
        items = [value[i] for i in range(len(value))]
    except TypeError:
        raise TypeError('%s: %s must be 3 numbers, got %r' % (func, name, value))
    if len(items) != 3:
        raise ValueError('%s: %s must be 3 numbers, got %d' % (func, name, len(items)))
    return np.array([number(func, name, x) for x in items])
