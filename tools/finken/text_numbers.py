"""Numbers written as text: the one grammar every reader and numeric option of the toolkit accepts.

ASCII only, as the simulator, C's printf and Python's repr write them:
  number   [+-]? (digits [. digits] | . digits) ([eE] [+-]? digits), or nan, inf, infinity (any case, signed)
  integer  [+-]? digits (options only; with hex_ok also 0x followed by hex digits)
  id       a number whose value is a whole number from 0 to MAX_ID (so 3, 3.0 and 3e0 are copter 3)
Surrounding spaces and tabs are ignored. Python's float() and int() accept more: underscores (`1_5` reads
as 15), digits of other scripts (`١٥`, `１５`) and Unicode spaces; nothing here does. `nan` and `inf` are
returned as such: each caller says whether "no value" or an infinity means anything where it reads.
"""
import math
import re

import numpy as np

MAX_ID = 2**31 - 1   # ids are C ints in the simulator's logs (and exact in a float64)
ID_RANGE = f"an integer from 0 to {MAX_ID}"
SPACES = " \t"

# re.ASCII: without it IGNORECASE folds the dotless i (U+0131) to i, and 'ınf' would pass the grammar
_NUMBER = re.compile(r"[+-]?(?:(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][+-]?[0-9]+)?|nan|inf|infinity)",
                     re.IGNORECASE | re.ASCII)
_FIELD = re.compile(f"(?:{_NUMBER.pattern})?", re.IGNORECASE | re.ASCII)   # a number or an empty field
_INVALID_LINE = re.compile(rf"^(?!{_FIELD.pattern}$).*$", re.IGNORECASE | re.ASCII | re.MULTILINE)
# Python's float() reads an ASCII text without these characters exactly when the grammar accepts it (float()
# also takes underscores between digits and surrounding white space, and non-ASCII digits and spaces)
_FLOAT_ONLY = "_ \t\r\x0b\x0c\x1c\x1d\x1e\x1f"
_INTEGER = re.compile(r"[+-]?[0-9]+")
_HEX_INTEGER = re.compile(r"[+-]?0[xX][0-9a-fA-F]+")


class ColumnError(ValueError):
    """A field of a column outside the grammar: `index` (0 = first field) and `reason` (names the text)."""

    def __init__(self, index, reason):
        self.index, self.reason = index, reason
        super().__init__(reason)


def parse_number(text):
    """`text` as a float (nan and +-inf included); ValueError "'text' is not a number" outside the grammar."""
    stripped = text.strip(SPACES)
    if not _NUMBER.fullmatch(stripped):
        raise ValueError(f"'{stripped}' is not a number")
    return float(stripped)


def parse_finite(text):
    """`text` as a finite float; ValueError "'text' is not a finite number" otherwise."""
    try:
        value = parse_number(text)
    except ValueError:
        value = math.nan
    if not math.isfinite(value):
        raise ValueError(f"'{text.strip(SPACES)}' is not a finite number")
    return value


def parse_integer(text, hex_ok=False):
    """`text` as an int (decimal; also 0x... with hex_ok); ValueError "'text' is not an integer" otherwise."""
    stripped = text.strip(SPACES)
    if _INTEGER.fullmatch(stripped):
        return int(stripped, 10)
    if hex_ok and _HEX_INTEGER.fullmatch(stripped):
        return int(stripped, 16)
    raise ValueError(f"'{stripped}' is not an integer")


def is_id(values):
    """True where a float (or array of floats) is a whole number from 0 to MAX_ID."""
    values = np.asarray(values, dtype=np.float64)
    with np.errstate(invalid="ignore"):
        return (values >= 0) & (values <= MAX_ID) & (values == np.floor(values))


def parse_id(text):
    """`text` as an id (int from 0 to MAX_ID); ValueError "'text' is not an integer from 0 to ..." otherwise."""
    try:
        value = parse_number(text)
    except ValueError:
        value = math.nan
    if not is_id(value):
        raise ValueError(f"'{text.strip(SPACES)}' is not {ID_RANGE}")
    return int(value)


def parse_column(texts):
    """A sequence of str (surrounding spaces already removed) as a float64 array, '' as NaN; raises
    ColumnError at the first field outside the number grammar. Conversion by float() (about 50 ns a field);
    when the fields are ASCII without the few characters float() reads beyond the grammar, float() succeeding
    on every field is the grammar check, else one regular-expression search finds the first bad field."""
    texts = texts.tolist() if isinstance(texts, np.ndarray) else [str(t) for t in texts]
    if not texts:
        return np.zeros(0, dtype=np.float64)
    blob = "\n".join(texts)
    if blob.isascii() and blob.count("\n") == len(texts) - 1 and not any(c in blob for c in _FLOAT_ONLY):
        if blob == "" or "\n\n" in blob or blob[0] == "\n" or blob[-1] == "\n":
            texts = [t or "nan" for t in texts]
        try:
            return np.fromiter(map(float, texts), dtype=np.float64, count=len(texts))
        except ValueError:
            pass
    bad = _first_invalid(texts)
    if bad is not None:
        raise ColumnError(bad, f"'{texts[bad]}' is not a number")
    return np.fromiter((float(t) if t else math.nan for t in texts), dtype=np.float64, count=len(texts))


def _first_invalid(texts):
    """Index of the first str that is neither empty nor a number, or None. One search over the fields joined
    by line breaks (4 x faster than matching each field) unless a field holds a line break itself."""
    blob = "\n".join(texts)
    if blob.count("\n") == len(texts) - 1:
        found = _INVALID_LINE.search(blob)
        return None if found is None else blob.count("\n", 0, found.start())
    matches = list(map(_FIELD.fullmatch, texts))
    return matches.index(None) if None in matches else None
