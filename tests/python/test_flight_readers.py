"""Readers of a lab's flight (finken.flight: records, mocap, server_log, motive, csv_table) on small hand-made files.

Every expected value is worked out by hand in the test (or its comment), never by the code under test:
- stamps: 2^32 = 4294967296 us; a stamp of 704 us after 4294967000 us is 4294967296 + 704 us = 4294.968 s;
- ROTORCRAFT_FP: east 256 x 0.0039063 m = 1.0000128 m; psi 0 = heading north = yaw +90 deg from east;
- Motive y-up: arena (x, y, z) = (x_m, -z_m, y_m); (100, 50, -200) cm is (1.0, 2.0, 0.5) m; a turn of +90 deg about
  Motive's y (up) is a turn of +90 deg about the arena's z: (0, 0, sin 45, cos 45);
- slerp halfway through a 90 deg yaw: 45 deg, (0, 0, sin 22.5, cos 22.5).
Tolerances: 1e-12 for values computed from exact decimal inputs in float64, 1e-6 where the input is printed with
six decimals (Motive's 0.707107).
"""
import math
import re

import numpy as np
import pytest

from finken.flight.errors import FlightInputError
from finken.flight.mocap import Transform, parse_bodies, parse_transform, read_mocap
from finken.flight.records import read_decisions, read_records

EXACT = 1e-12
S45 = math.sqrt(0.5)


def write(path, text):
    path.write_text(text)
    return path


# ------------------------------------------------------------------ records: CSV

RECORDS_CSV = """t,vehicle,sensor,peer,measured
0.10,1,sonar_front,,1.25
0.10,1,ranging,2,2.5
0.20,1,sonar_front,,-1
0.20,1,sonar_down,,inf
0.30,1,sonar_front,,
"""


def test_records_csv_without_true_range(tmp_path):
    records = read_records(write(tmp_path / "rec.csv", RECORDS_CSV))
    assert records.format == "csv"
    assert records.t.tolist() == [0.1, 0.1, 0.2, 0.2, 0.3]
    assert records.vehicle.dtype == np.int64 and records.vehicle.tolist() == [1] * 5
    assert list(records.sensor) == ["sonar_front", "ranging", "sonar_front", "sonar_down", "sonar_front"]
    assert records.peer.tolist() == [-1, 2, -1, -1, -1]
    # glitches are data: kept as they are; empty = no reading
    assert records.measured[:4].tolist() == [1.25, 2.5, -1.0, math.inf] and math.isnan(records.measured[4])
    assert records.line.tolist() == [2, 3, 4, 5, 6]
    assert records.decisions is None


def test_records_csv_with_true_range_ignores_it(tmp_path):
    text = "t,vehicle,sensor,peer,true_range,measured\n0.5,3,sonar_left,,9.0,0.75\n"
    records = read_records(write(tmp_path / "rec.csv", text))
    assert records.measured.tolist() == [0.75] and records.vehicle.tolist() == [3]
    assert not hasattr(records, "true_range")


def test_records_csv_unknown_sensor_names_file_line_and_sensor(tmp_path):
    path = write(tmp_path / "rec.csv", RECORDS_CSV.replace("0.20,1,sonar_down", "0.20,1,sonar_top"))
    with pytest.raises(FlightInputError) as err:
        read_records(path)
    assert str(err.value).startswith(f"{path}:5:") and "'sonar_top'" in str(err.value)
    assert err.value.line == 5


def test_decisions_csv(tmp_path):
    path = write(tmp_path / "dec.csv", "t,vehicle,sensor,measured,detector_class,confidence,baseline_class\n"
                                       "1.5,2,sonar_right,0.8,wall,0.9,copter\n1.6,2,sonar_right,1.2,2,0.6,none\n")
    records = read_records(write(tmp_path / "rec.csv", RECORDS_CSV), decisions=path)
    d = records.decisions
    assert d.t.tolist() == [1.5, 1.6] and d.vehicle.tolist() == [2, 2]
    assert list(d.sensor) == ["sonar_right"] * 2
    assert list(d.detector_class) == ["wall", "copter"] and list(d.baseline_class) == ["copter", "none"]
    assert d.confidence.tolist() == [0.9, 0.6] and d.measured.tolist() == [0.8, 1.2] and d.line.tolist() == [2, 3]
    bad = write(tmp_path / "bad.csv", "t,vehicle,sensor,measured,detector_class,confidence,baseline_class\n"
                                      "1.5,2,sonar_right,0.8,door,0.9,copter\n")
    with pytest.raises(FlightInputError, match=rf"^{bad}:2: column 'detector_class': 'door'"):
        read_decisions(bad)


