"""Fly the FINken airframe in Paparazzi's own NPS (fdm_finken) and check hover and a guided velocity step.

What it does, in a writable Paparazzi tree (a scratch copy, never the reference tree):
  1. with --install, copies our files into the tree: the flight model (sw/simulator/nps/nps_fdm_finken.c,
     nps_finken_quadrotor.{c,h}), its descriptor (conf/modules/fdm_finken.xml), the airframe, flight plan and conf
     (conf/airframes/finken, conf/flight_plans/finken, conf/userconf/finken);
  2. writes a check flight plan, conf/flight_plans/finken/finken_arena_check.xml: finken_arena.xml (take-off to
     0.6 m, hover, GUIDED) with, in its Guided block, HOLD seconds of holding, then
     autopilot_guided_move_ned(VN, VE, 0, 0) -- the call the swarm modules make -- for STEP seconds, then a stop;
     and a conf, conf/userconf/finken/finken_check_conf.xml, with one aircraft FINKEN_CHECK of that flight plan;
  3. builds it (make AIRCRAFT=FINKEN_CHECK nps.compile, CONF_XML= that conf) and runs
     var/aircrafts/FINKEN_CHECK/nps/simsitl --norc --time_factor F --ivy_bus 127.255.255.255:PORT with
     FINKEN_FDM_LOG=<out>/fdm.csv (the flight model's log: truth, commands, autopilot mode, setpoints, estimate),
     and stops it once the log reaches DURATION simulated seconds;
  4. checks, from the log:
     - hover: the height above ground stays within 0.6 m +- HOVER_TOL (default 0.05 m) over the last 5 s of the
       NAV hover (Standby) and over the GUIDED hold before the step;
     - the velocity step: the time constant tau of v(t) = v0 + (v_cmd - v0)(1 - exp(-(t - t_step) / tau)) fitted
       (least squares) to the velocity along the command over STEP seconds lies in [TAU_MIN, TAU_MAX]
       (default 0.4-0.7 s: the host's 0.5 s, -0.1/+0.2 s), and the 63 % rise time is reported;
     - agreement with the host's flight model: nps_finken_lag (libfinken_nps.so, velocity time constant LAG_TAU,
       default the host airframe's NPS_FINKEN_VELOCITY_TAU) driven by the same guided command from the step on;
       the largest velocity difference from the step to 3 s after the stop is at most LAG_TOL (default 0.1 m/s,
       20 % of a 0.5 m/s step).
Prints the figures, writes <out>/flight_check.json, exits 0 when every check passes, 1 otherwise, 2 on a failed
build or run.

    . /work/pprz/env.sh                     # Paparazzi's environment (ivy, OCaml generators)
    make build                              # libfinken_nps.so for the lag model
    PYTHONPATH=tools build/venv/bin/python -m finken.paparazzi.flight_check \\
        --tree /tmp/pprz_fdm --install --out build/paparazzi_check
"""
import argparse
import json
import math
import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

if __package__ in (None, ""):
    sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

import numpy as np
from lxml import etree

REPO = Path(__file__).resolve().parents[3]
AIRCRAFT = "FINKEN_CHECK"
OUR_FILES = ("sw/simulator/nps/nps_fdm_finken.c", "sw/simulator/nps/nps_finken_quadrotor.c",
             "sw/simulator/nps/nps_finken_quadrotor.h", "conf/modules/fdm_finken.xml",
             "conf/airframes/finken/finken_quad.xml", "conf/flight_plans/finken/finken_arena.xml",
             "conf/userconf/finken/finken_conf.xml")
ARENA_PLAN = "conf/flight_plans/finken/finken_arena.xml"
CHECK_PLAN = "conf/flight_plans/finken/finken_arena_check.xml"
CHECK_CONF = "conf/userconf/finken/finken_check_conf.xml"
HOST_AIRFRAME = REPO / "conf/airframes/finken_nps.xml"
AP_MODE_GUIDED = 19   # Paparazzi's autopilot_static.h


class CheckError(RuntimeError):
    """The tree cannot be prepared, built or run."""


# ---------------------------------------------------------------- pure analysis

def first_order(t, v0, v_cmd, tau):
    """v0 + (v_cmd - v0)(1 - exp(-t / tau)) for t >= 0 (t in s, tau in s)."""
    return v0 + (v_cmd - v0) * (1.0 - np.exp(-np.asarray(t, dtype=float) / tau))


