"""Checks of the values polydem.Scene's methods take, before they go into the scene text.

Each function returns the value in the form the scene file wants, or raises TypeError (a value
of the wrong kind) or ValueError (NaN, an infinity, a wrong shape, a value out of range) whose
message starts with `where`, e.g. "add_material('rock'): density must be > 0, got -1.0". A
string is a number with a unit ("30 deg", "2 GPa"): it passes unchanged, and the scene reader
checks its unit and range when the scene is built.
"""
import math
import numbers

import numpy as np


def _is_number(v):
    return isinstance(v, numbers.Real) and not isinstance(v, (bool, np.bool_))


def scalar(v, where, minimum=None, exclusive=False, maximum=None, units=True):
    """A finite number (or, with `units`, a string with a unit), optionally bounded below by
    `minimum` (strictly with `exclusive`) and above by `maximum` (strictly)."""
    if units and isinstance(v, str):
        return v
    if not _is_number(v):
        raise TypeError("%s must be a number%s, got %s" % (
            where, " or a string with a unit" if units else "", type(v).__name__))
    f = float(v)
    if not math.isfinite(f):
        raise ValueError("%s must be finite, got %r" % (where, f))
    if minimum is not None and (f <= minimum if exclusive else f < minimum):
        raise ValueError("%s must be %s %r, got %r" % (where, ">" if exclusive else ">=",
                                                       minimum, f))
    if maximum is not None and f >= maximum:
        raise ValueError("%s must be < %r, got %r" % (where, maximum, f))
    return f


def integer(v, where, minimum=None):
    """An integer (a float that is a whole number is accepted), at least `minimum`."""
    if _is_number(v) and float(v).is_integer():
        i = int(v)
    else:
        raise TypeError("%s must be an integer, got %r" % (where, v))
    if minimum is not None and i < minimum:
        raise ValueError("%s must be >= %d, got %d" % (where, minimum, i))
    return i


def boolean(v, where):
    if not isinstance(v, (bool, np.bool_)):
        raise TypeError("%s must be True or False, got %r" % (where, v))
    return bool(v)


def name(v, where):
    if not isinstance(v, str) or not v:
        raise TypeError("%s must be a non-empty string, got %r" % (where, v))
    return v


def text(v, where):
    if not isinstance(v, str):
        raise TypeError("%s must be a string, got %s" % (where, type(v).__name__))
    return v


def array(v, where, shape):
    """A float array of `shape` (None: any length along that axis) with finite entries, as nested
    lists; an array-like holding unit strings passes unchanged if its shape fits."""
    try:
        a = np.asarray(v, dtype=float)
    except (TypeError, ValueError):
        a = None
    if a is None:
        raw = np.asarray(v, dtype=object)
        if _fits(raw.shape, shape) and all(isinstance(x, str) or _is_number(x)
                                           for x in raw.ravel()):
            return raw.tolist()
        raise TypeError("%s must be numbers of shape %s, got %r" % (where, _shape_text(shape), v))
    if not _fits(a.shape, shape):
        raise ValueError("%s must have shape %s, got shape %s" % (where, _shape_text(shape),
                                                                 tuple(a.shape)))
    if not np.all(np.isfinite(a)):
        raise ValueError("%s must be finite, got %r" % (where, a.tolist()))
    return a.tolist()


def vec3(v, where):
    return array(v, where, (3,))


def _fits(actual, wanted):
    return len(actual) == len(wanted) and all(w is None or a == w for a, w in zip(actual, wanted))


def _shape_text(shape):
    return "(" + ", ".join("n" if s is None else str(s) for s in shape) + (",)" if len(shape) == 1
                                                                           else ")")


def quaternion(v, where):
    """A rotation given as a quaternion (w, x, y, z), not zero (the reader normalises it)."""
    q = array(v, where, (4,))
    if not all(_is_number(x) for x in q) or math.sqrt(sum(x * x for x in q)) == 0.0:
        raise ValueError("%s must be a non-zero quaternion (w, x, y, z) of numbers, got %r"
                         % (where, q))
    return {"quaternion": q}


def rotation(v, where):
    """A rotation as scene files write it: a dict ({"axis": .., "angle": ..}, {"quaternion": ..},
    {"euler_zyx": ..}) or a list of them, applied in order."""
    if isinstance(v, dict):
        return {name(k, where + " key"): _plain(x, "%s %s" % (where, k)) for k, x in v.items()}
    if isinstance(v, (list, tuple)) and v and all(isinstance(r, dict) for r in v):
        return [rotation(r, where) for r in v]
    raise TypeError("%s must be a dict such as {'axis': [0, 0, 1], 'angle': 30} or a list of "
                    "them, got %r" % (where, v))


def _plain(v, where):
    """A value inside a dict (region, joint set, rotation): numbers, strings, booleans, arrays of
    them, nested dicts; NaN and infinities refused."""
    if isinstance(v, dict):
        return {name(k, where + " key"): _plain(x, "%s %s" % (where, k)) for k, x in v.items()}
    if isinstance(v, (str, bool, np.bool_)):
        return bool(v) if isinstance(v, np.bool_) else v
    if isinstance(v, numbers.Integral):
        return int(v)  # counts stay integers
    if _is_number(v):
        return scalar(v, where)
    if isinstance(v, (list, tuple, np.ndarray)):
        return [_plain(x, where) for x in (v.tolist() if isinstance(v, np.ndarray) else v)]
    raise TypeError("%s: unsupported value %r" % (where, v))


def table(v, where):
    """A dict of scene-file keys (a rock mass's region, a joint set), checked as _plain."""
    if not isinstance(v, dict):
        raise TypeError("%s must be a dict, got %s" % (where, type(v).__name__))
    return _plain(v, where)