# ------------------------------------------------------------------ Paparazzi's server log

FIELDS_RANGE = """      <message name="FINKEN_RANGE_READING" id="195">
        <field name="stamp" type="uint32" unit="us"/>
        <field name="sensor" type="uint8"/>
        <field name="peer" type="uint16"/>
        <field name="measured" type="float" unit="m"/>
      </message>"""

FIELDS_DECISION = """      <message name="FINKEN_WALL_DECISION" id="194">
        <field name="stamp" type="uint32" unit="us"/>
        <field name="sonar" type="uint8"/>
        <field name="detector_class" type="uint8"/>
        <field name="confidence" type="float"/>
        <field name="measured" type="float" unit="m"/>
        <field name="baseline_class" type="uint8"/>
      </message>"""


def fields_fp(coef="0.0039063"):
    m = f'type="int32" alt_unit="m" alt_unit_coef="{coef}"'
    ms = 'type="int32" alt_unit="m/s" alt_unit_coef="0.0000019"'
    deg = 'type="int32" alt_unit="deg" alt_unit_coef="0.0139882"'
    names = [("east", m), ("north", m), ("up", m), ("veast", ms), ("vnorth", ms), ("vup", ms), ("phi", deg),
             ("theta", deg), ("psi", deg), ("carrot_east", m), ("carrot_north", m), ("carrot_up", m),
             ("carrot_psi", deg), ("thrust", 'type="int32"'), ("flight_time", 'type="uint16" unit="s"')]
    body = "\n".join(f'        <field name="{n}" {a}/>' for n, a in names)
    return f'      <message name="ROTORCRAFT_FP" id="147">\n{body}\n      </message>'


def server_log(folder, data_lines, telemetry=None, name="24_01_15__10_00_00"):
    """A .log/.data pair as sw/ground_segment/tmtc/server.ml writes it: two comments, then <configuration> with the
    expanded conf and pprzlink's <protocol>; the .data one "%.3f %s %s %s" line per message."""
    telemetry = telemetry if telemetry is not None else "\n".join([fields_fp(), FIELDS_RANGE, FIELDS_DECISION])
    log = folder / f"{name}.log"
    log.write_text(f"""<!-- logged with runtime paparazzi_version v6.3_stable -->
<!-- logged with build paparazzi_version v6.3_stable -->
<configuration time_of_day="1705312800." data_file="{name}.data">
  <conf>
    <aircraft name="finken1" ac_id="1" airframe="airframes/finken.xml" radio="radios/dummy.xml"
      telemetry="telemetry/finken.xml" flight_plan="flight_plans/finken.xml" settings="" color="red"/>
  </conf>
  <protocol>
    <msg_class name="telemetry" id="1">
      <message name="ALIVE" id="2">
        <field name="md5sum" type="uint8[]"/>
      </message>
{telemetry}
    </msg_class>
    <msg_class name="datalink" id="2">
      <message name="EXTERNAL_POSE" id="54" link="forwarded">
        <field name="ac_id" type="uint8"/>
        <field name="timestamp" type="uint32" unit="ms"/>
        <field name="enu_x" type="float" unit="m"/>
        <field name="enu_y" type="float" unit="m"/>
        <field name="enu_z" type="float" unit="m"/>
        <field name="enu_xd" type="float" unit="m/s"/>
        <field name="enu_yd" type="float" unit="m/s"/>
        <field name="enu_zd" type="float" unit="m/s"/>
        <field name="body_qi" type="float"/>
        <field name="body_qx" type="float"/>
        <field name="body_qy" type="float"/>
        <field name="body_qz" type="float"/>
      </message>
    </msg_class>
  </protocol>
</configuration>
""")
    data = folder / f"{name}.data"
    data.write_text("".join(line + "\n" for line in data_lines))
    return log, data


