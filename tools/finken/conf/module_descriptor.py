"""Read Paparazzi module descriptors (conf/modules/*.xml, grammar of module.dtd) for one build target."""
import os
import re
from dataclasses import dataclass, field
from pathlib import Path

from finken.conf.module_deps import Requirement, parse_depends, parse_provides
from finken.xml_errors import XmlInputError, parse_xml, require_attr

#: Value checks for the `type` attribute of a documented <define>.
_TYPE_PATTERNS = {
    "int": r"[+-]?\d+",
    "uint": r"\+?\d+",
    "float": r"[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?[fF]?",
    "bool": r"TRUE|FALSE|true|false|1|0",
    "string": r"\".*\"|[^\s]+",
}


@dataclass
class Periodic:
    fun: str
    freq_hz: float
    delay: int
    autorun: bool
    line: int


@dataclass
class ModuleDescriptor:
    path: str
    name: str
    dir: str
    provides: list[str]
    depends: list[Requirement]            # <depends> entries, as Paparazzi parses them (finken.conf.module_deps)
    documented_defines: dict[str, dict]   # name -> attributes of the <doc> define (value, type, description...)
    headers: list[str]                    # include paths relative to sw/airborne
    inits: list[str]
    periodics: list[Periodic]
    events: list[str]
    sources: list[str] = field(default_factory=list)        # files to compile, relative to the repository
    defines: list[tuple[str, str | None]] = field(default_factory=list)
    include_dirs: list[str] = field(default_factory=list)


def dtd_path(repo_root):
    """Paparazzi's own module.dtd when PAPARAZZI_HOME is set, else our copy of its grammar."""
    home = os.environ.get("PAPARAZZI_HOME")
    if home and Path(home, "conf/modules/module.dtd").is_file():
        return str(Path(home, "conf/modules/module.dtd"))
    return str(Path(repo_root, "conf/modules/module.dtd"))


def target_matches(spec, target):
    """Paparazzi's makefile target attribute: absent = every target, else alternatives separated by '|'."""
    return spec is None or target in [t.strip() for t in spec.split("|")]


def _call(path, element):
    fun = require_attr(path, element, "fun")
    if element.get("cond"):
        raise XmlInputError(path, element.sourceline, "the host generator does not evaluate 'cond' attributes")
    return fun if fun.endswith(")") else fun + "()"


def _substitute(path, element, text, variables):
    def lookup(match):
        if match.group(1) not in variables:
            raise XmlInputError(path, element.sourceline, f"$({match.group(1)}) is not a configure of this module or airframe")
        return variables[match.group(1)]
    return re.sub(r"\$\((\w+)\)", lookup, text)


def read_descriptor(path, repo_root, target, main_freq_hz, configures):
    """Parse and validate one descriptor; keep what `target` builds. `configures` are the airframe's values."""
    root = parse_xml(path, dtd_path(repo_root))
    name = require_attr(path, root, "name")
    mdir = root.get("dir", name)
    doc = root.find("doc")
    documented = {d.get("name"): dict(d.attrib) for d in doc.iter("define")}
    dep = root.find("dep")
    provides = parse_provides(dep.findtext("provides")) if dep is not None else []
    depends = parse_depends(dep.findtext("depends")) if dep is not None else []
    header = root.find("header")
    headers = []
    for f in (header.findall("file") if header is not None else []):
        fdir = f.get("dir", f"modules/{mdir}")
        headers.append(f"{fdir}/{require_attr(path, f, 'name')}")
    periodics = []
    for p in root.findall("periodic"):
        fun = _call(path, p)
        if p.get("freq"):
            freq = _number(path, p, "freq")
        elif p.get("period"):
            freq = 1.0 / _number(path, p, "period")
        else:
            freq = main_freq_hz
        if not 0 < freq <= main_freq_hz:
            raise XmlInputError(path, p.sourceline,
                                f"{fun} at {freq:g} Hz: expected a frequency in (0, {main_freq_hz:g}] Hz (PERIODIC_FREQUENCY)")
        periodics.append(Periodic(fun, freq, int(_number(path, p, "delay") if p.get("delay") else 0),
                                  p.get("autorun", "TRUE") != "FALSE", p.sourceline))
    module = ModuleDescriptor(str(path), name, mdir, provides, depends, documented, headers,
                              [_call(path, i) for i in root.findall("init")], periodics,
                              [_call(path, e) for e in root.findall("event")])
    variables = {"SRC_ARCH": "arch/sim" if target in ("nps", "sim") else "arch/linux", "TARGET": target}
    for mk in root.findall("makefile"):
        if not target_matches(mk.get("target"), target):
            continue
        if mk.get("cond"):
            raise XmlInputError(path, mk.sourceline, "the host generator does not evaluate 'cond' attributes")
        for c in mk.findall("configure"):
            cname = require_attr(path, c, "name")
            variables[cname] = configures.get(cname, c.get("value") or c.get("default") or "")
        for el in mk:
            if el.tag in ("file", "file_arch"):
                # Paparazzi: <file dir> is relative to sw/airborne, <file_arch dir> to the arch folder
                fdir = _substitute(path, el, el.get("dir", f"modules/{mdir}"), variables)
                if el.tag == "file_arch":
                    fdir = f"{variables['SRC_ARCH']}/{fdir}"
                name = require_attr(path, el, "name")
                source = f"sw/airborne/{fdir}/{name}"
                if not Path(repo_root, source).is_file() and target in ("nps", "sim"):
                    source = f"sw/simulator/{fdir}/{name}"    # NPS's VPATH (targets/nps_common.xml)
                if not Path(repo_root, source).is_file():
                    raise XmlInputError(path, el.sourceline, f"file sw/airborne/{fdir}/{name} does not exist")
                if source.endswith(".c"):
                    module.sources.append(source)
            elif el.tag == "define":
                value = el.get("value")
                module.defines.append((require_attr(path, el, "name"),
                                       None if value is None else _substitute(path, el, value, variables)))
            elif el.tag == "include":
                module.include_dirs.append(_substitute(path, el, require_attr(path, el, "name"), variables))
    return module


def check_define_value(module, define, airframe_path):
    """An airframe <define> for `module` must be documented in its <doc>, with a value of the documented type."""
    doc = module.documented_defines.get(define.name)
    if doc is None:
        known = ", ".join(sorted(module.documented_defines)) or "none"
        raise XmlInputError(airframe_path, define.line,
                            f"module {module.name} has no define {define.name} (documented: {known})")
    dtype = doc.get("type")
    if dtype in _TYPE_PATTERNS and define.value is not None and not re.fullmatch(_TYPE_PATTERNS[dtype], define.value):
        raise XmlInputError(airframe_path, define.line,
                            f"define {define.name}=\"{define.value}\" of module {module.name}: expected a {dtype} value")


def _number(path, element, attr):
    text = element.get(attr)
    try:
        return float(text)
    except (TypeError, ValueError):
        raise XmlInputError(path, element.sourceline, f"<{element.tag}> {attr}=\"{text}\" is not a number")
