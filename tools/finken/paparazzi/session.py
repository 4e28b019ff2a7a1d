"""A Paparazzi Center session read from a control-panel file, to run without the Center
(tools/paparazzi_session.py) or to take the ground programs from (make paparazzi-sim GCS=1).

Each program's command is the one the Center runs (sw/supervision/python/session_widget.py, launch_program): the
tool's `command` from the tree's conf/tools/*.xml (or the control panel's own `programs` section), under
$PAPARAZZI_SRC unless it starts with `$`, followed by the session's arguments only. Refused with file:line: a session
or a program that is not there, and a Simulator whose aircraft (`-a`) the conf file does not hold.
"""
from dataclasses import dataclass
from pathlib import Path

from finken.xml_errors import XmlInputError, parse_xml

SESSION_FILE = "conf/userconf/finken/finken_control_panel.xml"
SESSION = "FINken swarm"
SIMULATOR = "Simulator"
GCS = "PprzGCS"


@dataclass
class Program:
    name: str
    command: list     # what to run, the tool's command first
    line: int         # of the session's <program>

    def arg(self, flag):
        """The value given to `flag` (None when absent)."""
        args = self.command[1:]
        return next((args[i + 1] for i, a in enumerate(args[:-1]) if a == flag), None)


def read_session(home, control_panel=SESSION_FILE, name=SESSION, conf="conf/conf.xml"):
    """[Program] of session `name` in the control panel (relative paths under `home`), checked against the tools
    and the aircraft of `conf` (None: not checked)."""
    home = Path(home)
    path = home / control_panel
    root = parse_xml(path)
    tools = _tools(home, root)
    sessions = root.xpath("section[@name='sessions']/session")
    found = [s for s in sessions if s.get("name") == name]
    if not found:
        raise XmlInputError(path, root.sourceline, f"no session \"{name}\" (sessions: "
                            + ", ".join(f'"{s.get("name")}"' for s in sessions) + ")")
    aircraft = None if conf is None else {a.get("name") for a in parse_xml(home / conf).iter("aircraft")}
    programs = []
    for element in found[0].iter("program"):
        tool = element.get("name")
        if tool not in tools:
            raise XmlInputError(path, element.sourceline, f"program \"{tool}\" is no tool of {home / 'conf/tools'}")
        command = tools[tool] + [text for arg in element.iter("arg")
                                 for text in (arg.get("flag"), arg.get("constant")) if text is not None]
        program = Program(tool, command, element.sourceline)
        if tool == SIMULATOR and aircraft is not None and program.arg("-a") not in aircraft:
            raise XmlInputError(path, element.sourceline, f"aircraft \"{program.arg('-a')}\" of the session is not "
                                f"in the conf file {home / conf} (it holds {', '.join(sorted(aircraft)) or 'none'})")
        programs.append(program)
    return programs


def _tools(home, control_panel):
    """{tool name: [command]}: conf/tools/*.xml, overridden by the control panel's `programs` section."""
    elements = [parse_xml(p) for p in sorted((home / "conf/tools").glob("*.xml"))]
    elements += control_panel.xpath("section[@name='programs']/program")
    tools = {}
    for e in elements:
        if e.tag == "program" and e.get("name") and e.get("command"):
            command = e.get("command")
            tools[e.get("name")] = [command[1:] if command.startswith("$") else str(home / command)]
    return tools


def with_bus(program, bus):
    """The program's command on the Ivy bus `bus`: its own -b replaced, or added; for the GCS after `--`
    (Paparazzi's gcs_launch.py hands what follows `--` to the GCS, and takes no -b itself)."""
    command = list(program.command)
    if "-b" in command[1:]:
        command[command.index("-b", 1) + 1] = bus
    elif program.name == GCS:
        command += ([] if "--" in command else ["--"]) + ["-b", bus]
    else:
        command += ["-b", bus]
    return command


def describe(programs):
    return [f"{p.name}: {' '.join(map(str, p.command))}" for p in programs]

