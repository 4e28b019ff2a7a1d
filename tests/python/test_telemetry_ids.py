"""Our message ids and names against Paparazzi's: the telemetry messages of conf/telemetry/finken_messages.xml in
pprzlink's "telemetry" class, the ABI messages of conf/abi_finken.xml in Paparazzi's "airborne" ABI class.

Ids are uint8 per class. pprzlink's generator refuses a message whose id or name its class has already; Paparazzi's
ABI generator refuses a duplicate id and warns about one out of order, and tools/overlay.py appends ours at the end
of the class: our ABI ids must be above Paparazzi's highest.

Checked against (a) the lists of Paparazzi's messages in tests/data (each file says which commit it comes from) and
(b) when PAPARAZZI_HOME is set, that tree's own definitions, without the block tools/overlay.py may have added:
$PAPARAZZI_HOME/conf/messages.xml if it exists, else pprzlink's messages.xml; $PAPARAZZI_HOME/conf/abi.xml.
With the tree, our telemetry messages also go through pprzlink's generator (with its schema validation), and
sonar_array.c (periodic SONAR_ARRAY) and range_recorder_telemetry.c (event messages FINKEN_RANGE_READING and
FINKEN_WALL_DECISION) compile with telemetry on against the headers it generates.
"""
import os
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from airborne_build import REPO, airborne_flags, compile_or_fail, require_abi_header
from finken.paparazzi.overlay import ABI_SOURCE, PPRZLINK_MESSAGES, TELEMETRY_SOURCE, insert_messages, strip_block

DATA = REPO / "tests" / "data"


class Registry:
    """One class of messages we add to: our file, the stated list of Paparazzi's, the file of a tree."""

    def __init__(self, ours, class_name, stated, tree_files, ours_above):
        self.ours, self.class_name, self.stated, self.tree_files = ours, class_name, stated, tree_files
        self.ours_above = ours_above   # our ids must be above Paparazzi's highest (ABI: appended, in order)

    def tree_file(self, home):
        """The first of tree_files the tree has (the last one when it has none)."""
        return next((Path(home, f) for f in self.tree_files if Path(home, f).is_file()),
                    Path(home, self.tree_files[-1]))


TELEMETRY = Registry(TELEMETRY_SOURCE, "telemetry", "pprzlink_telemetry_messages.txt",
                     ("conf/messages.xml", PPRZLINK_MESSAGES), ours_above=False)
ABI = Registry(ABI_SOURCE, "airborne", "paparazzi_abi_messages.txt", ("conf/abi.xml",), ours_above=True)
REGISTRIES = pytest.mark.parametrize("registry", [TELEMETRY, ABI], ids=["telemetry", "abi"])


def messages_of_text(text, class_name):
    """[(name, id)] of one msg_class of a message file's text."""
    root = ET.fromstring(text)
    cls = next((c for c in root.findall("msg_class") if c.get("name") == class_name), None)
    assert cls is not None, f"no msg_class {class_name!r}"
    return [(m.get("name"), int(m.get("id"))) for m in cls.findall("message")]


def ours(registry):
    return messages_of_text((REPO / registry.ours).read_text(), registry.class_name)


def stated(registry):
    """[(name, id)] of tests/data/<registry.stated>: lines 'id name', '#' comments."""
    rows = [line.split() for line in (DATA / registry.stated).read_text().splitlines()
            if line.strip() and not line.startswith("#")]
    return [(name, int(mid)) for mid, name in rows]


def of_tree(registry, home):
    """[(name, id)] of the tree's definitions, without the block tools/overlay.py adds (our own messages)."""
    return messages_of_text(strip_block(registry.tree_file(home).read_text()), registry.class_name)


def problems(registry, theirs):
    """What keeps our messages from joining Paparazzi's class `theirs` ([(name, id)]); empty: nothing."""
    name_of = {mid: name for name, mid in theirs}
    id_of = dict(theirs)
    found = []
    for name, mid in ours(registry):
        if mid in name_of:
            found.append(f"{name} (id {mid}): id taken by {name_of[mid]}")
        if name in id_of:
            found.append(f"{name} (id {mid}): name taken (id {id_of[name]})")
        if registry.ours_above and mid <= max(name_of):
            found.append(f"{name} (id {mid}): not above Paparazzi's highest id {max(name_of)}")
    return found


