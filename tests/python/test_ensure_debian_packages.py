"""tools/ensure_debian_packages.sh with stand-ins for dpkg, dpkg-query, id and apt-get on PATH."""
import os
import subprocess
from pathlib import Path

SCRIPT = Path(__file__).resolve().parents[2] / "tools/ensure_debian_packages.sh"


def fake_tools(bin_dir, uid, installed=(), foreign=()):
    """Stand-ins that log their calls to bin_dir/calls."""
    calls = bin_dir / "calls"
    foreign_list = " ".join(foreign)
    tools = {
        "id": f'echo {uid}',
        "dpkg-query": 'for p in ' + " ".join(installed) + '; do [ "$p" = "$3" ] && echo "install ok installed" && exit 0; done; exit 1',
        "dpkg": f'echo "dpkg $*" >> {calls}; case "$1" in --print-architecture) echo amd64;; '
                f'--print-foreign-architectures) for a in {foreign_list}; do echo $a; done;; esac',
        "apt-get": f'echo "apt-get $*" >> {calls}',
    }
    for name, body in tools.items():
        path = bin_dir / name
        path.write_text("#!/bin/sh\n" + body + "\n")
        path.chmod(0o755)
    return calls


def run(tmp_path, packages, **fake):
    calls = fake_tools(tmp_path, **fake)
    env = dict(os.environ, PATH=f"{tmp_path}:{os.environ['PATH']}")
    result = subprocess.run(["sh", str(SCRIPT), *packages], capture_output=True, text=True, env=env)
    logged = calls.read_text().splitlines() if calls.exists() else []
    return result, logged


def test_nothing_missing_does_nothing(tmp_path):
    result, calls = run(tmp_path, ["gcc", "libgpiod-dev:armhf"], uid=0, installed=("gcc", "libgpiod-dev:armhf"))
    assert result.returncode == 0 and calls == []


def test_as_root_a_foreign_architecture_is_added_once_before_the_install(tmp_path):
    result, calls = run(tmp_path, ["gcc-arm-linux-gnueabihf", "libgpiod-dev:armhf", "libc6-dev:armhf"], uid=0)
    assert result.returncode == 0, result.stderr
    writes = [c for c in calls if not c.startswith("dpkg --print")]
    assert writes[0] == "dpkg --add-architecture armhf"
    assert writes.count("dpkg --add-architecture armhf") == 1
    assert writes[-1].startswith("apt-get install") and "libgpiod-dev:armhf" in writes[-1]


def test_a_known_foreign_architecture_is_not_added_again(tmp_path):
    result, calls = run(tmp_path, ["libgpiod-dev:armhf"], uid=0, foreign=("armhf",))
    assert result.returncode == 0
    assert not any("--add-architecture" in c for c in calls)


def test_not_root_names_the_packages_and_the_architecture_and_fails(tmp_path):
    result, calls = run(tmp_path, ["libgpiod-dev:armhf", "gcc"], uid=1000, installed=("gcc",))
    assert result.returncode == 1
    assert "libgpiod-dev:armhf" in result.stderr and "gcc" not in result.stderr.replace("gcc-", "")
    assert "sudo dpkg --add-architecture armhf" in result.stderr
    assert not any(c.startswith(("apt-get", "dpkg --add")) for c in calls)