def fit_time_constant(t, v, v0, v_cmd, tau_lo=0.02, tau_hi=10.0):
    """Least-squares tau [s] of first_order to samples (t from the step, v), by golden-section search on log tau."""
    t, v = np.asarray(t, dtype=float), np.asarray(v, dtype=float)

    def cost(log_tau):
        return float(np.sum((first_order(t, v0, v_cmd, math.exp(log_tau)) - v) ** 2))

    a, b = math.log(tau_lo), math.log(tau_hi)
    g = (math.sqrt(5.0) - 1.0) / 2.0
    c, d = b - g * (b - a), a + g * (b - a)
    for _ in range(100):
        if cost(c) < cost(d):
            b, d = d, c
            c = b - g * (b - a)
        else:
            a, c = c, d
            d = a + g * (b - a)
    return math.exp((a + b) / 2.0)


def rise_time(t, v, v0, v_cmd, fraction=1.0 - math.exp(-1.0)):
    """First t at which v has covered `fraction` of the way from v0 to v_cmd (linear between samples); nan if never."""
    t, v = np.asarray(t, dtype=float), np.asarray(v, dtype=float)
    target = v0 + fraction * (v_cmd - v0)
    sign = 1.0 if v_cmd >= v0 else -1.0
    above = np.nonzero(sign * (v - target) >= 0.0)[0]
    if len(above) == 0:
        return float("nan")
    i = above[0]
    if i == 0:
        return float(t[0])
    return float(t[i - 1] + (t[i] - t[i - 1]) * (target - v[i - 1]) / (v[i] - v[i - 1]))


def max_abs_deviation(values, reference):
    """max |values - reference|."""
    return float(np.max(np.abs(np.asarray(values, dtype=float) - np.asarray(reference, dtype=float))))


# ---------------------------------------------------------------- the host's lag model (libfinken_nps)

def lag_model_velocities(t, cmd_north, cmd_east, v0_north, v0_east, tau_s, max_speed_mps=10.0):
    """North and east velocities of nps_finken_lag from (v0_north, v0_east) at t[0], commanded cmd_*[i] over
    [t[i-1], t[i]] (the command logged at t[i-1] holds until t[i]). The C model's frame is ENU (x east, y north)."""
    from cffi import FFI
    from finken._native import library_path
    ffi = FFI()
    ffi.cdef((REPO / "sw/simulator/nps/nps_finken_lag.cdef").read_text())
    lib = ffi.dlopen(str(library_path()))
    params = ffi.new("struct nps_finken_lag_params *", {
        "velocity_tau_s": tau_s, "yaw_tau_s": 0.3, "altitude_m": 0.6, "altitude_tau_s": 0.5,
        "max_speed_mps": max_speed_mps})
    s = ffi.new("struct nps_finken_lag_state *")
    s.pos_m[2] = 0.6
    s.vel_mps[0], s.vel_mps[1] = v0_east, v0_north
    vn, ve = [v0_north], [v0_east]
    for i in range(1, len(t)):
        lib.nps_finken_lag_step(s, params, cmd_east[i - 1], cmd_north[i - 1], 0.0, t[i] - t[i - 1])
        vn.append(s.vel_mps[1])
        ve.append(s.vel_mps[0])
    return np.array(vn), np.array(ve)


def host_velocity_tau(path=HOST_AIRFRAME, default=0.5):
    """NPS_FINKEN_VELOCITY_TAU of the host airframe (the time constant our host flies), else `default`."""
    root = etree.parse(str(path)).getroot()
    for d in root.iter("define"):
        section = d.getparent()
        if section.tag == "section" and section.get("prefix", "") + d.get("name") == "NPS_FINKEN_VELOCITY_TAU":
            return float(d.get("value"))
    return default


# ---------------------------------------------------------------- the tree, the build, the run

def install(tree):
    """Copy our files into the tree (overwriting earlier copies of them)."""
    for rel in OUR_FILES:
        dst = tree / rel
        dst.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(REPO / rel, dst)


