"""What `make bench`'s paparazzi stage (finken.bench.paparazzi) makes of its flights: finken_world's line when a
process stops, whether a run held real time, the figures for bench.json and the table of Paparazzi's NPS with our
world against without it. Nothing here needs a Paparazzi tree.

Holding real time (time factor 1): every process ran to its end (with our world: exit 0 after its simulated
duration; alone: still flying when stopped after the duration's wall time), none printed NPS's own warning that its
simulated time falls behind the wall clock (NPS_LAG_WARNING), and, with our world, the run took at most
WALL_TOLERANCE x its simulated duration + START_S of wall time.
"""
import re
import statistics
from dataclasses import dataclass, field

#: finken_world's line when its process stops (sw/airborne/modules/finken_world/finken_world.c)
STOP_LINE = re.compile(r"finken_world: aircraft (?P<ac_id>\d+): (?P<steps>\d+) steps, (?P<peer_poses>\d+) peer poses "
                       r"\(.*\), exchange (?P<exchange>\S+) us per step \(of which waiting for others "
                       r"(?P<waiting>\S+) us\)")
#: NPS's warning (sw/simulator/nps/nps_main_sitl.c): each of more than 10 successive loops (40 ms of wall clock) had
#: more simulation steps to catch up than the one before, i.e. the simulated time keeps falling behind
NPS_LAG_WARNING = "The time factor is too large"
#: a run with our world may take this many times its simulated duration of wall time, plus START_S: the processes'
#: start (0.05 to 0.4 s here, more with more processes) and the launcher noticing their end (it looks every 0.25 s)
WALL_TOLERANCE = 1.05
START_S = 0.5


@dataclass(frozen=True)
class Exchange:
    """finken_world's figures of one process (per step of 1/512 s simulated)."""
    ac_id: int
    steps: int
    peer_poses: int
    exchange_us: float      # wall time of the whole exchange, waiting included
    waiting_us: float       # of which asleep, waiting for the other aircraft

    @property
    def own_us(self) -> float:
        """What the exchange itself costs: its wall time less the waiting."""
        return self.exchange_us - self.waiting_us


def parse_stop_line(line: str) -> Exchange | None:
    """The figures of finken_world's stop line, None for any other line."""
    m = STOP_LINE.search(line)
    if not m:
        return None
    return Exchange(int(m["ac_id"]), int(m["steps"]), int(m["peer_poses"]), float(m["exchange"]),
                    float(m["waiting"]))


def exchange_of(output: str) -> Exchange | None:
    """The last stop line in a process's output (None when it printed none: it did not end cleanly)."""
    found = [e for e in map(parse_stop_line, output.splitlines()) if e is not None]
    return found[-1] if found else None


def lag_warnings(output: str) -> int:
    """How many times NPS said its simulated time was falling behind."""
    return output.count(NPS_LAG_WARNING)


@dataclass
class Flight:
    """One run of `aircraft` NPS processes at time factor 1."""
    world: bool               # with finken_world (each process stops itself), or Paparazzi's NPS alone (stopped by us)
    aircraft: int
    duration_s: float         # simulated seconds asked of each process (alone: wall seconds before it is stopped)
    wall_s: float             # wall time of the run, from the start of the first process to the end of the last
    cpu_s: float              # user + system time of all the processes
    unexpected: list = field(default_factory=list)   # "FINKEN_3: killed by SIGSEGV": did not end as they should
    lag_warnings: int = 0     # NPS_LAG_WARNING in all their outputs
    exchanges: list = field(default_factory=list)    # Exchange of each process that printed one

    @property
    def simulated_s(self) -> float:
        """Simulated seconds per process: the duration; NPS alone runs until stopped, at real time as long as the
        wall clock (its start-up, a few tenths of a second, counted in)."""
        return self.duration_s if self.world else self.wall_s

    @property
    def cpu_per_simulated_s(self) -> float:
        """CPU seconds per simulated second per aircraft."""
        return self.cpu_s / (self.aircraft * self.simulated_s)


def why_not_real_time(flight: Flight) -> str | None:
    """Why the run did not hold real time (None when it did); module docstring."""
    if flight.unexpected:
        return (f"{len(flight.unexpected)} of {flight.aircraft} processes did not run to the end "
                f"({flight.unexpected[0]})")
    if flight.lag_warnings:
        return f"NPS warned {flight.lag_warnings} times that its simulated time fell behind"
    if flight.world and flight.wall_s > WALL_TOLERANCE * flight.duration_s + START_S:
        return (f"{flight.wall_s:.1f} s of wall time for {flight.duration_s:g} s simulated (more than "
                f"{WALL_TOLERANCE:g} x + {START_S:g} s)")
    return None


