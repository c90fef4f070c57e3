"""A small TOML writer for the scene documents polydem.Scene builds (Python's tomllib only reads).

It writes what scene files use: tables, arrays of tables, inline tables, arrays, strings,
booleans, integers and floats. Floats are written with repr(), the shortest text that reads back
to the same bits, so a scene written here and read by polydem's reader holds exactly the values
Python held.
"""
import json
import math
import re

import numpy as np

_BARE_KEY = re.compile(r"^[A-Za-z0-9_-]+$")


def key(name):
    """A TOML key: bare where TOML allows it, else a quoted string."""
    name = str(name)
    return name if _BARE_KEY.match(name) else string(name)


def string(text):
    """A TOML basic string. json.dumps escapes quotes, backslashes and control characters in forms
    TOML shares; DEL, which TOML also forbids raw, is escaped by hand."""
    return json.dumps(str(text), ensure_ascii=False).replace("\x7f", "\\u007F")


def value(v, where="value"):
    """The TOML text of a value; ValueError (naming `where`) for NaN, infinities or a type TOML
    cannot hold."""
    if isinstance(v, (bool, np.bool_)):
        return "true" if v else "false"
    if isinstance(v, (int, np.integer)):
        return str(int(v))
    if isinstance(v, (float, np.floating)):
        f = float(v)
        if not math.isfinite(f):
            raise ValueError("%s must be finite, got %r" % (where, f))
        return repr(f)
    if isinstance(v, str):
        return string(v)
    if isinstance(v, dict):
        return "{" + ", ".join("%s = %s" % (key(k), value(x, "%s.%s" % (where, k)))
                               for k, x in v.items()) + "}"
    if isinstance(v, np.ndarray):
        v = v.tolist()
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(value(x, where) for x in v) + "]"
    raise TypeError("%s: cannot write a %s to a scene file" % (where, type(v).__name__))


def document(sections):
    """The text of a document given as a list of (name, table, is_array_entry): `[name]` tables
    and `[[name]]` entries, in the order given (the order of bodies matters to polydem)."""
    out = []
    for name, table, array_entry in sections:
        out.append(("[[%s]]" if array_entry else "[%s]") % key(name))
        for k, v in table.items():
            out.append("%s = %s" % (key(k), value(v, "%s %s" % (name, k))))
        out.append("")
    return "\n".join(out)
