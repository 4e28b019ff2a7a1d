"""The progress display while the workflow fits: tqdm bars on stderr (shown only when enabled)."""
import sys


def bar(total, desc, enabled, unit="fit"):
    """A tqdm progress bar of `total` steps (of `unit`; None: not known yet) on stderr; a silent one when not
    enabled. unit="B" counts bytes, shown in kB, MB."""
    from tqdm import tqdm
    return tqdm(total=total, desc=desc, disable=not enabled, file=sys.stderr, unit=unit, mininterval=0.5,
                dynamic_ncols=True, leave=False, unit_scale=unit == "B")


def note(text, enabled):
    """One line of progress text on stderr."""
    if enabled:
        from tqdm import tqdm
        tqdm.write(text, file=sys.stderr)
