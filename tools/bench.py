#!/usr/bin/env python3
"""`make bench`: speed, scale and memory of the FINken simulation, measured against peers in the same run.

    tools/bench.py --bin build/bench/bin --host build/host/finken_nps/nps_host --arena conf/arena/swarmlab.xml \
        --mixture conf/sensor_models/finken_ranging_gmm_k100.xml --work build/bench --json build/bench.json \
        [--airframe conf/airframes/finken_nps.xml] [--only gmm,walls,world,host,sweep,paparazzi] [--quick]
        [--reps N] [--run-seconds S] [--sweep-runs N] [--paparazzi-max N] [--paparazzi-seconds S]

Stages (docs/performance.md says what bounds each figure):
  gmm    conditional GMM draws per second, alias-table and exact methods (tests/bench/bench_gmm.c), and the
         Python gmr package conditioning and sampling the same mixture (finken.bench.gmr_peer): their ratio
  walls  one wall step (copter index and plate dynamics) at 4 copters x 20 plates per wall, 100 copters x 1000
         plates and 1000 copters x 4000 plates (tests/bench/bench_walls.c)
  world  the simulator side alone (sonar and ranging pipelines, walls) for 4 .. 1000 copters laid out at the
         SwarmLab density, without and with the range log (tests/bench/bench_world.c)
  host   the whole NPS-style host with every sensor and module of the example airframe, 4, 16, 100 and 1000
         copters, arenas scaled to the density of 4 copters in 3 m x 4 m, 20 and 1000 plates per wall: batch runs
         without logs (the headline sim_rtf_N, and clock_ghz_N: the processor's effective clock around each run,
         tests/bench/bench_clock.c) and, with 20 plates, runs with every log (finken.bench.host)
  sweep  the Dask sweep engine (make sweep): make sim's runs of 4 copters for 60 s per minute on a LocalCluster of 1
         and of 2 workers, their ratio, and the engine's overhead per run beyond the run's own time
         (finken.bench.sweep)
  paparazzi  (when PAPARAZZI_HOME is set) Paparazzi's NPS with our shared world against without it: the exchange's
         cost per aircraft-step, the largest swarm holding real time on this machine with and without our world,
         the CPU time per simulated second per aircraft of both (finken.bench.paparazzi)
Every figure is the median of several repetitions; ratios compare figures measured in this same run.
Output: a table on the terminal and --json ({"results": [{"name", "value", "unit", "target"}]}).
"""
import argparse
import os
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from finken.bench import report as bench_report  # noqa: E402
from finken.bench.arena import write_scaled_arena  # noqa: E402
from finken.bench.gmr_peer import gmr_figures  # noqa: E402
from finken.bench.host import host_figures, startup_figure  # noqa: E402
from finken.bench.paparazzi import paparazzi_figures  # noqa: E402
from finken.bench.programs import run_program  # noqa: E402
from finken.bench.sweep import sweep_figures  # noqa: E402
from finken.cli_types import integer, real  # noqa: E402
from finken.paparazzi.sim import max_aircraft  # noqa: E402
from finken.paparazzi.tree import PaparazziFailed  # noqa: E402

STAGES = ("gmm", "walls", "world", "host", "sweep", "paparazzi")
#: swarm sizes of the whole-simulation and world stages
SIZES = (4, 16, 100, 1000)
#: plates per wall: the report's 15-20, and the 1000 the V-REP model could not afford
SEGMENTS = (20, 1000)
#: the default sensor model of the example airframe
MODEL = Path("conf/sensor_models/finken_default.xml")
#: simulated seconds x copters of one bench_world repetition (about half a second at 2 us per copter-step)
WORLD_COPTER_SECONDS = 2500.0


def size_label(vehicles: int, segments: int) -> str:
    """Suffix of a configuration's figures: "1000", or "1000_s1000" for 1000 plates per wall."""
    return f"{vehicles}" if segments == SEGMENTS[0] else f"{vehicles}_s{segments}"


def stage_gmm(args, figures):
    add(figures, run_program(args.bin / "bench_gmm", ["--mixture", args.mixture, "--reps", args.reps + 2,
                                                     "--draws", 400000 if args.quick else 4000000]))
    add(figures, gmr_figures(args.mixture, reps=args.reps, draws=20 if args.quick else 100))


def stage_walls(args, figures):
    add(figures, run_program(args.bin / "bench_walls", ["--reps", args.reps + 2, "--seconds",
                                                       60 if args.quick else 600]))


def stage_world(args, figures):
    scale = 0.2 if args.quick else 1.0
    for vehicles in SIZES:
        arena = write_scaled_arena(args.arena, args.work, vehicles, SEGMENTS[0])
        seconds = max(2.0, scale * WORLD_COPTER_SECONDS / vehicles)
        common = ["--arena", arena, "--model", MODEL, "--vehicles", vehicles, "--seconds", seconds, "--reps", args.reps]
        add(figures, run_program(args.bin / "bench_world", common + ["--suffix", "" if vehicles == 4 else
                                                                    f"_{vehicles}"]))
        if vehicles in (4, 1000):   # the same with the range log and wall snapshots, into a folder deleted after
            suffix = "_logged" if vehicles == 4 else f"_{vehicles}_logged"
            with tempfile.TemporaryDirectory(prefix="finken_bench_") as log_dir:
                add(figures, run_program(args.bin / "bench_world", common + ["--log", log_dir, "--suffix", suffix]))


