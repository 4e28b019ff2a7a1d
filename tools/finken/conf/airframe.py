"""Read a Paparazzi airframe file: the modules of one firmware target, their defines, the sections.

Only what the NPS-style host needs is read; the rest of the airframe (commands, servos, ...) is ignored.
"""
from dataclasses import dataclass, field

from finken.xml_errors import XmlInputError, parse_xml, require_attr

#: Targets a Paparazzi airframe may name; the host builds `nps`.
KNOWN_TARGETS = ("ap", "nps", "sim", "hitl", "test")


@dataclass
class Define:
    name: str
    value: str | None
    line: int


@dataclass
class ModuleUse:
    """A <module> element of the airframe: which descriptor, with which defines and configures."""
    name: str
    type: str | None
    line: int
    defines: list[Define] = field(default_factory=list)
    configures: dict[str, str] = field(default_factory=dict)

    @property
    def descriptor_name(self):
        return f"{self.name}_{self.type}" if self.type else self.name


@dataclass
class Airframe:
    path: str
    name: str
    firmware: str
    target: str
    modules: list[ModuleUse]
    defines: list[Define]            # firmware- and target-level defines: compile definitions for every file
    configures: dict[str, str]       # firmware- and target-level configures (make variables)
    section_defines: list[Define]    # <section prefix=...> defines, with the prefix applied: airframe.h


def _defines(path, element):
    return [Define(require_attr(path, d, "name"), d.get("value"), d.sourceline) for d in element.findall("define")]


def _configures(path, element):
    return {require_attr(path, c, "name"): (c.get("value") or c.get("default") or "") for c in element.findall("configure")}


def _module_uses(path, element):
    uses = []
    for m in element.findall("module"):
        use = ModuleUse(require_attr(path, m, "name"), m.get("type"), m.sourceline,
                        _defines(path, m), _configures(path, m))
        uses.append(use)
    return uses


def read_airframe(path, target="nps"):
    """Parse `path` and select `target`; errors name the file and line."""
    root = parse_xml(path)
    if root.tag != "airframe":
        raise XmlInputError(path, root.sourceline, f"root element is <{root.tag}>, expected <airframe>")
    name = require_attr(path, root, "name")
    chosen = None
    for firmware in root.findall("firmware"):
        for t in firmware.findall("target"):
            tname = require_attr(path, t, "name")
            if tname not in KNOWN_TARGETS:
                raise XmlInputError(path, t.sourceline,
                                    f"unknown target '{tname}', expected one of {', '.join(KNOWN_TARGETS)}")
            if tname == target and chosen is None:
                chosen = (firmware, t)
    if chosen is None:
        raise XmlInputError(path, root.sourceline, f"no <firmware> has a <target name=\"{target}\">")
    firmware, target_el = chosen
    modules = _module_uses(path, firmware) + _module_uses(path, target_el)
    seen = {}
    for use in modules:
        if use.descriptor_name in seen:
            raise XmlInputError(path, use.line, f"module '{use.descriptor_name}' is listed twice (first at line {seen[use.descriptor_name]})")
        seen[use.descriptor_name] = use.line
    sections = []
    for section in root.findall("section"):
        prefix = section.get("prefix", "")
        sections += [Define(prefix + d.name, d.value, d.line) for d in _defines(path, section)]
    return Airframe(str(path), name, require_attr(path, firmware, "name"), target, modules,
                    _defines(path, firmware) + _defines(path, target_el),
                    {**_configures(path, firmware), **_configures(path, target_el)}, sections)


def airframe_arena(path):
    """The airframe's NPS_ARENA_FILE (the host's arena when make sim names none)."""
    for define in read_airframe(path, "nps").section_defines:
        if define.name == "NPS_ARENA_FILE" and define.value:
            return define.value.strip('"')
    raise ValueError(f"{path}: the airframe sets no NPS_ARENA_FILE")