DATA = [
    "12.345 1 ALIVE 10,20,30,40",                                   # 1
    "12.400 1 FINKEN_RANGE_READING 4294966296 0 65535 1.25",        # 2: 2^32 - 1000 us
    "12.450 1 FINKEN_RANGE_READING 4294967000 5 2 2.",              # 3: OCaml's string_of_float 2.0 = "2."
    "12.480 ground INTRUDER 7 intruder 1 2 3 4 5",                  # 4: another kind of line, skipped
    "12.500 1 FINKEN_RANGE_READING 704 0 65535 nan",                # 5: wrapped: 2^32 + 704 us
    "12.550 2 FINKEN_RANGE_READING 1000000 4 65535 -3.5",           # 6: aircraft 2, its own clock; a glitch
    "12.600 1 FINKEN_WALL_DECISION 1704 0 1 0.93 1.3 3",            # 7: wrapped too: 2^32 + 1704 us
    "12.600 1 ROTORCRAFT_FP 256 512 128 0 0 0 0 0 0 0 0 0 0 3000 12",   # 8
    "13.600 1 ROTORCRAFT_FP 512 512 128 0 0 0 0 2145 0 0 0 0 0 3000 13",  # 9
]


@pytest.mark.parametrize("which", ["log", "data"])
def test_records_of_server_log_from_either_file(tmp_path, which):
    log, data = server_log(tmp_path, DATA)
    records = read_records(log if which == "log" else data)
    assert records.format == "paparazzi" and records.path == str(data)
    assert records.line.tolist() == [2, 3, 5, 6]
    assert records.vehicle.tolist() == [1, 1, 1, 2]
    # stamps unwrapped per aircraft: 2^32 - 1000, 2^32 - 296, 2^32 + 704 us; aircraft 2 alone: 1e6 us
    assert records.t.tolist() == pytest.approx([4294.966296, 4294.967, 4294.968, 1.0], abs=EXACT)
    assert list(records.sensor) == ["sonar_front", "ranging", "sonar_front", "sonar_down"]
    assert records.peer.tolist() == [-1, 2, -1, -1]
    assert records.measured[[0, 1, 3]].tolist() == [1.25, 2.0, -3.5] and math.isnan(records.measured[2])
    assert records.t_log.tolist() == [12.4, 12.45, 12.5, 12.55]
    d = records.decisions
    assert d.t.tolist() == pytest.approx([4294.969], abs=EXACT) and d.line.tolist() == [7]
    assert list(d.sensor) == ["sonar_front"] and list(d.detector_class) == ["wall"]
    assert list(d.baseline_class) == ["none"] and d.confidence.tolist() == [0.93] and d.measured.tolist() == [1.3]
    assert str(log) in records.definitions


def test_server_log_field_order_and_scale_come_from_the_log(tmp_path):
    permuted = FIELDS_RANGE.replace(
        '<field name="sensor" type="uint8"/>\n        <field name="peer" type="uint16"/>\n'
        '        <field name="measured" type="float" unit="m"/>',
        '<field name="measured" type="float" unit="m"/>\n        <field name="peer" type="uint16"/>\n'
        '        <field name="sensor" type="uint8"/>')
    assert permuted != FIELDS_RANGE
    log, data = server_log(tmp_path, ["1.000 4 FINKEN_RANGE_READING 5000000 0.5 3 5",
                                      "1.000 4 ROTORCRAFT_FP 256 0 100 0 0 0 0 0 0 0 0 0 0 0 1"],
                           telemetry="\n".join([fields_fp(coef="0.01"), permuted]))
    records = read_records(data)
    assert list(records.sensor) == ["ranging"] and records.peer.tolist() == [3]
    assert records.measured.tolist() == [0.5] and records.t.tolist() == [5.0]
    poses = read_mocap(log)
    assert poses.pos[4][0].tolist() == pytest.approx([2.56, 0.0, 1.0], abs=EXACT)   # 256 x 0.01 m, 100 x 0.01 m


