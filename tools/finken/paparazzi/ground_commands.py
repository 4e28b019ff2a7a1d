"""Commands from the ground, as the GCS sends them: ground messages on the Ivy bus of Paparazzi's server, which turns
them into uplink messages that `link` sends to the aircraft (server.ml: DL_SETTING -> SETTING, JUMP_TO_BLOCK ->
BLOCK).

Run as a program beside a swarm (a helper of fleet.run_fleet): it waits until every aircraft reports the block
`--after` (the telemetry `link` puts on the bus, ROTORCRAFT_NAV_STATUS), sets setting `--setting INDEX=VALUE` and
jumps every aircraft to block `--jump`, then waits until each reports that block or a later one, and exits 0; 1 when
the wait for either lasts longer than `--timeout` seconds (naming the aircraft that did not report). With `--picture
PNG`, it first lets the swarm fly `--picture-after` seconds and takes the GCS's picture (gcs_view.py, on $DISPLAY).
"""
import argparse
import sys
import threading
import time

from finken.paparazzi.gcs_view import take_picture

NAV_STATUS = r"^(\d+) ROTORCRAFT_NAV_STATUS \S+ \S+ \S+ \S+ (\d+) "


class Blocks:
    """The newest block each aircraft reported, and an event set whenever one changes."""

    def __init__(self):
        self.block, self.lock, self.changed = {}, threading.Lock(), threading.Event()

    def on_nav_status(self, _agent, ac_id, block):
        with self.lock:
            self.block[int(ac_id)] = int(block)
        self.changed.set()

    def wait_all(self, aircraft, ok, timeout_s):
        """Wait until ok(block) holds for every aircraft; the aircraft for which it does not (empty: done)."""
        deadline = time.monotonic() + timeout_s
        while True:
            with self.lock:
                waiting = [a for a in aircraft if not ok(self.block.get(a))]
            if not waiting or time.monotonic() >= deadline:
                return waiting
            self.changed.clear()
            self.changed.wait(max(0.0, deadline - time.monotonic()))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--bus", required=True, help="the ground segment's Ivy bus")
    ap.add_argument("--aircraft", required=True, help="aircraft ids: 1,2,3,4")
    ap.add_argument("--after", type=int, required=True, help="send once every aircraft is in this block")
    ap.add_argument("--setting", required=True, help="INDEX=VALUE of the setting to set")
    ap.add_argument("--jump", type=int, required=True, help="the block to jump to")
    ap.add_argument("--timeout", type=float, default=120.0, help="longest wait for each step [s]")
    ap.add_argument("--picture", help="PNG of the GCS's screen, taken before the commands")
    ap.add_argument("--picture-after", type=float, default=5.0, help="wall seconds of flight before the picture")
    args = ap.parse_args(argv)
    from ivy.ivy import IvyServer
    aircraft = [int(a) for a in args.aircraft.split(",")]
    index, _, value = args.setting.partition("=")
    blocks = Blocks()
    ivy = IvyServer("finken_ground_commands", "finken_ground_commands READY")
    ivy.bind_msg(blocks.on_nav_status, NAV_STATUS)
    ivy.start(args.bus)
    try:
        late = blocks.wait_all(aircraft, lambda b: b == args.after, args.timeout)
        if late:
            print(f"ground_commands: aircraft {late} not in block {args.after} after {args.timeout:g} s", flush=True)
            return 1
        if args.picture:
            time.sleep(args.picture_after)
            try:
                take_picture(args.picture)
                print(f"ground_commands: the GCS's picture: {args.picture}", flush=True)
            except RuntimeError as err:
                print(f"ground_commands: {err}", flush=True)
                return 1
        for ac_id in aircraft:
            ivy.send_msg(f"gcs DL_SETTING {ac_id} {int(index)} {float(value)}")
            ivy.send_msg(f"gcs JUMP_TO_BLOCK {ac_id} {args.jump}")
        print(f"ground_commands: sent DL_SETTING {index}={value} and JUMP_TO_BLOCK {args.jump} to {aircraft}",
              flush=True)
        late = blocks.wait_all(aircraft, lambda b: b is not None and b >= args.jump, args.timeout)
        if late:
            print(f"ground_commands: aircraft {late} did not reach block {args.jump} in {args.timeout:g} s", flush=True)
            return 1
        print(f"ground_commands: every aircraft reported block {args.jump} or later", flush=True)
        return 0
    finally:
        ivy.stop()


if __name__ == "__main__":
    sys.exit(main())
