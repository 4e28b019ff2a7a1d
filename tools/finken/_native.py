"""Private cffi (ABI mode) binding of libfinken_nps: the one C implementation of the sensor models.

The declarations live next to the C headers they mirror, in sw/simulator/nps/nps_sensor_model.cdef.
The library is $FINKEN_LIB, else <repo>/build/lib/libfinken_nps.so.
"""
import os
from pathlib import Path

import numpy as np
from cffi import FFI

REPO = Path(__file__).resolve().parents[2]
CDEF_PATH = REPO / "sw" / "simulator" / "nps" / "nps_sensor_model.cdef"
ERR_LEN = 512

_ffi = None
_lib = None


class NativeLibraryError(RuntimeError):
    """libfinken_nps.so cannot be loaded."""


def library_path():
    """Where the shared library is expected: $FINKEN_LIB, else build/lib/libfinken_nps.so in the repository."""
    return Path(os.environ.get("FINKEN_LIB") or REPO / "build" / "lib" / "libfinken_nps.so")


def load():
    """(ffi, lib), loading the library on first use."""
    global _ffi, _lib
    if _lib is None:
        path = library_path()
        if not path.is_file():
            raise NativeLibraryError(
                f"the sensor-model library {path} does not exist: run `make build` in {REPO} "
                "(or point FINKEN_LIB at libfinken_nps.so)")
        ffi = FFI()
        ffi.cdef(CDEF_PATH.read_text())
        try:
            _lib = ffi.dlopen(str(path))
        except OSError as err:
            raise NativeLibraryError(f"cannot load {path}: {err} (rebuild it with `make build`)") from err
        _ffi = ffi
    return _ffi, _lib


def err_buffer():
    """A buffer for the library's error messages."""
    ffi, _ = load()
    return ffi.new("char[]", ERR_LEN)


def text(cdata):
    """A C string as str ('' for NULL)."""
    ffi, _ = load()
    return "" if cdata == ffi.NULL else ffi.string(cdata).decode()


def strings(names):
    """(count, char *[] of the names or NULL, what keeps them alive) for a C list of strings."""
    ffi, _ = load()
    keep = [ffi.new("char[]", str(name).encode()) for name in names]
    return len(keep), (ffi.new("char *[]", keep) if keep else ffi.NULL), keep


def doubles(values, n=None):
    """A contiguous float64 copy-or-view of `values` (broadcast to length n when given)."""
    a = np.asarray(values, dtype=np.float64)
    if n is not None:
        a = np.broadcast_to(a, (n,))
    return np.ascontiguousarray(a)


def ptr(array, ctype="double *"):
    """A C pointer to a contiguous numpy array (keep the array alive while the pointer is used)."""
    ffi, _ = load()
    return ffi.cast(ctype, ffi.from_buffer(array))