def test_server_log_with_its_protocol_in_upper_case_as_the_server_writes_it(tmp_path):
    """Paparazzi's server writes the .log's protocol with upper-case attribute names (`<message NAME="ROTORCRAFT_FP"
    ID="147">`, `<field TYPE="int32" NAME="east" ALT_UNIT_COEF="0.0039063" ALT_UNIT="m">`, seen in a real log of
    our swarm): the field order and scale still come from the .log."""
    permuted = FIELDS_RANGE.replace(
        '<field name="sensor" type="uint8"/>\n        <field name="peer" type="uint16"/>\n'
        '        <field name="measured" type="float" unit="m"/>',
        '<field name="measured" type="float" unit="m"/>\n        <field name="peer" type="uint16"/>\n'
        '        <field name="sensor" type="uint8"/>')
    log, data = server_log(tmp_path, ["1.000 4 FINKEN_RANGE_READING 5000000 0.5 3 5",
                                      "1.000 4 ROTORCRAFT_FP 256 0 100 0 0 0 0 0 0 0 0 0 0 0 1"],
                           telemetry="\n".join([fields_fp(coef="0.01"), permuted]))
    head, protocol = log.read_text().split("<protocol>")
    upper = re.sub(r' (name|id|type|unit|alt_unit|alt_unit_coef|link)="', lambda m: f' {m.group(1).upper()}="', protocol)
    log.write_text(head + "<protocol>" + upper)
    assert 'NAME="ROTORCRAFT_FP"' in log.read_text()
    records = read_records(data)
    assert str(log) in records.definitions
    assert list(records.sensor) == ["ranging"] and records.peer.tolist() == [3] and records.measured.tolist() == [0.5]
    assert read_mocap(log).pos[4][0].tolist() == pytest.approx([2.56, 0.0, 1.0], abs=EXACT)


def test_server_log_unknown_sensor_code(tmp_path):
    _, data = server_log(tmp_path, DATA[:2] + ["12.420 1 FINKEN_RANGE_READING 4294966300 7 65535 1.0"])
    with pytest.raises(FlightInputError, match=rf"^{data}:3: FINKEN_RANGE_READING: unknown sensor code 7"):
        read_records(data)


def test_server_log_stream_going_back_in_time(tmp_path):
    _, data = server_log(tmp_path, ["1.000 1 FINKEN_RANGE_READING 9000000 0 65535 1.0",
                                    "1.100 1 FINKEN_RANGE_READING 8000000 0 65535 1.0"])
    with pytest.raises(FlightInputError, match=rf"^{data}:2: t = 8\.000000 s goes back .* restart"):
        read_records(data)


def test_rotorcraft_fp_poses(tmp_path):
    log, data = server_log(tmp_path, DATA)
    poses = read_mocap(data)
    assert poses.format == "paparazzi:ROTORCRAFT_FP" and poses.vehicles == [1]
    assert poses.t[1].tolist() == [12.6, 13.6] and poses.lines[1].tolist() == [8, 9]
    assert poses.pos[1][0].tolist() == pytest.approx([256 * 0.0039063, 512 * 0.0039063, 128 * 0.0039063],
                                                     abs=EXACT)
    # psi 0: nose north, i.e. yaw +90 deg about the arena's z
    assert poses.quat[1][0] == pytest.approx([0.0, 0.0, S45, S45], abs=EXACT)
    # second pose: still north, nose up by theta = 2145 x 0.0139882 deg: forward = (0, cos theta, sin theta)
    theta = math.radians(2145 * 0.0139882)
    x, y, z, w = poses.quat[1][1]
    forward = [1 - 2 * (y * y + z * z), 2 * (x * y + w * z), 2 * (x * z - w * y)]   # rotation matrix column 1
    assert forward == pytest.approx([0.0, math.cos(theta), math.sin(theta)], abs=1e-12)
    assert any("estimate" in note for note in poses.notes)


def test_external_pose_preferred_and_its_body_frame(tmp_path):
    # identity body quaternion: Paparazzi (gps_datalink.c) reads it as nose north
    log, _ = server_log(tmp_path, DATA + ["14.000 1 EXTERNAL_POSE 3 14000 1.5 2.5 0.75 0. 0. 0. 1. 0. 0. 0.",
                                          "14.010 1 EXTERNAL_POSE 3 14010 1.5 2.5 0.75 0. 0. 0. 1. 0. 0. 0."])
    poses = read_mocap(log)
    assert poses.format == "paparazzi:EXTERNAL_POSE" and poses.vehicles == [3]   # the message's ac_id
    assert poses.pos[3][0].tolist() == [1.5, 2.5, 0.75]
    assert poses.quat[3][0] == pytest.approx([0.0, 0.0, S45, S45], abs=EXACT)


