"""What the ground segment saw (tools/finken/paparazzi/ground_check.py) read from a server log written as Paparazzi's
server writes it (the .log's protocol in upper case, the .data one message per line): an aircraft missing from the
server's view, or one that did not obey a command, fails the check, naming it."""
import math

from finken.paparazzi.ground_check import ground_view, position_errors

PROTOCOL = """<!-- logged with runtime paparazzi_version v7.0_unstable -->
<configuration time_of_day="1796649598.37" data_file="{name}.data">
  <protocol>
    <msg_class NAME="telemetry" ID="1">
      <message NAME="ROTORCRAFT_FP" ID="147">
{fp}
      </message>
      <message NAME="ROTORCRAFT_NAV_STATUS" ID="159">
        <field TYPE="uint16" NAME="block_time" UNIT="s"></field>
        <field TYPE="uint16" NAME="stage_time" UNIT="s"></field>
        <field TYPE="float" NAME="dist_home" UNIT="m"></field>
        <field TYPE="float" NAME="dist_wp" UNIT="m"></field>
        <field TYPE="uint8" NAME="cur_block"></field>
        <field TYPE="uint8" NAME="cur_stage"></field>
        <field TYPE="uint8" NAME="horizontal_mode"></field>
      </message>
      <message NAME="DL_VALUE" ID="31">
        <field TYPE="uint8" NAME="index"></field>
        <field TYPE="float" NAME="value"></field>
      </message>
      <message NAME="FINKEN_RANGE_READING" ID="195">
        <field UNIT="us" TYPE="uint32" NAME="stamp"></field>
        <field TYPE="uint8" NAME="sensor"></field>
        <field TYPE="uint16" NAME="peer"></field>
        <field UNIT="m" TYPE="float" NAME="measured"></field>
      </message>
      <message NAME="FINKEN_WALL_DECISION" ID="194">
        <field UNIT="us" TYPE="uint32" NAME="stamp"></field>
        <field TYPE="uint8" NAME="sonar"></field>
        <field TYPE="uint8" NAME="detector_class"></field>
        <field TYPE="float" NAME="confidence"></field>
        <field UNIT="m" TYPE="float" NAME="measured"></field>
        <field TYPE="uint8" NAME="baseline_class"></field>
      </message>
    </msg_class>
    <msg_class NAME="datalink" ID="2">
      <message NAME="SETTING" ID="4">
        <field TYPE="uint8" NAME="index"></field>
        <field TYPE="uint8" NAME="ac_id"></field>
        <field TYPE="float" NAME="value"></field>
      </message>
      <message NAME="BLOCK" ID="5">
        <field TYPE="uint8" NAME="block_id"></field>
        <field TYPE="uint8" NAME="ac_id"></field>
      </message>
    </msg_class>
  </protocol>
</configuration>
"""
FP_FIELDS = ("east", "north", "up", "veast", "vnorth", "vup", "phi", "theta", "psi", "carrot_east", "carrot_north",
             "carrot_up", "carrot_psi", "thrust", "flight_time")
LAND, SETTING_INDEX = 7, 11


def fp_field(name):
    if name in ("east", "north", "up", "carrot_east", "carrot_north", "carrot_up"):
        return f'        <field TYPE="int32" NAME="{name}" ALT_UNIT_COEF="0.0039063" ALT_UNIT="m"></field>'
    if name in ("phi", "theta", "psi", "carrot_psi"):
        return f'        <field TYPE="int32" NAME="{name}" ALT_UNIT_COEF="0.0139882" ALT_UNIT="deg"></field>'
    if name in ("veast", "vnorth", "vup"):
        return f'        <field TYPE="int32" NAME="{name}" ALT_UNIT_COEF="0.0000019" ALT_UNIT="m/s"></field>'
    return f'        <field TYPE="int32" NAME="{name}"></field>'


