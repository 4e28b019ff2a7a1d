"""argparse types for numeric options: the grammar of finken.text_numbers and the range where a value means
something. A value outside is refused by argparse itself (exit status 2, "argument --x: ..."), never used nor
left to fail later with a traceback.

    parser.add_argument("--seed", type=integer(0, 2**32 - 1))
    parser.add_argument("--max-pose-gap", type=real(0, inf_ok=True))
"""
import argparse
import math

from finken.text_numbers import parse_integer, parse_number

SEED_MAX = 2**64 - 1   # the simulator's seeds are 64-bit (nps_host --seed)


def integer(low=None, high=None, hex_ok=False):
    """Type of an integer option from `low` to `high` (None: unbounded); hex_ok also takes 0x..."""
    expected = "an integer" + _range_text(low, high, low_open=False)

    def parse(text):
        try:
            value = parse_integer(text, hex_ok)
        except ValueError:
            value = None
        if value is None or (low is not None and value < low) or (high is not None and value > high):
            raise argparse.ArgumentTypeError(f"'{text}' is not {expected}")
        return value

    parse.__name__ = "integer"
    return parse


def real(low=None, high=None, low_open=False, inf_ok=False):
    """Type of a number option from `low` (excluded with low_open) to `high` (None: unbounded); never NaN,
    infinite only with inf_ok (and then within the bounds)."""
    expected = ("a number" if inf_ok else "a finite number") + _range_text(low, high, low_open)

    def parse(text):
        try:
            value = parse_number(text)
        except ValueError:
            value = math.nan
        bad = (math.isnan(value) or (math.isinf(value) and not inf_ok)
               or (low is not None and (value <= low if low_open else value < low))
               or (high is not None and value > high))
        if bad:
            raise argparse.ArgumentTypeError(f"'{text}' is not {expected}")
        return value

    parse.__name__ = "number"
    return parse


def _range_text(low, high, low_open):
    """' from 0 to 9', ' >= 0', ' > 0', ' <= 9' or ''."""
    def show(x):
        return f"{x:g}" if isinstance(x, float) else str(x)
    if low is not None and high is not None and not low_open:
        return f" from {show(low)} to {show(high)}"
    parts = [f"{'>' if low_open else '>='} {show(low)}"] if low is not None else []
    parts += [f"<= {show(high)}"] if high is not None else []
    return " " + " and ".join(parts) if parts else ""
