"""tools/sim_report.py on a tiny hand-written run: it writes its three outputs, and an output it cannot write
is one message naming the file with exit status 1 (no traceback)."""
import sim_report

WALLS = ["t,wall,segment,x0,y0,x1,y1,nx,ny,angle_deg,disp_flight_m,disp_bottom_m,target_deg,driven",
         "0,0,0,0,0,3,0,0,1,0,0,0,0,0", "0,1,0,3,0,3,4,-1,0,0,0,0,0,0",
         "0,2,0,3,4,0,4,0,-1,0,0,0,0,0", "0,3,0,0,4,0,0,1,0,0,0,0,0,0"]
POSES = ["t,vehicle,x,y,z,yaw", "0,1,1,1,0.6,0", "0,2,2,3,0.6,0", "1,1,1.2,1,0.6,0", "1,2,2,2.8,0.6,0"]
READINGS = ["t,vehicle,sensor,peer,true_range,measured", "0.5,1,sonar_front,,1.8,1.75", "0.5,1,ranging,2,2.2,2.25",
            "0.5,2,sonar_down,,0.6,0.61"]
DETECTIONS = ["t,vehicle,sensor,peer,true_range,measured,ctx_target_copter,detector_class,confidence,baseline_class",
              "0.5,1,sonar_front,,1.8,1.75,0,wall,0.9,wall", "0.5,2,sonar_front,,1.0,0.98,1,copter,0.8,wall"]


def _run_folder(folder, with_readings):
    folder.mkdir()
    files = {"poses.csv": POSES, "detections.csv": DETECTIONS}
    if with_readings:
        files.update({"walls.csv": WALLS, "readings.csv": READINGS})
    for name, lines in files.items():
        (folder / name).write_text("\n".join(lines) + "\n")


def test_writes_its_outputs_and_names_one_it_cannot_write(tmp_path, capsys):
    _run_folder(tmp_path / "on", with_readings=True)
    _run_folder(tmp_path / "on" / "detector_off", with_readings=False)
    argv = ["--on", str(tmp_path / "on"), "--off", str(tmp_path / "on" / "detector_off")]
    assert sim_report.main(argv) == 0
    for name in ("metrics.json", "trajectories.png", "arena.png"):
        assert (tmp_path / "on" / name).stat().st_size > 0
    (tmp_path / "on" / "arena.png").unlink()
    (tmp_path / "on" / "arena.png").mkdir()       # in the way: cannot be written
    capsys.readouterr()
    assert sim_report.main(argv) == 1
    err = capsys.readouterr().err
    assert err.strip() == f"error: {tmp_path / 'on' / 'arena.png'}: cannot write: Is a directory"


def test_sensor_errors_count_glitches_apart_from_the_error():
    """A sonar's glitches (negative, zero, infinite, absurd) are counted and leave its error statistics alone."""
    from types import SimpleNamespace

    import numpy as np

    from finken.sim_report.sensor_errors import format_table, sensor_error_stats
    true = np.array([1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0])
    measured = np.array([1.1, 0.9, 1.0, -3.0, 0.0, np.inf, 1e5, np.nan])
    stats = sensor_error_stats(SimpleNamespace(sensor=np.array(["sonar_front"] * 8), measured=measured,
                                               true_range=true))["sonar_front"]
    assert (stats["readings"], stats["no_reading"], stats["glitches"]) == (8, 1, 4)
    assert abs(stats["mean_error_m"]) < 1e-12 and np.isclose(stats["rmse_m"], np.sqrt(0.02 / 3))
    assert "glitches" in format_table({"sonar_front": stats}).splitlines()[0]
