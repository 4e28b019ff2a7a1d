"""Whether the ground segment's ports are free before a session starts: the data link's UDP port (link binds it
alone: a second link dies with `Unix.Unix_error(Unix.EADDRINUSE, "bind", "")`) and the Ivy bus (another session's
server or GCS on it would see, and command, our aircraft too).
"""
import errno
import socket
import threading

LINK_UDP_PORT = 4242         # link -udp: the telemetry it receives (Paparazzi's default)
IVY_LISTEN_S = 1.0           # how long to listen for other agents on a bus: Ivy has no "nobody here" answer


def udp_port_problem(port=LINK_UDP_PORT):
    """Why the data link could not bind UDP `port` (None when it can)."""
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
        try:
            s.bind(("", port))
        except OSError as err:
            if err.errno == errno.EADDRINUSE:
                return (f"UDP port {port} (the data link's telemetry port) is taken: another Paparazzi link runs "
                        "(stop it, or its session)")
            return f"UDP port {port} (the data link's telemetry port): {err.strerror}"
    return None


def ivy_bus_problem(bus, listen_s=IVY_LISTEN_S):
    """Why the Ivy bus `bus` is not free (None when no other agent answered within listen_s): the names of the
    agents on it."""
    from ivy.ivy import IvyApplicationConnected, IvyServer
    agents, lock, found = set(), threading.Lock(), threading.Event()

    def on_agent(agent, event):
        if event == IvyApplicationConnected:
            with lock:
                agents.add(agent.agent_name)
            found.set()

    probe = IvyServer("finken_bus_probe", "", app_callback=on_agent)
    probe.start(bus)
    try:
        found.wait(listen_s)
    finally:
        probe.stop()
    with lock:
        if agents:
            return f"the Ivy bus {bus} is in use by {', '.join(sorted(agents))} (another session?)"
    return None