# ------------------------------------------------------------------ Motive

MOTIVE_META = ("Format Version,1.23,Take Name,Take 2024-01-15 10.00.00 AM,Capture Frame Rate,100.000000,"
               "Export Frame Rate,100.000000,Capture Start Time,2024-01-15 10.00.00.000 AM,Total Frames in Take,4,"
               "Total Exported Frames,4,Rotation Type,{rotation},Length Units,Centimeters,Coordinate Space,Global")
RB = "Rigid Body"
MOTIVE_HEADER = [
    "",
    ",Type," + ",".join([RB] * 8 + ["Rigid Body Marker"] * 3 + [RB] * 7 + ["Marker"] * 3),
    ",Name," + ",".join(["finken3"] * 8 + ["finken3:Marker1"] * 3 + ['"Rigid Body 7"'] * 7 + ["Unlabeled 1000"] * 3),
    ",ID," + ",".join(["1"] * 11 + ["2"] * 7 + ["3"] * 3),
    ",," + ",".join(["Rotation"] * 4 + ["Position"] * 3 + ["Mean Marker Error"] + ["Position"] * 3
                    + ["Rotation"] * 4 + ["Position"] * 3 + ["Position"] * 3),
    "Frame,Time (Seconds)," + ",".join(list("XYZW") + list("XYZ") + [""] + list("XYZ") + list("XYZW") + list("XYZ")
                                       + list("XYZ")),
]
#  finken3: +90 deg about Motive's y at (100, 50, -200) cm, still; Rigid Body 7 at the origin, lost in frame 2
MOTIVE_ROWS = [
    "0,0.000000,0,0.707107,0,0.707107,100,50,-200,0.0001,101,50,-200,0,0,0,1,0,0,0,5,5,5",
    "1,0.010000,0,0.707107,0,0.707107,100,50,-200,0.0001,101,50,-200,0,0,0,1,0,0,0,5,5,5",
    "2,0.020000,0,0.707107,0,0.707107,100,50,-200,0.0001,101,50,-200,,,,,,,,5,5,5",
    "3,0.030000,0,0.707107,0,0.707107,100,50,-200,0.0001,101,50,-200,0,0,0,1,0,0,0,5,5,5",
]


def motive(tmp_path, header=None, rotation="Quaternion"):
    lines = [MOTIVE_META.format(rotation=rotation)] + (MOTIVE_HEADER if header is None else header) + MOTIVE_ROWS
    return write(tmp_path / "take.csv", "\r\n".join(lines) + "\r\n")


def test_motive_y_up_centimetres(tmp_path):
    poses = read_mocap(motive(tmp_path))
    assert poses.format == "motive" and poses.up == "y" and poses.unit == "cm"
    assert poses.vehicles == [3, 7] and poses.body == {3: "finken3", 7: "Rigid Body 7"}
    assert poses.t[3].tolist() == [0.0, 0.01, 0.02, 0.03] and poses.lines[3].tolist() == [8, 9, 10, 11]
    assert poses.pos[3][0] == pytest.approx([1.0, 2.0, 0.5], abs=EXACT)
    assert poses.quat[3][0] == pytest.approx([0.0, 0.0, S45, S45], abs=1e-6)
    # Rigid Body 7: frame 2 (line 10) lost; between frames 1 and 3 nothing is made up
    assert poses.t[7].tolist() == [0.0, 0.01, 0.03]
    assert [(k.vehicle, k.line, k.t_first, k.t_last, k.samples) for k in poses.lost] == [(7, 10, 0.02, 0.02, 1)]
    _, _, valid = poses.at(7, [0.005, 0.015, 0.02, 0.025, 0.03])
    assert valid.tolist() == [True, False, False, False, True]
    assert poses.at(3, [0.02])[2].tolist() == [True]


def test_motive_up_z_override(tmp_path):
    poses = read_mocap(motive(tmp_path), up="z")
    assert poses.pos[3][0] == pytest.approx([1.0, 0.5, -2.0], abs=EXACT)
    assert poses.quat[3][0] == pytest.approx([0.0, S45, 0.0, S45], abs=1e-6)


