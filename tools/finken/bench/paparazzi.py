"""`make bench`'s paparazzi stage: what our shared world costs in Paparazzi's NPS (issue 27), in one run.

  1. a scratch copy of $PAPARAZZI_HOME with our overlay (finken.paparazzi.tree), and two airframes there: the example
     airframe with our world (paparazzi-sim's detector-on variant) and the same without our world
     (paparazzi_swarm_conf.bare_airframe: Paparazzi's NPS alone, on the same flight model); one build of each flown
     by every process of a run: with our world, process k is aircraft k of the world by finken_world's
     FINKEN_WORLD_AC_ID (its telemetry keeps the build's sender id, which nobody reads here); alone, nothing in a
     process depends on its ac_id but that sender id;
  2. the exchange: 4 aircraft with our world at time factor EXCHANGE_TIME_FACTOR; finken_world's stop line of each
     gives the exchange's wall time less its waiting per step (at time factor 1 the waiting, ~2 ms a step, would
     leave the difference of the line's 3 significant digits +-10 us);
  3. real time: swarms at time factor 1 for `duration_s`, with our world, then alone: 2, 4, 8, ... aircraft up to
     `cap` until a size fails, then halving the gap down to 2 aircraft (finken.bench.paparazzi_figures.next_size;
     held: why_not_real_time); the user and system time of the processes (getrusage of the children) per simulated
     second per aircraft.
Every process writes its output to logs/ (kept); our world writes no logs of its own (FINKEN_WORLD_OUT empty).
"""
import os
import resource
import time
from pathlib import Path

from finken.bench.paparazzi_figures import (Flight, exchange_figure, exchange_of, lag_warnings, next_size,
                                            search_figures, side_by_side, why_not_real_time)
from finken.paparazzi.fleet import Member, run_fleet
from finken.paparazzi.sim import (VARIANTS, build_aircraft, ivy_bus, max_aircraft, report_failure, run_base_port,
                                  simsitl_command, world_env, write_variant)
from finken.paparazzi.swarm_conf import bare_airframe, swarm_conf, template_aircraft
from finken.paparazzi.tree import (AIRFRAME, CONF_XML, PaparazziFailed, build, check_airframe, prepare_scratch_tree,
                                   tree_problem)

WORLD = VARIANTS[0]
#: Paparazzi's NPS alone: its airframe and conf file in the scratch tree, and its one aircraft
ALONE_AIRFRAME = "conf/airframes/finken/bench_alone.xml"
ALONE_CONF = "conf/userconf/finken/bench_alone.xml"
ALONE_AIRCRAFT = "FINKEN_ALONE_1"
WORLD_AIRCRAFT = WORLD.aircraft(1)[0][0]   # the one build of our world, flown as every aircraft
SEED = 1
EXCHANGE_AIRCRAFT = 4
EXCHANGE_TIME_FACTOR = 10.0
EXCHANGE_SECONDS = 30.0


