"""Column names of the range-log format, and the options that read a lab's own CSV as a range log.

read_range_log(path, columns=..., unit=..., fill=..., group=...) takes these as dicts; tools take them as text
on their command line and turn it into a dict with parse_column_map and parse_fill (ValueError with a reason
that names the offending item). Spec names are the six required columns and `ctx_<name>`.
"""
REQUIRED_COLUMNS = ("t", "vehicle", "sensor", "peer", "true_range", "measured")
SENSOR_NAMES = ("sonar_front", "sonar_right", "sonar_back", "sonar_left", "sonar_down", "ranging")
CTX_PREFIX = "ctx_"
UNITS = {"m": 1.0, "cm": 100.0, "mm": 1000.0}   # what true_range and measured are divided by
SPEC_NAMES = ", ".join(REQUIRED_COLUMNS) + f" or {CTX_PREFIX}<name>"


def is_spec_name(name):
    """True for a required column's name or `ctx_<name>`."""
    return name in REQUIRED_COLUMNS or (name.startswith(CTX_PREFIX) and len(name) > len(CTX_PREFIX))


def parse_items(text, what, key="spec_name", key_words="column name"):
    """`a=b,c=d` as [(a, b), (c, d)], names and values stripped of spaces; '' gives []. ValueError naming the item:
    an empty item, one without '=' (expected `key`=`what`), an empty name (`key_words`)."""
    if not text.strip():
        return []
    items = []
    for item in text.split(","):
        if not item.strip():
            raise ValueError(f"'{text.strip()}': an empty item (a comma too many)")
        name, equals, value = item.partition("=")
        name = name.strip()
        if not equals:
            raise ValueError(f"'{item.strip()}': expected {key}={what}")
        if not name:
            raise ValueError(f"'{item.strip()}': empty {key_words} before '='")
        items.append((name, value.strip()))
    return items


def check_column_map(columns):
    """`columns` ({spec name: the file's column name}, or None) checked; a new dict."""
    result = {}
    for spec, column in (columns or {}).items():
        if not isinstance(spec, str) or not is_spec_name(spec):
            raise ValueError(f"columns: unknown column '{spec}' (expected {SPEC_NAMES})")
        if not isinstance(column, str) or not column.strip():
            raise ValueError(f"columns: empty file column name for '{spec}'")
        column = column.strip()
        if column in result.values():
            other = next(s for s, c in result.items() if c == column)
            raise ValueError(f"columns: file column '{column}' is given for both '{other}' and '{spec}'")
        result[spec] = column
    return result


def check_fill(fill):
    """`fill` ({spec name: value text}, or None) checked for its names; a new dict (values are checked by
    the reader, as the file's values)."""
    result = {}
    for spec, value in (fill or {}).items():
        if not isinstance(spec, str) or not is_spec_name(spec):
            raise ValueError(f"fill: unknown column '{spec}' (expected {SPEC_NAMES})")
        if not isinstance(value, str):
            raise ValueError(f"fill: the value of '{spec}' is not text")
        result[spec] = value
    return result


def parse_column_map(text):
    """`measured=rng,true_range=real_rng` -> {"measured": "rng", "true_range": "real_rng"} ({spec name: the
    file's column}); ValueError for an unknown or repeated spec name, an empty name, a file column given twice."""
    return _parse_checked(text, "file_column", "columns", check_column_map)


def parse_fill(text):
    """`sensor=ranging,vehicle=1,peer=2` -> {"sensor": "ranging", "vehicle": "1", "peer": "2"} ({spec name:
    value text for every row}; an empty value is allowed: `peer=`); ValueError for an unknown or repeated
    spec name or an empty name."""
    return _parse_checked(text, "value", "fill", check_fill)


def _parse_checked(text, value_name, option, check):
    """{spec name: value} of `name=value,...` (parse_items), each pair checked as it is added (`check`); a spec
    name given twice is refused naming the option."""
    result = {}
    for spec, value in parse_items(text, value_name):
        if spec in result:
            raise ValueError(f"{option}: '{spec}' is given twice")
        result[spec] = value
        check(result)
    return result