def test_motive_malformed_header(tmp_path):
    no_names = [row for row in MOTIVE_HEADER if not row.startswith(",Name,")]
    path = motive(tmp_path, header=no_names)
    with pytest.raises(FlightInputError, match=rf"^{path}:6: malformed Motive header: no ',Name,' row"):
        read_mocap(path)


def test_motive_euler_refused(tmp_path):
    path = motive(tmp_path, rotation="XYZ")
    with pytest.raises(FlightInputError, match=rf"^{path}:1: Rotation Type 'XYZ': only quaternions"):
        read_mocap(path)


# ------------------------------------------------------------------ plain CSV and poses.csv

def test_poses_csv_yaw_interpolation_and_slerp(tmp_path):
    path = write(tmp_path / "poses.csv", "t,vehicle,x,y,z,yaw\n0.0,1,0.0,0.0,0.5,0.0\n"
                                         "1.0,1,1.0,2.0,0.5,1.5707963267948966\n")
    poses = read_mocap(path)
    assert poses.format == "poses" and poses.vehicles == [1]
    pos, quat, valid = poses.at(1, [0.5, 0.25])
    assert valid.tolist() == [True, True]
    assert pos[0] == pytest.approx([0.5, 1.0, 0.5], abs=EXACT)
    assert quat[0] == pytest.approx([0.0, 0.0, math.sin(math.radians(22.5)), math.cos(math.radians(22.5))],
                                    abs=EXACT)
    # a quarter of the way: 22.5 deg by slerp (a normalised lerp would give 2 atan(0.1768 / 0.9268) = 21.6 deg)
    assert 2 * math.degrees(math.atan2(quat[1][2], quat[1][3])) == pytest.approx(22.5, abs=1e-9)


def test_gap_makes_valid_false(tmp_path):
    rows = "".join(f"{t},2,{t},0,1,0\n" for t in (0.0, 0.01, 0.02, 0.5, 0.51, 0.52))
    poses = read_mocap(write(tmp_path / "poses.csv", "t,vehicle,x,y,z,yaw\n" + rows))
    assert poses.max_gap_s[2] == 0.1   # max(0.1 s, 3 x the median period 0.01 s)
    pos, _, valid = poses.at(2, [-0.1, 0.015, 0.25, 0.5, 0.515, 0.6])
    assert valid.tolist() == [False, True, False, True, True, False]
    assert pos[1] == pytest.approx([0.015, 0.0, 1.0], abs=EXACT) and np.isnan(pos[2]).all()
    assert read_mocap(tmp_path / "poses.csv", max_gap_s=1.0).at(2, [0.25])[2].tolist() == [True]
    assert poses.at(9, [0.0])[2].tolist() == [False]   # a vehicle without poses


PLAIN = "t,body,x,y,z,qx,qy,qz,qw\n"


def test_plain_csv_jump_named_and_left_out(tmp_path):
    rows = ["0.00,finken4,0.000,0,1,0,0,0,1", "0.01,finken4,0.005,0,1,0,0,0,1", "0.02,finken4,0.010,0,1,0,0,0,1",
            "0.03,finken4,1.015,0,1,0,0,0,1", "0.04,finken4,0.020,0,1,0,0,0,1", "0.04,finken4,0.020,0,1,0,0,0,1"]
    poses = read_mocap(write(tmp_path / "m.csv", PLAIN + "\n".join(rows) + "\n"))
    assert poses.format == "csv" and poses.vehicles == [4]
    assert poses.t[4].tolist() == [0.0, 0.01, 0.02, 0.04]
    [jump] = poses.jumps
    # from the last good sample (x 0.010 at 0.02 s): 1.005 m in 0.01 s
    assert (jump.vehicle, jump.body, jump.line, jump.t) == (4, "finken4", 5, 0.03)
    assert jump.distance == pytest.approx(1.005, abs=1e-12) and jump.speed == pytest.approx(100.5, abs=1e-9)
    assert [(d.vehicle, d.line) for d in poses.duplicates] == [(4, 7)]


