"""An airframe's modules as Paparazzi loads them for one target: descriptors, dependencies, defines.

Shared by the host's generator (tools/gen_modules.py) and the sweeps (finken.sweep.spec), which check a swept
define against the same descriptors.
"""
from pathlib import Path

from finken.conf.airframe import Define, ModuleUse
from finken.conf.module_descriptor import check_define_value, read_descriptor
from finken.xml_errors import XmlInputError

REPO_ROOT = Path(__file__).resolve().parents[3]
#: Paparazzi rotorcraft's default main-loop frequency [Hz].
DEFAULT_PERIODIC_FREQUENCY = 512.0


def main_frequency(airframe):
    for d in airframe.defines:
        if d.name == "PERIODIC_FREQUENCY":
            try:
                return float(d.value)
            except (TypeError, ValueError):
                raise XmlInputError(airframe.path, d.line, f"PERIODIC_FREQUENCY=\"{d.value}\" is not a number")
    return float(airframe.configures.get("PERIODIC_FREQUENCY", DEFAULT_PERIODIC_FREQUENCY))


def load_modules(airframe, modules_dir, main_freq):
    """The airframe's modules, then the modules their <depends> name (Paparazzi loads those as dependencies);
    every requirement checked as Paparazzi's aircraft.ml does: a module name or '@functionality' must be
    present."""
    modules = []

    def load(use, name, line_of_error):
        path = Path(modules_dir, name + ".xml")
        if not path.is_file():
            raise XmlInputError(airframe.path, line_of_error, f"unknown module '{name}': no {path}")
        module = read_descriptor(path, REPO_ROOT, airframe.target, main_freq,
                                 {**airframe.configures, **use.configures})
        modules.append((use, module))
        return module

    for use in airframe.modules:
        module = load(use, use.descriptor_name, use.line)
        for define in use.defines:
            check_define_value(module, define, airframe.path)
    for use, module in modules:    # grows while dependencies load
        for requirement in module.depends:
            name = requirement.module_to_load()
            if name and name not in {m.name for _, m in modules}:
                load(ModuleUse(name, None, use.line), name, use.line)
    present = {m.name for _, m in modules} | {p for _, m in modules for p in m.provides}
    for use, module in modules:
        for requirement in module.depends:
            if not requirement.satisfied_by(present):
                raise XmlInputError(airframe.path, use.line,
                                    f"module {module.name} depends on '{requirement.text}', which no module of "
                                    "the airframe provides (a name with '@' is a functionality of <provides>, "
                                    "without it a module)")
    return modules


def override_defines(airframe, texts):
    """Apply NAME=VALUE texts to the airframe in place. A section's define of that name (its prefix included, e.g.
    NPS_FINKEN_ALTITUDE) takes the value in airframe.h; any other replaces the airframe's defines of that name and
    becomes a compile definition (the compiler refuses a name defined twice with two values)."""
    for text in texts:
        name, _, value = text.partition("=")
        sections = [d for d in airframe.section_defines if d.name == name]
        for define in sections:
            define.value = value or None
        if sections:
            continue
        airframe.defines = [d for d in airframe.defines if d.name != name] + [Define(name, value or None, 0)]
        for use in airframe.modules:
            use.defines = [d for d in use.defines if d.name != name]
