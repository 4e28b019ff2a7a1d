"""Per-sensor summary of a simulated (or measured) range log: readings, glitches and error against ground truth."""
import numpy as np

from finken.discrepancy.glitches import absurd_limit, classify
from finken.rangelog import SENSOR_NAMES

#: Longest range each kind of sensor reports [m] (sonar: report section 3.2; ranging: section 4.1).
MAX_RANGE_M = {"sonar": 3.0, "ranging": 2.5}


def sensor_error_stats(log, max_range_m=MAX_RANGE_M):
    """{sensor: {readings, no_reading, glitches, mean_error_m, std_error_m, rmse_m, median_abs_error_m}} for each
    sensor.

    Error = measured - true_range [m], over the rows with a reading that is no glitch (finken.discrepancy.glitches:
    negative, zero, infinite, absurd; counted apart) and a true range within the sensor's range (so the value a
    sensor reports beyond its maximum does not count as an error).
    """
    stats = {}
    present = set(log.sensor.tolist())
    for sensor in [s for s in SENSOR_NAMES if s in present] + sorted(present - set(SENSOR_NAMES)):
        rows = log.sensor == sensor
        measured = log.measured[rows]
        error = measured - log.true_range[rows]
        has_reading = ~np.isnan(measured)
        kind = "ranging" if sensor == "ranging" else "sonar"
        glitch = classify(measured, absurd_limit(max_range_m[kind], log.true_range[rows])) > 0
        in_range = has_reading & ~glitch & (log.true_range[rows] <= max_range_m[kind])
        e = error[in_range]
        stats[sensor] = {
            "readings": int(rows.sum()),
            "no_reading": int((~has_reading).sum()),
            "glitches": int(glitch.sum()),
            "mean_error_m": float(e.mean()) if e.size else float("nan"),
            "std_error_m": float(e.std(ddof=1)) if e.size > 1 else float("nan"),
            "rmse_m": float(np.sqrt(np.mean(e ** 2))) if e.size else float("nan"),
            "median_abs_error_m": float(np.median(np.abs(e))) if e.size else float("nan"),
        }
    return stats


def format_table(stats):
    """The statistics as a fixed-width text table."""
    header = (f"{'sensor':<12} {'readings':>9} {'none':>6} {'glitches':>8} {'mean err':>9} {'std err':>8} "
              f"{'rmse':>7} {'med |e|':>8}")
    lines = [header, "-" * len(header)]
    for sensor, s in stats.items():
        lines.append(f"{sensor:<12} {s['readings']:>9d} {s['no_reading']:>6d} {s['glitches']:>8d} "
                     f"{s['mean_error_m']:>+9.3f} {s['std_error_m']:>8.3f} {s['rmse_m']:>7.3f} "
                     f"{s['median_abs_error_m']:>8.3f}")
    lines.append("errors in metres, measured - true, over readings whose true range is within the sensor's range; "
                 "glitches (negative, zero, infinite or absurd readings) counted apart")
    return "\n".join(lines)
