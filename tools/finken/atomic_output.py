"""Write an output file so that nothing already there is lost: into a temporary file beside it, renamed over it
only once every byte is on disk. A failure (a full disk, a missing folder, an error of the caller half-way)
leaves the old file, or no file, and no temporary one; it is raised as WriteError naming the file.

A path naming something other than a regular file (/dev/null, /dev/stdout, a FIFO) is written in place:
renaming over it would replace the device. A symbolic link is followed: its target is replaced.

    with atomic_output("out.csv", newline="") as f:
        f.write(...)
    write_texts({"report.json": ..., "report.html": ...})   # a set of files: all renamed at the end
"""
import os
import secrets
import shutil
import stat
from contextlib import ExitStack, contextmanager
from pathlib import Path


class WriteError(OSError):
    """An output that could not be written: `path: cannot write: reason`."""

    def __init__(self, path, err):
        super().__init__(err.errno, err.strerror or str(err), str(path))
        self.path = str(path)

    def __str__(self):
        return f"{self.path}: cannot write: {self.strerror}"


@contextmanager
def atomic_output(path, mode="w", encoding=None, newline=None):
    """Open `path` for writing ("w" text, "wb" binary, UTF-8 by default) through a temporary file; yields the
    file object. Any OSError inside the block or while finishing the file is raised as WriteError."""
    in_place = _is_special(path)
    final = Path(os.path.realpath(path))
    target = Path(path) if in_place else final.with_name(f".{final.name}.{os.getpid()}.{secrets.token_hex(4)}.tmp")
    if encoding is None and "b" not in mode:
        encoding = "utf-8"
    done = False
    try:
        with open(target, mode if in_place else mode.replace("w", "x"), encoding=encoding, newline=newline) as f:
            yield f
            f.flush()
            if not in_place:
                os.fsync(f.fileno())
        if not in_place:
            if final.is_file():
                shutil.copymode(final, target)
            os.replace(target, final)
        done = True
    except WriteError:
        raise   # another output's (atomic_output blocks nest in write_texts)
    except OSError as err:
        raise WriteError(path, err) from err
    finally:
        if not (done or in_place):
            target.unlink(missing_ok=True)


def _is_special(path):
    """True if `path` (followed through links) exists and is not a regular file."""
    try:
        return not stat.S_ISREG(os.stat(path).st_mode)
    except OSError:
        return False


def write_text(path, text):
    """Write the str `text` (UTF-8) to `path` with atomic_output."""
    write_texts({path: text})


def write_texts(texts):
    """Write several files ({path: str}, UTF-8) as a set: every one is complete under its temporary name before
    the first is renamed, so a failure leaves all the old files (and no temporary one)."""
    with ExitStack() as files:
        for path, text in texts.items():
            files.enter_context(atomic_output(path)).write(text)