def test_plain_csv_transform_and_bodies(tmp_path):
    path = write(tmp_path / "m.csv", PLAIN + "0.0,wand,1,0,0,0,0,0,2\n0.0,copterA,0,0,0,0,0,0,1\n")
    poses = read_mocap(path, bodies="copterA=5,wand=-", transform="yaw=90,x=1")
    assert poses.vehicles == [5]
    poses = read_mocap(path, bodies={"wand": 6, "copterA": 5}, transform=parse_transform("yaw=90,x=1"))
    assert poses.pos[6][0] == pytest.approx([1.0, 1.0, 0.0], abs=EXACT)   # (1, 0, 0) turned 90 deg, + (1, 0, 0)
    assert poses.quat[6][0] == pytest.approx([0.0, 0.0, S45, S45], abs=EXACT)   # (0, 0, 0, 2) normalised, turned


def test_plain_csv_up_y(tmp_path):
    path = write(tmp_path / "m.csv", PLAIN + "0.0,finken1,1,2,3,0,0,0,1\n")
    poses = read_mocap(path, transform="up=y")
    assert poses.pos[1][0] == pytest.approx([1.0, -3.0, 2.0], abs=EXACT)


def test_body_without_vehicle(tmp_path):
    path = write(tmp_path / "m.csv", PLAIN + "0.0,finken1,0,0,0,0,0,0,1\n0.0,wand,0,0,0,0,0,0,1\n")
    with pytest.raises(FlightInputError, match=rf"^{path}:3: body 'wand' has no vehicle"):
        read_mocap(path)


def test_time_backwards(tmp_path):
    path = write(tmp_path / "m.csv", PLAIN + "0.2,finken1,0,0,0,0,0,0,1\n0.3,finken2,0,0,0,0,0,0,1\n"
                                             "0.1,finken1,0,0,0,0,0,0,1\n")
    with pytest.raises(FlightInputError, match=rf"^{path}:4: t = 0\.1 s goes back in time from t = 0\.2 s on line 2"):
        read_mocap(path)


def test_zero_quaternion_is_lost(tmp_path):
    rows = "".join(f"{t},finken1,0,0,1,0,0,0,{w}\n" for t, w in ((0.0, 1), (0.01, 0), (0.02, 1)))
    poses = read_mocap(write(tmp_path / "m.csv", PLAIN + rows))
    assert poses.t[1].tolist() == [0.0, 0.02] and [k.line for k in poses.lost] == [3]
    assert poses.at(1, [0.005])[2].tolist() == [False]


def test_option_texts():
    assert parse_transform("yaw=90, x=1.5,y=2.0,z=0") == Transform(90.0, (1.5, 2.0, 0.0), None)
    assert parse_bodies("finken1=1,finken2=2,wand=-") == {"finken1": 1, "finken2": 2, "wand": None}
    with pytest.raises(ValueError, match=r"transform 'yaw=90,roll=3': unknown key 'roll' \(known: yaw, x, y, z, up\)"):
        parse_transform("yaw=90,roll=3")
    with pytest.raises(ValueError, match="bodies 'finken1=x'"):
        parse_bodies("finken1=x")


def test_a_log_without_our_definitions_reads_them_from_the_telemetry_file(repo, tmp_path):
    """A .data without its .log: our recorder's messages are read with the definitions of
    conf/telemetry/finken_messages.xml (their one source), field by field in its order."""
    from lxml import etree
    from finken.flight.server_log import OUR_MESSAGES, _builtin_definitions

    assert OUR_MESSAGES == repo / "conf" / "telemetry" / "finken_messages.xml"
    ours = etree.parse(str(OUR_MESSAGES)).getroot()
    for name in ("FINKEN_RANGE_READING", "FINKEN_WALL_DECISION"):
        [message] = [m for m in ours.iter("message") if m.get("name") == name]
        fields = _builtin_definitions()[("telemetry", name)]
        assert [(f.name, f.type, f.unit) for f in fields] == [
            (f.get("name"), f.get("type"), f.get("unit")) for f in message.iter("field")]
        assert all(f.path == str(OUR_MESSAGES) for f in fields)
    data = tmp_path / "flight.data"
    data.write_text("1.000 3 FINKEN_RANGE_READING 2500000 5 2 1.5\n")
    records = read_records(data)
    assert list(records.sensor) == ["ranging"] and records.peer.tolist() == [2] and records.t.tolist() == [2.5]
    assert "FINKEN_RANGE_READING" in records.definitions