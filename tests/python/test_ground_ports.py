"""The ground segment's ports checked before a session starts (tools/finken/paparazzi/ground_ports.py): a taken
UDP port and an Ivy bus with another agent on it are named; free ones pass."""
import os
import socket

from ivy.ivy import IvyServer

from finken.paparazzi.ground_ports import ivy_bus_problem, udp_port_problem


def test_a_taken_udp_port_is_named():
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as taken:
        taken.bind(("", 0))
        port = taken.getsockname()[1]
        assert udp_port_problem(port) == (f"UDP port {port} (the data link's telemetry port) is taken: another "
                                          "Paparazzi link runs (stop it, or its session)")
    assert udp_port_problem(port) is None   # closed: free again


def test_an_ivy_bus_with_another_agent_is_named_and_a_quiet_one_is_free():
    bus = f"127.255.255.255:{40000 + os.getpid() % 20000}"
    assert ivy_bus_problem(bus, listen_s=0.5) is None
    server = IvyServer("server", "server READY")
    server.start(bus)
    try:
        assert ivy_bus_problem(bus, listen_s=5.0) == f"the Ivy bus {bus} is in use by server (another session?)"
    finally:
        server.stop()
