"""finken.atomic_output: an output replaces its old file only when complete; a failure names the file and
leaves neither a partial file nor a temporary one; devices are written in place, never renamed over."""
import os
import stat
from pathlib import Path

import pytest

from finken.atomic_output import WriteError, atomic_output, write_text, write_texts


def _listing(folder):
    return sorted(p.name for p in Path(folder).iterdir())


def test_writes_and_replaces(tmp_path):
    path = tmp_path / "out.txt"
    write_text(path, "first")
    write_text(path, "second \u00e9")
    assert path.read_text(encoding="utf-8") == "second \u00e9" and _listing(tmp_path) == ["out.txt"]
    with atomic_output(tmp_path / "b.bin", "wb") as f:
        f.write(b"\x00\x01")
    assert (tmp_path / "b.bin").read_bytes() == b"\x00\x01"


def test_an_error_half_way_keeps_the_old_file(tmp_path):
    path = tmp_path / "out.txt"
    path.write_text("old")
    with pytest.raises(RuntimeError):
        with atomic_output(path) as f:
            f.write("new, half")
            raise RuntimeError("the caller failed")
    assert path.read_text() == "old" and _listing(tmp_path) == ["out.txt"]


def test_a_write_error_names_the_file(tmp_path):
    path = tmp_path / "out.txt"
    path.write_text("old")
    with pytest.raises(WriteError) as err:
        with atomic_output(path) as f:
            f.write("x")
            raise OSError(28, "No space left on device")
    assert str(err.value) == f"{path}: cannot write: No space left on device"
    assert path.read_text() == "old" and _listing(tmp_path) == ["out.txt"]
    with pytest.raises(WriteError, match=f"{tmp_path / 'absent' / 'x.txt'}: cannot write: No such file"):
        write_text(tmp_path / "absent" / "x.txt", "x")


def test_a_set_of_files_is_replaced_only_when_all_are_complete(tmp_path):
    (tmp_path / "a.txt").write_text("old a")
    (tmp_path / "b.txt").write_text("old b")
    with pytest.raises(WriteError, match="c.txt: cannot write"):
        write_texts({tmp_path / "a.txt": "new a", tmp_path / "b.txt": "new b", tmp_path / "no" / "c.txt": "c"})
    assert (tmp_path / "a.txt").read_text() == "old a" and (tmp_path / "b.txt").read_text() == "old b"
    assert _listing(tmp_path) == ["a.txt", "b.txt"]
    write_texts({tmp_path / "a.txt": "new a", tmp_path / "b.txt": "new b"})
    assert (tmp_path / "a.txt").read_text() == "new a" and (tmp_path / "b.txt").read_text() == "new b"


def test_a_link_is_followed_and_the_mode_kept(tmp_path):
    target = tmp_path / "target.txt"
    target.write_text("old")
    target.chmod(0o640)
    (tmp_path / "link.txt").symlink_to(target)
    write_text(tmp_path / "link.txt", "new")
    assert (tmp_path / "link.txt").is_symlink() and target.read_text() == "new"
    assert stat.S_IMODE(target.stat().st_mode) == 0o640


@pytest.mark.skipif(not os.path.exists("/dev/full"), reason="no /dev/full")
def test_a_device_is_written_in_place_never_replaced():
    write_text("/dev/null", "x")
    with pytest.raises(WriteError, match="^/dev/full: cannot write: No space left on device$"):
        write_text("/dev/full", "x" * 100000)
    for device in ("/dev/null", "/dev/full"):
        assert stat.S_ISCHR(os.stat(device).st_mode)
    assert not [name for name in os.listdir("/dev") if name.endswith(".tmp")]


def test_a_fifo_is_written_in_place(tmp_path):
    fifo = tmp_path / "fifo"
    os.mkfifo(fifo)
    reader = os.open(fifo, os.O_RDONLY | os.O_NONBLOCK)
    try:
        write_text(fifo, "through the pipe")
        assert os.read(reader, 100) == b"through the pipe"
    finally:
        os.close(reader)
    assert stat.S_ISFIFO(os.stat(fifo).st_mode)
