"""The session "FINken swarm" (conf/userconf/finken/finken_control_panel.xml) read as the Paparazzi Center reads it
(tools/finken/paparazzi/session.py): each program's command from the tree's tools and the session's arguments, each
simulator on an Ivy bus of its own; an aircraft missing from the conf file, an unknown program or session refused with
file:line."""
import re
import shutil

import pytest

from finken.paparazzi.session import SIMULATOR, read_session, with_bus
from finken.xml_errors import XmlInputError

TOOLS = {"data_link.xml": '<program command="sw/ground_segment/tmtc/link" name="Data Link">'
                           '<arg constant="/dev/ttyUSB0" flag="-d"/></program>',
         "server.xml": '<program command="sw/ground_segment/tmtc/server" name="Server"/>',
         "pprzgcs.xml": '<program command="sw/tools/gcs_launch.py" name="PprzGCS"/>',
         "simulator.xml": '<program command="sw/simulator/pprzsim-launch" name="Simulator" icon="simulator.png">'
                          '<arg constant="@AIRCRAFT" flag="-a"/></program>'}


@pytest.fixture
def home(tmp_path, repo):
    """A tree with Paparazzi's four tools (as conf/tools/*.xml has them), our conf and our session."""
    (tmp_path / "conf/tools").mkdir(parents=True)
    for name, text in TOOLS.items():
        (tmp_path / "conf/tools" / name).write_text(text + "\n")
    (tmp_path / "conf/userconf/finken").mkdir(parents=True)
    for name in ("finken_conf.xml", "finken_control_panel.xml"):
        shutil.copy(repo / "conf/userconf/finken" / name, tmp_path / "conf/userconf/finken" / name)
    shutil.copy(repo / "conf/userconf/finken/finken_conf.xml", tmp_path / "conf/conf.xml")
    return tmp_path


def test_the_session_starts_four_simulators_on_their_own_buses_and_the_ground_on_its_own(home):
    programs = read_session(home)
    assert [p.name for p in programs] == ["Data Link", "Server", "PprzGCS"] + [SIMULATOR] * 4
    assert programs[0].command == [str(home / "sw/ground_segment/tmtc/link"), "-udp", "-udp_broadcast"]
    sims = [p for p in programs if p.name == SIMULATOR]
    assert [p.arg("-a") for p in sims] == ["FINKEN_1", "FINKEN_2", "FINKEN_3", "FINKEN_4"]
    assert all(p.arg("-t") == "nps" for p in sims)
    buses = [p.arg("-b") for p in sims]
    assert len(set(buses)) == 4 and "127.255.255.255:2010" not in buses   # 2010: the ground's (the default)
    assert all(p.arg("-b") is None for p in programs if p.name != SIMULATOR)
    assert with_bus(programs[1], "127.255.255.255:3000")[1:] == ["-b", "127.255.255.255:3000"]
    assert with_bus(sims[0], "x")[-1] == "x" and with_bus(sims[0], "x").count("-b") == 1


def test_an_aircraft_missing_from_the_conf_file_is_refused_with_file_and_line(home):
    panel = home / "conf/userconf/finken/finken_control_panel.xml"
    text = panel.read_text()
    panel.write_text(text.replace('constant="FINKEN_3"', 'constant="FINKEN_7"'))
    line = next(i for i, l in enumerate(panel.read_text().splitlines(), 1) if "FINKEN_7" in l) - 1
    with pytest.raises(XmlInputError, match=rf"finken_control_panel.xml:{line}: aircraft \"FINKEN_7\" of the "
                                            r"session is not in the conf file .*conf.xml \(it holds FINKEN_1, FINKEN_2"):
        read_session(home)


def test_an_unknown_program_or_session_is_refused(home):
    panel = home / "conf/userconf/finken/finken_control_panel.xml"
    with pytest.raises(XmlInputError, match=r'no session "Replay" \(sessions: "FINken swarm"\)'):
        read_session(home, name="Replay")
    panel.write_text(panel.read_text().replace('<program name="Server"/>', '<program name="Sever"/>'))
    with pytest.raises(XmlInputError, match=re.escape('program "Sever" is no tool of')):
        read_session(home)