def stage_host(args, figures):
    add(figures, [startup_figure(args.bin / "bench_spawn", args.host, args.arena, args.reps)])
    for segments in SEGMENTS:
        for vehicles in SIZES:
            arena = write_scaled_arena(args.arena, args.work, vehicles, segments)
            label = size_label(vehicles, segments)
            t0 = time.perf_counter()
            results = host_figures(args.bin / "bench_spawn", args.host, vehicles, arena, label, args.reps,
                                   args.run_seconds, args.work, logged=segments == SEGMENTS[0],
                                   clock=args.bin / "bench_clock")
            add(figures, results)
            value = {r["name"]: r["value"] for r in results}
            print(f"    host {vehicles:5d} copters, {segments:4d} plates per wall: {value[f'sim_rtf_{label}']:10.4g} x "
                  f"real time without logs, at {value[f'clock_ghz_{label}']:.2f} GHz "
                  f"({time.perf_counter() - t0:.0f} s)", flush=True)


def stage_sweep(args, figures):
    add(figures, sweep_figures(args.airframe, args.work / "sweep", args.reps, args.sweep_runs))


def stage_paparazzi(args, figures):
    add(figures, paparazzi_figures(os.environ["PAPARAZZI_HOME"], args.work / "paparazzi", args.paparazzi_seconds,
                                   args.paparazzi_max))


def skip_reason(stage: str) -> str | None:
    """Why a stage cannot run here (None: it can)."""
    if stage == "paparazzi" and not os.environ.get("PAPARAZZI_HOME"):
        return "PAPARAZZI_HOME is not set"
    return None


def host_description(host: Path) -> str:
    """The host binary and the modules its airframe runs (from the generator's modules.mk beside it)."""
    modules_mk = host.parent / "modules.mk"
    for line in modules_mk.read_text().splitlines() if modules_mk.is_file() else []:
        if line.startswith("HOST_MODULES"):
            return f"{host} with modules {line.split(':=', 1)[1].strip()}"
    return str(host)


STAGE_RUNNERS = {"gmm": stage_gmm, "walls": stage_walls, "world": stage_world, "host": stage_host,
                 "sweep": stage_sweep, "paparazzi": stage_paparazzi}


def add(figures: dict, results: list[dict]) -> None:
    for r in results:
        figures[r["name"]] = r


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--bin", type=Path, required=True, help="folder of the benchmark programs (bench_*)")
    ap.add_argument("--host", type=Path, required=True, help="the NPS-style host binary (make host)")
    ap.add_argument("--airframe", type=Path, default=Path("conf/airframes/finken_nps.xml"),
                    help="the airframe of the sweep stage's runs (default conf/airframes/finken_nps.xml)")
    ap.add_argument("--arena", type=Path, required=True, help="reference arena (4 copters), scaled for the others")
    ap.add_argument("--mixture", type=Path, required=True, help="ranging mixture file (K = 100)")
    ap.add_argument("--work", type=Path, required=True, help="folder for generated arenas")
    ap.add_argument("--json", type=Path, required=True, help="where to write the results")
    ap.add_argument("--only", default=",".join(STAGES), help=f"comma-separated stages of {', '.join(STAGES)}")
    ap.add_argument("--reps", type=int, default=3, help="repetitions per figure (default 3; the cheap C stages +2)")
    ap.add_argument("--run-seconds", type=float, default=3.0, help="wall-clock seconds per host run (default 3)")
    ap.add_argument("--sweep-runs", type=integer(2), default=32, metavar="N",
                    help="sweep: runs per timed sweep (default 32)")
    ap.add_argument("--paparazzi-max", type=integer(4, max_aircraft()), default=max_aircraft(), metavar="N",
                    help=f"paparazzi: the largest swarm the real-time search may fly (4..{max_aircraft()}, the "
                         "default: what a shared world holds)")
    ap.add_argument("--paparazzi-seconds", type=real(0.0, low_open=True), default=20.0, metavar="S",
                    help="paparazzi: simulated seconds of each real-time run (default 20)")
    ap.add_argument("--quick", action="store_true", help="a fast smoke run: short runs, 1 repetition")
    args = ap.parse_args(argv)
    if args.quick:
        args.reps, args.run_seconds, args.sweep_runs = 1, 0.5, 8
        args.paparazzi_max, args.paparazzi_seconds = 4, min(args.paparazzi_seconds, 5.0)
    stages = [s.strip() for s in args.only.split(",") if s.strip()]
    unknown = sorted(set(stages) - set(STAGES))
    if unknown:
        ap.error(f"--only: unknown stage(s) {', '.join(unknown)}; expected some of {', '.join(STAGES)}")
    args.work.mkdir(parents=True, exist_ok=True)
    figures, failed = {}, []
    t0 = time.perf_counter()
    for stage in (s for s in STAGES if s in stages):
        if skip_reason(stage):
            print(f"{stage}: skipped ({skip_reason(stage)})", flush=True)
            continue
        print(f"== {stage}", flush=True)
        try:
            STAGE_RUNNERS[stage](args, figures)
        except PaparazziFailed as err:
            print(f"{stage}: FAILED: {err}", flush=True)
            failed.append(stage)
    bench_report.derive(figures)
    print()
    info = bench_report.machine()
    if "host" in stages:
        info["host"] = host_description(args.host)
    if "paparazzi" in stages and not skip_reason("paparazzi"):
        info["paparazzi"] = os.environ["PAPARAZZI_HOME"]
    print(bench_report.table(figures, info))
    bench_report.write_json(figures, args.json)
    print(f"\nwrote {args.json} ({time.perf_counter() - t0:.0f} s)")
    if failed:
        print(f"FAILED: {', '.join(failed)} (see above)")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