def next_size(held: dict, cap: int) -> int | None:
    """The next swarm size to fly, given whether each size flown so far held real time (size -> bool): 2, 4, 8, ...
    up to `cap` until one fails, then the even size halfway between the largest that held below it and the smallest
    that failed, until they are 2 apart. None: the search is done (the largest that held is known, or every size up
    to `cap` held). Each size is flown once: a size that fails is taken to make every larger one fail too."""
    if not held:
        return min(2, cap)
    failed = min((n for n, ok in held.items() if not ok), default=None)
    largest = max((n for n, ok in held.items() if ok and (failed is None or n < failed)), default=0)
    if failed is None:
        return min(2 * largest, cap) if largest < cap else None
    if failed - largest <= 2:
        return None
    middle = (largest + failed) // 2
    middle -= middle % 2
    return middle if middle > largest else largest + 2


def largest_held(flights: list[Flight]) -> int:
    """The largest swarm flown that held real time, every smaller one flown holding too (0: none)."""
    largest = 0
    for flight in sorted(flights, key=lambda f: f.aircraft):
        if why_not_real_time(flight) is not None:
            break
        largest = flight.aircraft
    return largest


def exchange_figure(exchanges: list[Exchange], aircraft: int) -> dict:
    """pprz_exchange_us_<aircraft>: the exchange's own cost per aircraft-step, median over the aircraft (min and max
    in the table's spread column); None when no process printed its figures."""
    costs = [e.own_us for e in exchanges]
    return {"name": f"pprz_exchange_us_{aircraft}", "value": statistics.median(costs) if costs else None, "unit": "us",
            "reps": len(costs), "min": min(costs, default=None), "max": max(costs, default=None)}


def _one(name, value, unit):
    return {"name": name, "value": value, "unit": unit, "reps": 1}


#: swarm sizes whose CPU per aircraft is a figure, with our world and alone (bench.report derives their ratios)
CPU_SIZES = (4, 16, 32)


def search_figures(world: list[Flight], alone: list[Flight], cap: int) -> list[dict]:
    """The largest swarm holding real time with our world and alone, the largest size the search may fly, and the
    CPU seconds per simulated second per aircraft of both at each size of CPU_SIZES (when flown)."""
    result = [_one("pprz_realtime_aircraft_world", largest_held(world), "aircraft"),
              _one("pprz_realtime_aircraft_alone", largest_held(alone), "aircraft"),
              _one("pprz_realtime_cap", cap, "aircraft")]
    for kind, flights in (("world", world), ("alone", alone)):
        result += [_one(f"pprz_cpu_per_sim_s_{kind}_{f.aircraft}", f.cpu_per_simulated_s, "s/s")
                   for f in flights if f.aircraft in CPU_SIZES]
    return result


def _side(flight: Flight | None, with_wall: bool) -> str:
    if flight is None:
        return f"{'':>5} {'':>8} {'':>9}" if with_wall else f"{'':>5} {'':>9}"
    held = "yes" if why_not_real_time(flight) is None else "NO"
    wall = f" {flight.wall_s:8.1f}" if with_wall else ""
    return f"{held:>5}{wall} {flight.cpu_per_simulated_s:9.4f}"


def side_by_side(world: list[Flight], alone: list[Flight], cap: int) -> list[str]:
    """The table of both searches, a row per swarm size flown, then why each run that failed did not hold real time
    and which search stopped at the cap."""
    by_size = {f.aircraft: [f, None] for f in world}
    for f in alone:
        by_size.setdefault(f.aircraft, [None, None])[1] = f
    lines = [f"{'':8}  {'with finken_world':^24}  {'Paparazzi NPS alone':^15}",
             f"{'aircraft':>8}  {'held':>5} {'wall [s]':>8} {'CPU [s/s]':>9}  {'held':>5} {'CPU [s/s]':>9}  "
             "world / alone"]
    for size in sorted(by_size):
        w, a = by_size[size]
        ratio = f"{w.cpu_per_simulated_s / a.cpu_per_simulated_s:8.2f} x" if w and a and a.cpu_s > 0 else ""
        lines.append(f"{size:8d}  {_side(w, True)}  {_side(a, False)}  {ratio}")
    for kind, flights in (("with finken_world", world), ("alone", alone)):
        lines += [f"  {kind}, {f.aircraft} aircraft: {why_not_real_time(f)}" for f in flights
                  if why_not_real_time(f) is not None]
        if flights and largest_held(flights) == cap:
            lines.append(f"  {kind}: every size up to {cap}, the largest flown, held real time: the machine's limit "
                         "is higher")
    return lines
