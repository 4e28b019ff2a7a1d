"""The module generator: scheduler, sources and defines from an airframe; clear errors on bad input."""
import subprocess
import sys
import textwrap

import pytest

AIRFRAME = """<airframe name="t">
  <firmware name="rotorcraft">
    <target name="nps" board="pc"/>
    <define name="PERIODIC_FREQUENCY" value="100"/>
    {modules}
  </firmware>
  <section name="SIMULATOR" prefix="NPS_">
    <define name="FINKEN_ALTITUDE" value="0.8"/>
  </section>
</airframe>
"""

DESCRIPTOR = """<!DOCTYPE module SYSTEM "module.dtd">
<module name="{name}" dir="wander">
  <doc><description>test module</description>
    <define name="{upper}_GAIN" value="1.0" type="float"/>
  </doc>
  {dep}
  <header><file name="wander.h"/></header>
  <init fun="{name}_init()"/>
  <periodic fun="{name}_periodic()" freq="{freq}"/>
  <event fun="{name}_event()"/>
  <makefile target="nps|ap"><file name="wander.c"/><define name="{upper}_NPS"/></makefile>
  <makefile target="ap"><file name="does_not_exist.c"/></makefile>
</module>
"""


def write(tmp_path, modules='<module name="m1"><define name="M1_GAIN" value="2.5"/></module>', descriptors=None):
    mdir = tmp_path / "modules"
    mdir.mkdir()
    for name, text in (descriptors or {"m1": DESCRIPTOR.format(name="m1", upper="M1", freq=20, dep="")}).items():
        (mdir / f"{name}.xml").write_text(text)
    af = tmp_path / "af.xml"
    af.write_text(AIRFRAME.format(modules=modules))
    return af, mdir


def run(repo, af, mdir, out, *extra):
    return subprocess.run([sys.executable, str(repo / "tools/gen_modules.py"), "--airframe", str(af),
                           "--modules", str(mdir), "--out", str(out), *extra],
                          capture_output=True, text=True, env={"PYTHONPATH": str(repo / "tools")})


def test_generates_prescaled_scheduler_sources_and_defines(repo, tmp_path):
    af, mdir = write(tmp_path)
    out = tmp_path / "out"
    result = run(repo, af, mdir, out)
    assert result.returncode == 0, result.stderr
    modules_h = (out / "generated/modules.h").read_text()
    assert '#include "modules/wander/wander.h"' in modules_h
    assert "m1_init();" in modules_h and "m1_event();" in modules_h
    # 20 Hz in a 100 Hz main loop: every 5th step
    assert "if (step % 5u == 0u) { m1_periodic(); }" in modules_h
    mk = (out / "modules.mk").read_text()
    assert "HOST_SRCS := sw/airborne/modules/wander/wander.c" in mk
    assert "'-DPERIODIC_FREQUENCY=100'" in mk and "'-DM1_NPS'" in mk and "'-DM1_GAIN=2.5'" in mk
    assert "does_not_exist" not in mk          # the ap-only section is not built for nps
    assert "#define NPS_FINKEN_ALTITUDE 0.8" in (out / "generated/airframe.h").read_text()


def test_a_define_given_on_the_command_line_replaces_the_airframes(repo, tmp_path):
    """--define NAME=VALUE (make host HOST_DEFINES=, the sweeps): one definition of NAME, the new value; a section's
    define changes in airframe.h (a second -D of the same name with another value stops the compiler)."""
    af, mdir = write(tmp_path)
    out = tmp_path / "out"
    result = run(repo, af, mdir, out, "--define", "M1_GAIN=3.0", "--define", "NPS_FINKEN_ALTITUDE=0.4")
    assert result.returncode == 0, result.stderr
    mk = (out / "modules.mk").read_text()
    assert "'-DM1_GAIN=3.0'" in mk and "M1_GAIN=2.5" not in mk
    assert "NPS_FINKEN_ALTITUDE" not in mk
    airframe_h = (out / "generated/airframe.h").read_text()
    assert "#define NPS_FINKEN_ALTITUDE 0.4" in airframe_h and "0.8" not in airframe_h


