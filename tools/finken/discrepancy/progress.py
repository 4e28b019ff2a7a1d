"""The progress display while the workflow fits: tqdm bars on stderr (shown only when enabled)."""
import sys


def bar(total, desc, enabled, unit="fit"):
    """A tqdm progress bar of `total` steps (of `unit`) on stderr; a silent one when not enabled."""
    from tqdm import tqdm
    return tqdm(total=total, desc=desc, disable=not enabled, file=sys.stderr, unit=unit, mininterval=0.5,
                dynamic_ncols=True, leave=False)


def note(text, enabled):
    """One line of progress text on stderr."""
    if enabled:
        from tqdm import tqdm
        tqdm.write(text, file=sys.stderr)
