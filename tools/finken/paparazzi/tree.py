"""A scratch copy of a Paparazzi tree with our overlay, its environment, and Paparazzi's own make run on it.

Shared by `make paparazzi-check` (finken.paparazzi.check) and `make paparazzi-sim` (finken.paparazzi.sim): the
user's tree is only ever read; everything is built in the copy.
"""
import os
import re
import shutil
import subprocess
from pathlib import Path

from finken.paparazzi.overlay import install, overlay_files


# the example swarm's conf file and airframe, paths in the tree after the overlay
CONF_XML = "conf/userconf/finken/finken_conf.xml"
AIRFRAME = "conf/airframes/finken/finken_quad.xml"


class PaparazziFailed(RuntimeError):
    pass


def tree_problem(home):
    """Why `home` cannot be used as a Paparazzi tree (None when it can)."""
    if not home:
        return "PAPARAZZI_HOME is not set"
    for needed in ("Makefile.ac", "conf/airframes/airframe.dtd", "sw/tools/generators/gen_aircraft.out",
                   "var/include/pprzlink/messages.h"):
        if not Path(home, needed).exists():
            return (f"{home} lacks {needed}: not a Paparazzi tree with its generators and pprzlink built "
                    "(prepare one with shared/paparazzi/setup.sh, see its README)")
    return None


def paparazzi_env(tree):
    """The environment of a tree prepared by setup.sh (its env.sh beside it), pointed at the scratch copy."""
    env = dict(os.environ)
    env_sh = Path(os.environ["PAPARAZZI_HOME"]).resolve().parent / "env.sh"
    if env_sh.is_file():
        dump = subprocess.run(["bash", "-c", f". '{env_sh}' && env -0"], capture_output=True, check=True).stdout
        env.update(line.split("=", 1) for line in dump.decode().split("\0") if "=" in line)
    env.update(PAPARAZZI_HOME=str(tree), PAPARAZZI_SRC=str(tree))
    # run from `make paparazzi-check PAPARAZZI_HOME=...`, our make's command-line variables would reach Paparazzi's
    # make through MAKEFLAGS and override the environment: it would build in the user's tree, not in the copy
    for inherited in ("MAKEFLAGS", "MFLAGS", "MAKEOVERRIDES", "MAKELEVEL"):
        env.pop(inherited, None)
    return env


def run_logged(step, cmd, log, env, cwd=None, timeout=None):
    """Run cmd with its output in log; on failure raise with the error lines of the output."""
    print(f"  {step}: {' '.join(map(str, cmd))}  (log: {log})", flush=True)
    with open(log, "w") as f:
        rc = subprocess.run(cmd, stdout=f, stderr=subprocess.STDOUT, env=env, cwd=cwd, timeout=timeout).returncode
    if rc != 0:
        lines = Path(log).read_text(errors="replace").splitlines()
        errors = [l for l in lines if re.search(r"error|Error|ERROR|undefined reference", l)][:15] or lines[-15:]
        raise PaparazziFailed(f"{step} failed (exit {rc}); Paparazzi said:\n    " + "\n    ".join(errors) +
                              f"\n  full output: {log}")


def prepare_scratch_tree(home, tree, log, step):
    """Copy the tree `home` to `tree` (replacing an earlier copy), lay our overlay over it and regenerate its
    headers (make static_h, output in `log`). Returns the environment to run Paparazzi's tools in the copy."""
    shutil.rmtree(tree, ignore_errors=True)
    Path(tree).parent.mkdir(parents=True, exist_ok=True)
    shutil.copytree(home, tree, symlinks=True)
    install(tree)
    env = paparazzi_env(tree)
    run_logged(step, ["make", "-C", str(tree), "static_h"], log, env)
    return env


def check_airframe(step, tree, airframe, log, env):
    """Check the airframe file `airframe` (a path relative to `tree`) against Paparazzi's airframe.dtd (xmllint,
    output in `log`)."""
    run_logged(f"{step} {airframe} against airframe.dtd", ["xmllint", "--noout", "--valid", Path(tree) / airframe],
               log, env)


def warnings_in_our_files(log, ours):
    """Compiler warnings of the build log `log` that point into one of our files (paths relative to the tree)."""
    found = []
    for line in Path(log).read_text(errors="replace").splitlines():
        match = re.match(r"([^:\s]+):\d+:\d+: warning:", line)
        if match and any(f.endswith("/" + match[1]) or match[1].endswith("/" + f) or match[1] == f for f in ours):
            found.append(line)
    return found


def build(step, tree, conf_xml, aircraft, target, log, env, jobs):
    """Paparazzi's own make of one target of an aircraft of the conf file `conf_xml` (a path relative to `tree`);
    our files must compile without a warning."""
    run_logged(step, ["make", "-C", str(tree), f"CONF_XML={Path(tree) / conf_xml}", f"AIRCRAFT={aircraft}",
                      f"J={jobs}", f"{target}.compile"], log, env)
    warnings = warnings_in_our_files(log, overlay_files())
    if warnings:
        raise PaparazziFailed(f"{step}: {len(warnings)} compiler warning(s) in our files:\n    " +
                              "\n    ".join(warnings[:15]) + f"\n  full output: {log}")