@pytest.mark.parametrize("modules, descriptors, expected", [
    ('<module name="nope"/>', None, "af.xml:5: unknown module 'nope'"),
    ('<module name="m1"><define name="M1_GAIN" value="fast"/></module>', None,
     "af.xml:5: define M1_GAIN=\"fast\" of module m1: expected a float value"),
    ('<module name="m1"><define name="M1_GAINN" value="1"/></module>', None,
     "af.xml:5: module m1 has no define M1_GAINN (documented: M1_GAIN)"),
    ('<module name="m1"/>', {"m1": DESCRIPTOR.format(name="m1", upper="M1", freq=20, dep="").replace("<doc>", "<dok>").replace("</doc>", "</dok>")},
     "m1.xml:2: does not match"),
    ('<module name="m1"/>', {"m1": DESCRIPTOR.format(name="m1", upper="M1", freq=500, dep="")},
     "m1.xml:9: m1_periodic() at 500 Hz: expected a frequency in (0, 100] Hz"),
    ('<module name="m1"/>', {"m1": DESCRIPTOR.format(name="m1", upper="M1", freq=20, dep="<dep><depends>@radio</depends></dep>")},
     "af.xml:5: module m1 depends on '@radio', which no module of the airframe provides"),
    # without '@' Paparazzi reads a module name, and loads it: a functionality's name is not a module
    ('<module name="m1"/>', {"m1": DESCRIPTOR.format(name="m1", upper="M1", freq=20, dep="<dep><depends>radio</depends></dep>")},
     "af.xml:5: unknown module 'radio'"),
    ('<module name="m1"/>', {"m1": "<module name='m1'><doc><description>x</description></doc>"},
     "m1.xml:1: malformed XML"),
])
def test_bad_input_names_file_line_and_expectation(repo, tmp_path, modules, descriptors, expected):
    af, mdir = write(tmp_path, modules, descriptors)
    out = tmp_path / "out"
    (out / "generated").mkdir(parents=True)
    (out / "modules.mk").write_text("stale from an earlier run")
    result = run(repo, af, mdir, out)
    assert result.returncode == 1
    assert expected in result.stderr
    assert not (out / "modules.mk").exists()   # nothing left that looks like a valid build input


def test_unknown_target_is_rejected(repo, tmp_path):
    af, mdir = write(tmp_path)
    af.write_text(af.read_text().replace('<target name="nps" board="pc"/>', '<target name="npx" board="pc"/>'))
    result = run(repo, af, mdir, tmp_path / "out")
    assert result.returncode == 1
    assert "af.xml:3: unknown target 'npx', expected one of ap, nps, sim, hitl, test" in result.stderr


def test_every_shipped_descriptor_is_valid_and_generates(repo, tmp_path):
    """conf/modules/*.xml against module.dtd (ours, and Paparazzi's when PAPARAZZI_HOME is set)."""
    from finken.conf.module_descriptor import read_descriptor
    for path in sorted((repo / "conf/modules").glob("*.xml")):
        for target in ("nps", "ap"):
            read_descriptor(path, repo, target, 512.0, {})


def test_a_module_define_out_of_range_stops_the_build(repo, tmp_path):
    """min range above max range: the build fails naming the define (no silently wrong simulation)."""
    result = subprocess.run(["make", "--no-print-directory", "host", "AIRFRAME=conf/airframes/finken_nps.xml",
                             "HOST_VARIANT=_bad_range", "HOST_DEFINES=SONAR_ARRAY_MIN_RANGE=3.5"],
                            cwd=repo, capture_output=True, text=True)
    assert result.returncode != 0
    assert "SONAR_ARRAY_MIN_RANGE must be at least 0 and below SONAR_ARRAY_MAX_RANGE" in result.stdout + result.stderr


def test_an_unknown_sensor_model_file_is_refused_at_start(repo, tmp_path):
    subprocess.run(["make", "-s", "--no-print-directory", "host"], cwd=repo, check=True, stdout=subprocess.DEVNULL)
    result = subprocess.run([str(repo / "build/host/finken_nps/nps_host"), "--quiet", "--out", str(tmp_path),
                             "--sensor-model", "conf/sensor_models/nope.xml"], cwd=repo, capture_output=True, text=True)
    assert result.returncode == 1
    assert "conf/sensor_models/nope.xml" in result.stderr


def test_dependencies_resolve_as_paparazzi_resolves_them(repo, tmp_path):
    """'@f' is met by a module's <provides>f</provides>; a plain name is loaded as a module; '|' gives alternatives."""
    descriptors = {
        "m1": DESCRIPTOR.format(name="m1", upper="M1", freq=20, dep="<dep><depends>@sensor, m3 ,@a|@b</depends></dep>"),
        "m2": DESCRIPTOR.format(name="m2", upper="M2", freq=20, dep="<dep><provides>sensor,b</provides></dep>"),
        "m3": DESCRIPTOR.format(name="m3", upper="M3", freq=20, dep=""),
    }
    af, mdir = write(tmp_path, '<module name="m1"/><module name="m2"/>', descriptors)
    result = run(repo, af, mdir, tmp_path / "out")
    assert result.returncode == 0, result.stderr
    modules_h = (tmp_path / "out/generated/modules.h").read_text()
    assert "m3_init();" in modules_h      # loaded because m1 names it


@pytest.mark.parametrize("depends, expected", [
    ("@sensor @other", "depends on '@sensor @other'"),     # only commas separate entries, as in Paparazzi
    ("sensor", "unknown module 'sensor'"),                 # a functionality without '@' is a module name
    ("@a|@c", "depends on '@a|@c'"),
])
def test_dependencies_paparazzi_rejects_are_rejected(repo, tmp_path, depends, expected):
    descriptors = {
        "m1": DESCRIPTOR.format(name="m1", upper="M1", freq=20, dep=f"<dep><depends>{depends}</depends></dep>"),
        "m2": DESCRIPTOR.format(name="m2", upper="M2", freq=20, dep="<dep><provides>sensor,b</provides></dep>"),
    }
    af, mdir = write(tmp_path, '<module name="m1"/><module name="m2"/>', descriptors)
    result = run(repo, af, mdir, tmp_path / "out")
    assert result.returncode == 1
    assert expected in result.stderr