def write_check_plan(tree, hold_s, step_s, vn, ve):
    """The arena flight plan with the guided step in its Guided block (before its endless wait)."""
    doc = etree.parse(str(tree / ARENA_PLAN))
    block = doc.find(".//block[@name='Guided']")
    if block is None:
        raise CheckError(f"{tree / ARENA_PLAN}: no block 'Guided'")
    wait = block.find("while[@cond='TRUE']")
    steps = [("while", {"cond": f"LessThan(block_time, {hold_s:g})"}),
             ("call_once", {"fun": f"autopilot_guided_move_ned({vn:g}, {ve:g}, 0., 0.)"}),
             ("while", {"cond": f"LessThan(block_time, {hold_s + step_s:g})"}),
             ("call_once", {"fun": "autopilot_guided_move_ned(0., 0., 0., 0.)"})]
    for tag, attrs in steps:
        el = etree.Element(tag, attrs)
        el.tail = "\n      "
        wait.addprevious(el)
    doc.getroot().set("name", doc.getroot().get("name") + " + guided step (flight check)")
    doc.write(str(tree / CHECK_PLAN), doctype='<!DOCTYPE flight_plan SYSTEM "../flight_plan.dtd">',
              encoding="UTF-8")


def write_check_conf(tree):
    """A conf with one aircraft: the FINken airframe flying the check flight plan."""
    conf = etree.parse(str(tree / "conf/userconf/finken/finken_conf.xml")).getroot()
    aircraft = conf.find("aircraft")
    aircraft.set("name", AIRCRAFT)
    aircraft.set("ac_id", "99")
    aircraft.set("flight_plan", "flight_plans/finken/finken_arena_check.xml")
    root = etree.Element("conf")
    root.append(aircraft)
    etree.ElementTree(root).write(str(tree / CHECK_CONF), encoding="UTF-8")


def paparazzi_env(tree, env_sh):
    """The environment for make and simsitl: env.sh sourced (if given), PAPARAZZI_HOME/SRC at the tree."""
    env = dict(os.environ)
    if env_sh:
        out = subprocess.run(["bash", "-c", f". '{env_sh}' && env -0"], capture_output=True, check=True).stdout
        env = dict(item.split("=", 1) for item in out.decode().split("\0") if "=" in item)
    env["PAPARAZZI_HOME"] = env["PAPARAZZI_SRC"] = str(tree)
    return env


def build(tree, env, log_path):
    """make AIRCRAFT=FINKEN_CHECK nps.compile from a clean aircraft directory; the build log in log_path."""
    shutil.rmtree(tree / "var/aircrafts" / AIRCRAFT, ignore_errors=True)
    cmd = ["make", "-C", str(tree), f"CONF_XML={tree / CHECK_CONF}", f"AIRCRAFT={AIRCRAFT}", "nps.compile", "J=2"]
    with open(log_path, "w") as log:
        rc = subprocess.run(cmd, env=env, stdout=log, stderr=subprocess.STDOUT).returncode
    if rc != 0:
        raise CheckError(f"the build failed ({' '.join(cmd)}): see {log_path}")
    return tree / "var/aircrafts" / AIRCRAFT / "nps/simsitl"


def last_time(csv_path):
    """Simulated time of the log's last complete row (0 if none)."""
    try:
        with open(csv_path, "rb") as f:
            f.seek(0, os.SEEK_END)
            f.seek(max(0, f.tell() - 4096))
            lines = f.read().decode(errors="replace").splitlines()
    except FileNotFoundError:
        return 0.0
    for line in reversed(lines[:-1]):   # the last line may still be being written
        try:
            return float(line.split(",", 1)[0])
        except ValueError:
            continue
    return 0.0


def run(simsitl, env, csv_path, out_log, duration_s, time_factor, ivy_port, wall_timeout_s):
    """simsitl until the flight model's log reaches duration_s simulated seconds; then SIGINT (then SIGKILL)."""
    env = dict(env, FINKEN_FDM_LOG=str(csv_path))
    csv_path.unlink(missing_ok=True)
    cmd = [str(simsitl), "--norc", "--time_factor", f"{time_factor:g}", "--ivy_bus", f"127.255.255.255:{ivy_port}"]
    start = time.monotonic()
    with open(out_log, "w") as log:
        proc = subprocess.Popen(cmd, env=env, cwd=str(simsitl.parent), stdout=log, stderr=subprocess.STDOUT,
                                start_new_session=True)
        try:
            while last_time(csv_path) < duration_s:
                if proc.poll() is not None:
                    raise CheckError(f"simsitl stopped (status {proc.returncode}) at "
                                     f"{last_time(csv_path):.1f} s: see {out_log}")
                if time.monotonic() - start > wall_timeout_s:
                    raise CheckError(f"simsitl reached only {last_time(csv_path):.1f} s in {wall_timeout_s:.0f} s")
                time.sleep(0.2)
        finally:
            if proc.poll() is None:
                proc.send_signal(signal.SIGINT)
                try:
                    proc.wait(timeout=5)
                except subprocess.TimeoutExpired:
                    proc.kill()
                    proc.wait()
    return time.monotonic() - start