class Stage:
    """The scratch tree, its environment, and the two builds: with our world and Paparazzi's NPS alone."""

    def __init__(self, home, work, jobs):
        self.tree, self.logs, self.jobs = Path(work, "tree").resolve(), Path(work, "logs").resolve(), jobs
        self.logs.mkdir(parents=True, exist_ok=True)
        print(f"  {home} -> scratch copy {self.tree}", flush=True)
        self.env = prepare_scratch_tree(home, self.tree, self.logs / "static_h.log", "headers")
        write_variant(self.tree, WORLD, 1, SEED, self.env, self.logs, "with finken_world:")
        (self.tree / ALONE_AIRFRAME).write_text(bare_airframe(self.tree / AIRFRAME))
        (self.tree / ALONE_CONF).write_text(swarm_conf(template_aircraft(self.tree / CONF_XML),
                                                       ALONE_AIRFRAME.removeprefix("conf/"), "FINKEN_ALONE_", 1))
        check_airframe("alone:", self.tree, ALONE_AIRFRAME, self.logs / "airframe_dtd_alone.log", self.env)
        build_aircraft(self.tree, [(WORLD, WORLD_AIRCRAFT)], self.env, self.logs, jobs, "with finken_world:")
        build("alone: build", self.tree, ALONE_CONF, ALONE_AIRCRAFT, "nps", self.logs / f"build_{ALONE_AIRCRAFT}.log",
              self.env, jobs)
        self.base_port = run_base_port(os.getpid())

    def _fly(self, processes, wall_limit_s):
        """Run (name, command, environment) processes side by side; returns the fleet's outcome, their outputs and
        CPU time."""
        members = [Member(name, ["stdbuf", "-oL", *command], self.logs / f"{name}.log", env, self.tree)
                   for name, command, env in processes]   # line-buffered: NPS's warnings reach the log before a SIGTERM
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        fleet = run_fleet(members, wall_limit_s, on_failure=report_failure)
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        if fleet.interrupted:
            raise KeyboardInterrupt(fleet.interrupted)
        outputs = [m.log.read_text(errors="replace") if m.log.is_file() else "" for m in members]
        return fleet, outputs, (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)

    def fly_world(self, size, duration_s, time_factor=1.0):
        """`size` aircraft in one shared world (the one build as aircraft 1 to size), each stopping itself after
        duration_s simulated seconds."""
        run = f"bench-{os.getpid()}-{size}-x{time_factor:g}"
        env = world_env(self.env, run, f"{run}-{time.time_ns()}", size, "", duration_s)
        processes = [(f"FINKEN_{k}", simsitl_command(self.tree, WORLD_AIRCRAFT, time_factor, ivy_bus(self.base_port, k)),
                      dict(env, FINKEN_WORLD_AC_ID=str(k))) for k in range(1, size + 1)]
        fleet, outputs, cpu_s = self._fly(processes, 2 * duration_s / time_factor + 10)
        return Flight(True, size, duration_s, fleet.wall_s, cpu_s,
                      unexpected=[f"{e.name}: {e.how}" + (f" ({e.stopped})" if e.stopped else "")
                                  for e in fleet.ended if not e.ok],
                      lag_warnings=sum(map(lag_warnings, outputs)),
                      exchanges=[e for e in map(exchange_of, outputs) if e is not None])

    def fly_alone(self, size, duration_s):
        """`size` processes of Paparazzi's NPS alone, stopped (SIGTERM) after duration_s of wall time."""
        processes = [(f"ALONE_{k}", simsitl_command(self.tree, ALONE_AIRCRAFT, 1.0, ivy_bus(self.base_port, k)),
                      self.env) for k in range(1, size + 1)]
        fleet, outputs, cpu_s = self._fly(processes, duration_s)
        return Flight(False, size, duration_s, fleet.wall_s, cpu_s,
                      unexpected=[f"{e.name}: {e.how}" for e in fleet.ended if not e.stopped],
                      lag_warnings=sum(map(lag_warnings, outputs)))


def _say(flight):
    why = why_not_real_time(flight)
    kind = "with finken_world" if flight.world else "alone"
    print(f"    {kind}, {flight.aircraft} aircraft: {'held real time' if why is None else 'did NOT hold: ' + why}; "
          f"{flight.wall_s:.1f} s wall, CPU {flight.cpu_per_simulated_s:.4f} s per simulated s per aircraft",
          flush=True)


def _search(fly, cap):
    """Fly the sizes next_size picks; returns the flights in the order flown."""
    flights = {}
    while (size := next_size({n: why_not_real_time(f) is None for n, f in flights.items()}, cap)) is not None:
        flights[size] = fly(size)
        _say(flights[size])
    return list(flights.values())


def paparazzi_figures(home, work, duration_s=20.0, cap=None, jobs=2) -> list[dict]:
    """Everything the stage measures (module docstring); prints as it goes and ends with the side-by-side table."""
    problem = tree_problem(home)
    if problem:
        raise PaparazziFailed(problem)
    cap = cap or max_aircraft()
    if not EXCHANGE_AIRCRAFT <= cap <= max_aircraft():
        raise PaparazziFailed(f"the largest swarm must be {EXCHANGE_AIRCRAFT}..{max_aircraft()} (a shared world's "
                              f"aircraft), not {cap}")
    stage = Stage(home, work, jobs)
    exchange = stage.fly_world(EXCHANGE_AIRCRAFT, EXCHANGE_SECONDS, EXCHANGE_TIME_FACTOR)
    figure = exchange_figure(exchange.exchanges, EXCHANGE_AIRCRAFT)
    print(f"    exchange, {EXCHANGE_AIRCRAFT} aircraft at x{EXCHANGE_TIME_FACTOR:g}: "
          + ", ".join(f"aircraft {e.ac_id} {e.exchange_us:g} - {e.waiting_us:g} waiting = {e.own_us:.3g} us"
                      for e in exchange.exchanges), flush=True)
    if exchange.unexpected:
        print(f"    exchange: not every process ended cleanly: {', '.join(exchange.unexpected)}")
    world = _search(lambda size: stage.fly_world(size, duration_s), cap)
    alone = _search(lambda size: stage.fly_alone(size, duration_s), cap)
    print(f"\n  Paparazzi's NPS at time factor 1, {duration_s:g} s per run, with our world and alone; CPU: user + "
          "system seconds of the simsitl processes per simulated second per aircraft")
    print("\n".join("  " + line for line in side_by_side(world, alone, cap)), flush=True)
    return [figure] + search_figures(world, alone, cap)