def aircraft_lines(ac, landed=True, confirmed=True, ours=True):
    """One aircraft's flight as the server logs it: flying in block 6 at 0.6 m (154/256), the uplink of a setting
    and a jump to block 7 (the server logs SETTING and BLOCK), the answers."""
    up = 0 if landed else 154
    lines = [f"10.000 {ac} ROTORCRAFT_FP 0 0 154 0 0 0 0 0 0 0 0 0 0 3000 10",
             f"10.100 {ac} ROTORCRAFT_NAV_STATUS 4 4 0. 0. 6 0 3",
             f"21.455 {ac} SETTING {SETTING_INDEX} {ac} 0.8",
             f"21.455 {ac} BLOCK {LAND} {ac}",
             f"21.458 {ac} DL_VALUE {SETTING_INDEX} {0.8 if confirmed else 0.5}",
             f"21.800 {ac} ROTORCRAFT_NAV_STATUS 0 0 0. 0. 8 0 3",
             f"24.000 {ac} ROTORCRAFT_FP 0 0 {up} 0 0 0 0 0 0 0 0 0 0 0 24"]
    if ours:
        lines += [f"10.200 {ac} FINKEN_RANGE_READING 1721474 0 65535 1.278905",
                  f"10.200 {ac} FINKEN_WALL_DECISION 1721474 0 1 0.999991 1.278905 2"]
    return lines


def server_log(tmp_path, lines, name="26_12_07__13_19_58"):
    fp = "\n".join(fp_field(f) for f in FP_FIELDS)
    (tmp_path / f"{name}.log").write_text(PROTOCOL.format(name=name, fp=fp))
    data = tmp_path / f"{name}.data"
    data.write_text("".join(line + "\n" for line in sorted(lines, key=lambda text: float(text.split()[0]))))
    return data


def view(tmp_path, lines):
    return ground_view(server_log(tmp_path, lines), [1, 2, 3, 4], LAND, SETTING_INDEX, 0.8)


def test_four_aircraft_seen_and_obeying_pass(tmp_path):
    v = view(tmp_path, [line for ac in (1, 2, 3, 4) for line in aircraft_lines(ac)])
    assert v.problems() == [] and v.missing() == {}
    assert v.counts["FINKEN_RANGE_READING"] == {1: 1, 2: 1, 3: 1, 4: 1}
    assert all(v.obeyed[ac] == {"setting sent", "setting confirmed", "jump sent", "block reached", "landed"}
               for ac in (1, 2, 3, 4))


def test_an_aircraft_missing_from_the_servers_view_fails_naming_it(tmp_path):
    v = view(tmp_path, [line for ac in (1, 2, 4) for line in aircraft_lines(ac)])
    assert v.missing() == {3: ["ROTORCRAFT_FP", "ROTORCRAFT_NAV_STATUS", "FINKEN_RANGE_READING",
                               "FINKEN_WALL_DECISION"]}
    assert any(p.startswith("aircraft 3 is missing from the server's view") for p in v.problems())


def test_an_aircraft_without_our_telemetry_or_not_obeying_fails_naming_it(tmp_path):
    lines = [line for ac in (1, 2) for line in aircraft_lines(ac)]
    lines += aircraft_lines(3, ours=False) + aircraft_lines(4, landed=False, confirmed=False)
    problems = view(tmp_path, lines).problems()
    assert problems == ["aircraft 3 is missing from the server's view: no FINKEN_RANGE_READING, FINKEN_WALL_DECISION",
                        "aircraft 4 did not obey: landed, setting confirmed missing"]


def test_server_positions_are_arena_positions(tmp_path):
    """ROTORCRAFT_FP is in the flight plan's frame, the arena's (finken_world.h): the server's positions are compared
    with poses.csv as they are. Two copters circle 60 s in the arena; the server logs on its wall clock, the simulator
    runs at time factor 2 with world time 5 s ahead; copter 2's estimate is 0.3 m east of its truth."""
    truth_rows, lines = ["t,vehicle,x,y,z,yaw,qx,qy,qz,qw"], []
    for k in range(1200):
        world_t = 0.1 * k
        for ac, shift_m in ((1, 0.0), (2, 0.3)):
            x, y = 1.5 + 0.8 * math.cos(0.2 * world_t + ac), 2.0 + 0.8 * math.sin(0.2 * world_t + ac)
            truth_rows.append(f"{world_t:.1f},{ac},{x:.4f},{y:.4f},0.6,0,0,0,0,1")
            if k % 2 == 0:   # 5 messages per wall second
                east, north = round((x + shift_m) * 256), round(y * 256)
                fields = [east, north, 154] + [0] * 12
                lines.append(f"{(world_t - 5.0) / 2 + 100:.3f} {ac} ROTORCRAFT_FP " + " ".join(map(str, fields)))
    poses = tmp_path / "poses.csv"
    poses.write_text("\n".join(truth_rows) + "\n")
    errors = position_errors(server_log(tmp_path, lines), poses, time_factor=2.0)
    assert errors[1][1] < 0.01                    # 1/256 m steps
    assert abs(errors[2][0] - 0.3) < 0.01