def read_log(csv_path):
    """The flight model's CSV as a dict of numpy columns."""
    data = np.genfromtxt(str(csv_path), delimiter=",", names=True, invalid_raise=False)
    return {name: data[name] for name in data.dtype.names}


# ---------------------------------------------------------------- the checks

def analyse(log, hold_s, step_s, vn_cmd, ve_cmd, lag_tau_s, height_m=0.6, settle_s=3.0):
    """Figures of the flight: hover errors, the step's time constant and rise time, the gap to the lag model."""
    t = log["t_s"]
    guided = np.nonzero(log["ap_mode"] == AP_MODE_GUIDED)[0]
    if len(guided) == 0:
        raise CheckError("the aircraft never entered GUIDED mode")
    t_guided = float(t[guided[0]])
    t_step = t_guided + hold_s
    speed = math.hypot(vn_cmd, ve_cmd)
    un, ue = vn_cmd / speed, ve_cmd / speed
    v_along = log["vn_mps"] * un + log["ve_mps"] * ue
    agl = log["agl_m"]

    nav_hover = (t >= t_guided - 5.0) & (t < t_guided)
    guided_hold = (t >= t_guided + 1.0) & (t < t_step)
    step = (t >= t_step) & (t <= t_step + step_s)
    i0 = int(np.nonzero(t >= t_step)[0][0])
    v0 = float(v_along[i0])
    tau = fit_time_constant(t[step] - t_step, v_along[step], v0, speed)
    t63 = rise_time(t[step] - t_step, v_along[step], v0, speed)

    compare = (t >= t_step) & (t <= t_step + step_s + settle_s)
    tc = t[compare]
    on = (tc >= t_step) & (tc < t_step + step_s)
    lag_n, lag_e = lag_model_velocities(tc, np.where(on, vn_cmd, 0.0), np.where(on, ve_cmd, 0.0),
                                        float(log["vn_mps"][i0]), float(log["ve_mps"][i0]), lag_tau_s)
    gap = np.hypot(log["vn_mps"][compare] - lag_n, log["ve_mps"][compare] - lag_e)
    logged_cmd = np.hypot(log["sp_vn_mps"][step], log["sp_ve_mps"][step])
    return {
        "t_guided_s": t_guided,
        "t_step_s": t_step,
        "hover_nav_max_err_m": max_abs_deviation(agl[nav_hover], height_m),
        "hover_nav_mean_m": float(np.mean(agl[nav_hover])),
        "hover_guided_max_err_m": max_abs_deviation(agl[guided_hold], height_m),
        "hover_guided_mean_m": float(np.mean(agl[guided_hold])),
        "step_speed_mps": speed,
        "step_guidance_setpoint_mps": float(np.median(logged_cmd)),
        "step_tau_fit_s": tau,
        "step_t63_s": t63,
        "step_final_speed_mps": float(v_along[step][-1]),
        "step_height_max_err_m": max_abs_deviation(agl[step], height_m),
        "lag_tau_s": lag_tau_s,
        "lag_max_gap_mps": float(np.max(gap)),
        "lag_rms_gap_mps": float(np.sqrt(np.mean(gap ** 2))),
    }


