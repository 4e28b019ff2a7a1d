"""The JSON report of a calibration: the log, the method, every axis's fit with its interval and Allan deviation,
the Paparazzi defines and the warnings."""
import json

from finken.imu.noise_fit import CONFIDENCE, FIT_PASSES

UNITS = {"gyro": ("rad/s", "rad/s/sqrt(Hz)", "rad/s", "rad/s^2/sqrt(Hz)"),
         "accel": ("m/s^2", "m/s^2/sqrt(Hz)", "m/s^2", "m/s^3/sqrt(Hz)")}
METHOD = ("overlapping Allan deviation (AllanTools oadev) at octave averaging times; adev^2 = N^2/tau + "
          "(2 ln 2/pi) B^2 + K^2 tau/3 fitted by weighted non-negative least squares on the Allan variances, weights "
          f"2 avar^2/edf with Greenhall's edf for the dominant noise ({FIT_PASSES} passes); intervals by a parametric "
          "bootstrap of simulated logs of the fitted noise")


def _term(term, unit):
    return {"value": term.value, "low": term.low, "high": term.high, "unit": unit, "resolved": term.resolved}


def report(cal):
    """The report of a finken.imu.calibration.Calibration as a dict (JSON-ready)."""
    log = cal.log
    axes = {}
    columns = {name: column for name, column, _ in log.axes()}
    for name, fit in cal.fits.items():
        unit, white, bias, walk = UNITS[name.split()[0]]
        curve = cal.curves[name]
        axes[name] = {
            "column": columns[name], "unit": unit, "mean": cal.means[name],
            "white": _term(fit.white, white), "bias_instability": _term(fit.bias_instability, bias),
            "rate_random_walk": _term(fit.rate_random_walk, walk),
            "allan": {"tau_s": curve.tau.tolist(), "adev": curve.adev.tolist(), "fit": fit.adev(curve.tau).tolist()},
        }
    return {
        "log": log.path, "rows": len(log.t), "rate_hz": log.rate_hz, "duration_s": float(log.t[-1] - log.t[0]),
        "tau_max_s": cal.tau_max_s, "method": METHOD,
        "bootstrap": {"reps": cal.reps, "seed": cal.seed, "confidence": CONFIDENCE},
        "axes": axes,
        "paparazzi": {"dt_s": cal.dt_s, "defines": {f"NPS_{n}": v for n, v, _ in cal.defines.rows},
                      "notes": cal.defines.notes},
        "warnings": list(log.warnings),
    }


def report_json(cal):
    return json.dumps(report(cal), indent=2) + "\n"