def paparazzi_home():
    home = os.environ.get("PAPARAZZI_HOME")
    if not home:
        pytest.skip("PAPARAZZI_HOME is not set: no Paparazzi tree to check against")
    return Path(home)


@REGISTRIES
def test_our_ids_are_uint8_and_ours_alone(registry):
    messages = ours(registry)
    assert messages, f"{registry.ours}: no message in class {registry.class_name}"
    assert all(0 <= mid <= 255 for _, mid in messages), messages
    assert len({mid for _, mid in messages}) == len(messages), f"{registry.ours}: an id twice: {messages}"
    assert len({name for name, _ in messages}) == len(messages), f"{registry.ours}: a name twice: {messages}"


@REGISTRIES
def test_our_ids_and_names_are_free_in_the_stated_list(registry):
    assert problems(registry, stated(registry)) == []


def test_our_telemetry_messages_are_the_documented_ones():
    """The ids docs/sensors.md and the range_recorder descriptor give: 193, first asked for FINKEN_RANGE_READING, is
    pprzlink's AHRS_LKF, so the recorder's messages are 194 and 195."""
    assert sorted(ours(TELEMETRY), key=lambda m: m[1]) == [
        ("SONAR_ARRAY", 192), ("FINKEN_WALL_DECISION", 194), ("FINKEN_RANGE_READING", 195)]
    assert ("AHRS_LKF", 193) in stated(TELEMETRY)
    assert problems(TELEMETRY, [("AHRS_LKF", 193)]) == []
    assert problems(TELEMETRY, [("AHRS_LKF", 195)]) == ["FINKEN_RANGE_READING (id 195): id taken by AHRS_LKF"]


def test_the_recorders_message_fields_match_its_c_calls():
    """The fields, in order, with the C types range_recorder_telemetry.c passes (pprzlink sends them in this order)."""
    root = ET.fromstring((REPO / TELEMETRY_SOURCE).read_text())
    fields = {m.get("name"): [(f.get("name"), f.get("type")) for f in m.findall("field")] for m in root.iter("message")}
    assert fields["FINKEN_RANGE_READING"] == [("stamp", "uint32"), ("sensor", "uint8"), ("peer", "uint16"),
                                              ("measured", "float")]
    assert fields["FINKEN_WALL_DECISION"] == [("stamp", "uint32"), ("sonar", "uint8"), ("detector_class", "uint8"),
                                              ("confidence", "float"), ("measured", "float"),
                                              ("baseline_class", "uint8")]


def test_the_stated_lists_hold_what_collided():
    """The lists are Paparazzi's: SONAR_ARRAY's former id 240 is pprzlink's NPS_SPEED_POS, AGL an ABI message."""
    assert ("NPS_SPEED_POS", 240) in stated(TELEMETRY)
    assert ("AGL", 2) in stated(ABI) and ("OBSTACLE_DETECTION", 17) in stated(ABI)


@REGISTRIES
def test_our_ids_and_names_are_free_in_the_tree(registry):
    home = paparazzi_home()
    path = registry.tree_file(home)
    if not path.is_file():
        pytest.skip(f"{path} does not exist")
    assert problems(registry, of_tree(registry, home)) == [], f"against {path}"


def generated_telemetry(tmp_path):
    """Our telemetry messages added to the tree's definitions as tools/overlay.py adds them, validated by pprzlink's
    generator (its schema) and generated as C headers: the include folder (tmp_path/include)."""
    home = paparazzi_home()
    generator = home / "sw/ext/pprzlink/tools/generator/gen_messages.py"
    if not generator.is_file():
        pytest.skip(f"{generator} does not exist")
    base = TELEMETRY.tree_file(home)
    our_messages = [ET.tostring(m, encoding="unicode").strip()
                    for m in ET.fromstring((REPO / TELEMETRY_SOURCE).read_text()).iter("message")]
    merged = tmp_path / "messages.xml"
    merged.write_text(insert_messages(strip_block(base.read_text()), "telemetry", our_messages, base))

    def generator_run(*args):
        result = subprocess.run([sys.executable, generator, *args, merged, "telemetry"], capture_output=True,
                                text=True)
        assert result.returncode == 0, f"pprzlink's generator ({' '.join(args)}) failed:\n{result.stdout}{result.stderr}"
        return result.stdout

    # the generator goes on after a failed validation: validate alone first (against pprzlink's schema)
    assert "Validating msg_class telemetry" in generator_run("--only-validate")
    header = tmp_path / "include" / "pprzlink" / "messages.h"
    generator_run("--no-validate", "--protocol", "2.0", "--messages", "1.0", "--lang", "C", "-o", str(header))
    return header.parent.parent


