"""tools/overlay.py on a small stand-in of a Paparazzi tree: adds only new files, names any that exist, extends the
two registries between markers, and `remove` gives the tree back byte for byte."""
import subprocess
import sys

import pytest

from finken.paparazzi.overlay import BEGIN, PPRZLINK_MESSAGES, insert_messages, overlay_files

ABI = """<?xml version="1.0"?>
<protocol>
  <msg_class name="airborne">
    <message name="BARO_ABS" id="0">
      <field name="stamp" type="uint32_t"/>
    </message>
  </msg_class>
</protocol>
"""
MESSAGES = """<?xml version="1.0"?>
<protocol>
  <msg_class name="telemetry" id="1">
    <message name="ALIVE" id="2">
      <field name="md5sum" type="uint8[]"/>
    </message>
  </msg_class>
</protocol>
"""


@pytest.fixture
def tree(tmp_path):
    (tmp_path / "conf/modules").mkdir(parents=True)
    (tmp_path / "conf/abi.xml").write_text(ABI)
    (tmp_path / PPRZLINK_MESSAGES).parent.mkdir(parents=True)
    (tmp_path / PPRZLINK_MESSAGES).write_text(MESSAGES)
    (tmp_path / "conf/modules/sonar_adc.xml").write_text("<module name='sonar_adc'/>")
    return tmp_path


def snapshot(root):
    return {p.relative_to(root).as_posix(): p.read_bytes() for p in root.rglob("*") if p.is_file()}


def overlay(repo, *args):
    return subprocess.run([sys.executable, str(repo / "tools/overlay.py"), *map(str, args)], capture_output=True,
                          text=True, env={"PYTHONPATH": str(repo / "tools")})


def test_install_adds_files_and_messages_and_remove_restores_the_tree(repo, tree):
    before = snapshot(tree)
    result = overlay(repo, "install", tree)
    assert result.returncode == 0, result.stderr
    for f in overlay_files(repo):
        assert (tree / f).read_bytes() == (repo / f).read_bytes()
    assert "conf/modules/module.dtd" not in overlay_files(repo)        # Paparazzi's own grammar stays
    abi = (tree / "conf/abi.xml").read_text()
    assert BEGIN in abi and 'name="WALL_DETECTION"' in abi and 'name="BARO_ABS"' in abi
    assert 'name="SONAR_ARRAY"' in (tree / "conf/messages.xml").read_text()
    assert (tree / PPRZLINK_MESSAGES).read_text() == MESSAGES          # pprzlink's file is not touched

    assert overlay(repo, "install", tree).returncode == 1              # installed already
    result = overlay(repo, "remove", tree)
    assert result.returncode == 0, result.stderr
    assert snapshot(tree) == before


def test_an_existing_file_stops_the_install_before_anything_is_written(repo, tree):
    (tree / "sw/airborne/modules/sonar").mkdir(parents=True)
    (tree / "sw/airborne/modules/sonar/sonar_array.c").write_text("the user's own file")
    before = snapshot(tree)
    result = overlay(repo, "install", tree)
    assert result.returncode == 1
    assert "sw/airborne/modules/sonar/sonar_array.c" in result.stderr
    assert snapshot(tree) == before


def test_remove_leaves_a_file_changed_since_install(repo, tree):
    assert overlay(repo, "install", tree).returncode == 0
    changed = tree / "conf/arena/swarmlab.xml"
    changed.write_text("edited by the user")
    result = overlay(repo, "remove", tree)
    assert result.returncode == 0
    assert "conf/arena/swarmlab.xml: changed since install" in result.stderr
    assert changed.read_text() == "edited by the user"


def test_a_message_id_taken_in_the_tree_is_refused():
    taken = ABI.replace('name="BARO_ABS" id="0"', 'name="BARO_ABS" id="201"')
    with pytest.raises(RuntimeError, match=r"WALL_DETECTION \(id 201\) collides with BARO_ABS"):
        insert_messages(taken, "airborne", ['<message name="WALL_DETECTION" id="201"/>'], "abi.xml")