def verdicts(fig, hover_tol, tau_min, tau_max, lag_tol):
    """(name, passed, text) for each check."""
    return [
        ("hover NAV", fig["hover_nav_max_err_m"] <= hover_tol,
         f"height {fig['hover_nav_mean_m']:.3f} m, max |h - 0.6| {fig['hover_nav_max_err_m']:.3f} m <= {hover_tol}"),
        ("hover GUIDED", fig["hover_guided_max_err_m"] <= hover_tol,
         f"height {fig['hover_guided_mean_m']:.3f} m, max |h - 0.6| {fig['hover_guided_max_err_m']:.3f} m "
         f"<= {hover_tol}"),
        ("step tau", tau_min <= fig["step_tau_fit_s"] <= tau_max,
         f"tau {fig['step_tau_fit_s']:.3f} s in [{tau_min}, {tau_max}] (63 % at {fig['step_t63_s']:.3f} s)"),
        ("lag model", fig["lag_max_gap_mps"] <= lag_tol,
         f"max |v - v_lag| {fig['lag_max_gap_mps']:.3f} m/s <= {lag_tol} (rms {fig['lag_rms_gap_mps']:.3f}, "
         f"lag tau {fig['lag_tau_s']} s)"),
    ]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--tree", type=Path, default=os.environ.get("PAPARAZZI_HOME"),
                    help="writable Paparazzi tree (default $PAPARAZZI_HOME)")
    ap.add_argument("--env-sh", help="a Paparazzi env.sh to source first (e.g. /work/pprz/env.sh)")
    ap.add_argument("--install", action="store_true", help="copy our files into the tree first")
    ap.add_argument("--out", type=Path, default=REPO / "build/paparazzi_check", help="logs and results")
    ap.add_argument("--duration", type=float, default=35.0, help="simulated seconds (default 35)")
    ap.add_argument("--time-factor", type=float, default=5.0)
    ap.add_argument("--ivy-port", type=int, default=2010)
    ap.add_argument("--hold", type=float, default=4.0, help="GUIDED hold before the step [s]")
    ap.add_argument("--step", type=float, default=3.0, help="duration of the velocity step [s]")
    ap.add_argument("--vn", type=float, default=0.5, help="step velocity north [m/s]")
    ap.add_argument("--ve", type=float, default=0.0, help="step velocity east [m/s]")
    ap.add_argument("--hover-tol", type=float, default=0.05)
    ap.add_argument("--tau-min", type=float, default=0.4)
    ap.add_argument("--tau-max", type=float, default=0.7)
    ap.add_argument("--lag-tau", type=float, default=None, help="default: the host airframe's NPS_FINKEN_VELOCITY_TAU")
    ap.add_argument("--lag-tol", type=float, default=0.1)
    ap.add_argument("--no-build", action="store_true", help="reuse the last build")
    args = ap.parse_args(argv)
    if args.tree is None:
        ap.error("--tree or PAPARAZZI_HOME is needed")
    if math.hypot(args.vn, args.ve) == 0.0:
        ap.error("the step needs a non-zero velocity")
    tree = args.tree.resolve()
    args.out.mkdir(parents=True, exist_ok=True)
    csv_path = args.out / "fdm.csv"
    try:
        if args.install:
            install(tree)
        write_check_plan(tree, args.hold, args.step, args.vn, args.ve)
        write_check_conf(tree)
        env = paparazzi_env(tree, args.env_sh)
        simsitl = tree / "var/aircrafts" / AIRCRAFT / "nps/simsitl"
        if not args.no_build:
            print(f"building {AIRCRAFT} in {tree} (log {args.out / 'build.log'})", flush=True)
            simsitl = build(tree, env, args.out / "build.log")
        print(f"flying {args.duration:g} s at time factor {args.time_factor:g} (log {csv_path})", flush=True)
        wall = run(simsitl, env, csv_path, args.out / "simsitl.log", args.duration, args.time_factor,
                   args.ivy_port, wall_timeout_s=3.0 * args.duration / args.time_factor + 60.0)
        lag_tau = args.lag_tau if args.lag_tau is not None else host_velocity_tau()
        fig = analyse(read_log(csv_path), args.hold, args.step, args.vn, args.ve, lag_tau)
    except (CheckError, subprocess.CalledProcessError, OSError) as err:
        print(f"paparazzi_flight_check: {err}", file=sys.stderr)
        return 2
    fig["wall_time_s"] = wall
    results = verdicts(fig, args.hover_tol, args.tau_min, args.tau_max, args.lag_tol)
    fig["checks"] = {name: ok for name, ok, _ in results}
    (args.out / "flight_check.json").write_text(json.dumps(fig, indent=2) + "\n")
    print(f"GUIDED at {fig['t_guided_s']:.2f} s, step {args.vn:g}/{args.ve:g} m/s (north/east) at "
          f"{fig['t_step_s']:.2f} s, guidance setpoint {fig['step_guidance_setpoint_mps']:.3f} m/s; "
          f"height during the step within {fig['step_height_max_err_m']:.3f} m of 0.6; "
          f"speed after {args.step:g} s {fig['step_final_speed_mps']:.3f} m/s")
    for name, ok, text in results:
        print(f"{'PASS' if ok else 'FAIL'}  {name}: {text}")
    return 0 if all(ok for _, ok, _ in results) else 1


if __name__ == "__main__":
    sys.exit(main())