def test_sonar_array_compiles_against_pprzlink_generated_telemetry(tmp_path, build_dir):
    """sonar_array.c compiled with telemetry on against the header generated (the rest of Paparazzi's telemetry
    interface is its telemetry_common.h; telemetry.h, which wants an aircraft's generated files, is a three-line
    stand-in here)."""
    home = paparazzi_home()
    require_abi_header(build_dir)
    include = generated_telemetry(tmp_path)
    assert "PPRZ_MSG_ID_SONAR_ARRAY" in (include / "pprzlink" / "telemetry" / "SONAR_ARRAY.h").read_text()

    stand_in = tmp_path / "stand_in" / "modules" / "datalink" / "telemetry.h"
    stand_in.parent.mkdir(parents=True)
    stand_in.write_text('#include "modules/datalink/telemetry_common.h"\n'
                        "extern struct periodic_telemetry pprz_telemetry;\n"
                        "#define DefaultPeriodic (&pprz_telemetry)\n")
    compile_or_fail("sonar_array.c with telemetry", [
        "gcc", "-fsyntax-only", "-std=gnu99", "-Wall", "-Wextra", "-Werror",
        "-DPERIODIC_TELEMETRY=1", "-DDOWNLINK=1", "-DAC_ID=1", f"-I{tmp_path / 'stand_in'}",
        *airborne_flags(build_dir), f"-I{include}", f"-I{home / 'sw/airborne'}",
        "sw/airborne/modules/sonar/sonar_array.c"])


def test_range_recorder_compiles_against_pprzlink_generated_telemetry(tmp_path, build_dir):
    """range_recorder_telemetry.c with a downlink (DOWNLINK=1) against the headers generated: the two event messages
    with their ids and the argument types of its calls, under Paparazzi's warning flags. downlink.h, which wants an
    aircraft's generated files, is a stand-in giving DefaultChannel and DefaultDevice the members Paparazzi's
    transports and devices have (trans_tx, device)."""
    include = generated_telemetry(tmp_path)
    for name, mid in (("FINKEN_RANGE_READING", 195), ("FINKEN_WALL_DECISION", 194)):
        assert f"#define PPRZ_MSG_ID_{name} {mid}" in (include / "pprzlink" / "telemetry" / f"{name}.h").read_text()

    stand_in = tmp_path / "stand_in" / "modules" / "datalink" / "downlink.h"
    stand_in.parent.mkdir(parents=True)
    stand_in.write_text('#include "pprzlink/messages.h"\n'
                        "struct finken_channel { struct transport_tx trans_tx; };\n"
                        "struct finken_device { struct link_device device; };\n"
                        "extern struct finken_channel finken_channel;\n"
                        "extern struct finken_device finken_device;\n"
                        "#define DefaultChannel finken_channel\n"
                        "#define DefaultDevice finken_device\n"
                        "#define AC_ID 1\n")
    obj = tmp_path / "range_recorder_telemetry.o"
    compile_or_fail("range_recorder_telemetry.c with a downlink", [
        "gcc", "-c", "-std=gnu99", "-Wall", "-Wextra", "-Werror", "-Wshadow", "-Wcast-qual", "-Wstrict-prototypes",
        "-Wmissing-prototypes", "-DDOWNLINK=1", f"-I{tmp_path / 'stand_in'}", f"-I{include}", "-Isw/airborne",
        "sw/airborne/modules/range_recorder/range_recorder_telemetry.c", "-o", obj])
    symbols = subprocess.run(["nm", obj], capture_output=True, text=True, check=True).stdout
    # the messages go out through pprzlink's transport interface (the generated inline functions call it)
    assert " T range_recorder_telemetry_reading" in symbols and " T range_recorder_telemetry_decision" in symbols
    assert "finken_channel" in symbols and "finken_device" in symbols
