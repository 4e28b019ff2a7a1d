"""Scenarios of `make validate` beside the random hidden-effect cases: what a lab meets on its first real log.
Each runs the workflow over several seeds and checks one property; the name named in each seed
and its stability are reported, so that a name that changes with the seed shows.

- uwb_range: a UWB-like log (uwb_like.py: 0.4-12.8 m, LOS/NLOS, RSSI, recordings) against the 2.5 m model,
  held out by recording: the range is fitted, `ranging: nlos_bias | ctx_nlos` is named in every seed, stable
  (where named alone), and the held-out gap falls to at most a third of the input model's.
- uwb_columns: the same log written as a lab writes it (its own column names, millimetres, no vehicle/sensor/
  peer columns), read with --columns/--unit/--fill: the same name.
- nlos_exponential: an exponential excess path on ctx_blocked ranging rows: nlos_bias, not a mixture.
- latency_only: sensor latency alone: exactly one effect.
- flag_zero: a bias on the sonar rows whose first hit is a wall (ctx_target_copter == 0): named with that
  condition.
- cut: a bias where the copter is fast (ctx_speed >= 0.6): named under a cut of ctx_speed near 0.6.
- two_columns: a bias on sonar echoes from copters while fast (ctx_target_copter and ctx_speed >= 0.4): named
  with both columns, the cut near 0.4.
- bad_input: a reading of 1e300 is a glitch, read and counted; a negative true range is refused with its line; a
  log whose `measured` is empty says the sensor never reported; a 2-row log says it has too few rows.
Then the scenarios of real logs as they come (validate_real_logs.py).
"""
import numpy as np

from finken import models
from finken.discrepancy import glitches, hidden, synthetic
from finken.discrepancy.uwb_like import uwb_log
from finken.discrepancy.workflow import calibrate
from finken.rangelog import RangeLog, RangeLogError, read_range_log, write_range_log

SEEDS = (1, 2, 3)
#: The issue's target: held-out gap after at most this share of the input model's.
UWB_GAP_SHARE = 1 / 3


def named(result):
    return [e.fit.candidate.label for e in result.effects]


def stability_text(result):
    return "; ".join(e.stability.text() for e in result.effects if e.stability) or "-"


def runs_over_seeds(make_log, base, **kwargs):
    """(seed, result) for each of SEEDS."""
    return [(s, calibrate(make_log(s), base, seed=s, **kwargs)) for s in SEEDS]


def report(name, runs, ok, detail=""):
    lines = [f"{'ok ' if ok else 'BAD'} {name}: {detail}".rstrip()]
    lines += [f"      seed {s}: named {named(r) or 'nothing'}; gap {r.gap_before:.4g} -> {r.gap_after:.4g} m; "
              f"stability: {stability_text(r)}" for s, r in runs]
    return ok, "\n".join(lines)


def uwb_range(base, out):
    target = "ranging: nlos_bias | ctx_nlos"
    runs = runs_over_seeds(lambda s: read_uwb(out, s), base)
    ok = all(target in named(r) and _stable(r.effects[named(r).index(target)])
             and r.gap_after <= UWB_GAP_SHARE * r.gap_before and r.ranges["ranging"].max_out >= 12.8
             for _, r in runs)
    return report("uwb_range", runs, ok, f"{target} named and stable in every seed, gap after <= "
                   f"{UWB_GAP_SHARE:.2f} x before, range fitted beyond 12.8 m")


def _stable(effect):
    """Stable over resamples where that was measured (an effect named alone; two named together are fitted and
    tested together)."""
    return effect.stability is None or effect.stability.stable


def read_uwb(out, seed, lab_columns=False):
    """The UWB-like log of a seed written to `out` and read back held out by recording (as a lab's file)."""
    log = uwb_log(seed=seed, restart_time=True)
    path = out / f"uwb_{seed}{'_lab' if lab_columns else ''}.csv"
    if not lab_columns:
        write_range_log(path, log)
        return read_range_log(path, group="recording")
    rows = ["time_s,range_mm,real_range_mm,NLOS,RSSI,recording"]
    rows += [f"{t!r},{1000 * m!r},{1000 * tr!r},{n:g},{r!r},{rec}" for t, m, tr, n, r, rec in
             zip(log.t.tolist(), log.measured.tolist(), log.true_range.tolist(), log.ctx["ctx_nlos"].tolist(),
                 log.ctx["ctx_rssi"].tolist(), log.extra["recording"].tolist())]
    path.write_text("\n".join(rows) + "\n")
    return read_range_log(path, columns={"t": "time_s", "measured": "range_mm", "true_range": "real_range_mm",
                                         "ctx_nlos": "NLOS", "ctx_rssi": "RSSI"},
                          unit="mm", fill={"sensor": "ranging", "vehicle": "1", "peer": "2"}, group="recording")


def uwb_columns(base, out):
    target = "ranging: nlos_bias | ctx_nlos"
    runs = runs_over_seeds(lambda s: read_uwb(out, s, lab_columns=True), base)
    ok = all(target in named(r) for _, r in runs)
    return report("uwb_columns", runs, ok, f"{target} named from the lab's own columns in mm")


def hidden_log(truth, base, kind, effect, seed):
    return hidden.simulate_measured(truth, hidden.hidden_model(base, [hidden.HiddenEffect(kind, effect)]), seed)


def _one_named(name, base, truth, kind, effect, expect):
    runs = runs_over_seeds(lambda s: hidden_log(truth, base, kind, effect, 100 + s), base)
    ok = all(named(r) == [expect] for _, r in runs)
    return report(name, runs, ok, f"exactly [{expect}] in every seed")


def scenarios(out):
    """(all passed, text) of every scenario, those of real logs as they come (validate_real_logs.py) last."""
    from finken.discrepancy import validate_real_logs
    base = models.SensorModel.load(models.GAUSSIAN_ONLY_PATH)
    truth = synthetic.ground_truth(4, 120.0, seed=5)
    results = [
        uwb_range(base, out),
        uwb_columns(base, out),
        _one_named("nlos_exponential", base, truth, "ranging",
                   models.Effect("nlos_bias", {"mean": 0.15}, "ctx_blocked"), "ranging: nlos_bias | ctx_blocked"),
        _one_named("latency_only", base, truth, "sonar", models.Effect("latency", {"tau": 0.2}), "sonar: latency"),
        _one_named("flag_zero", base, truth, "sonar", models.Effect("bias", {"b": 0.1}, "ctx_target_copter == 0"),
                   "sonar: bias | ctx_target_copter == 0"),
        cut(base, truth),
        two_columns(base, truth),
        bad_input(base, truth, out),
        *validate_real_logs.scenarios(base, truth),
    ]
    return all(ok for ok, _ in results), "\n".join(text for _, text in results)


def _cut_named(name, runs, label_head, cut, tolerance):
    """Exactly one effect named in every seed, `label_head` followed by a cut within `tolerance` of `cut`."""
    def near(label):
        return label.startswith(label_head) and abs(float(label.rsplit(" ", 1)[1]) - cut) <= tolerance
    ok = all(len(r.effects) == 1 and near(named(r)[0]) for _, r in runs)
    return report(name, runs, ok, f"{label_head}c named, c within {tolerance} of {cut}")


def cut(base, truth):
    effect = models.Effect("bias", {"b": 0.12}, "ctx_speed >= 0.6")
    runs = runs_over_seeds(lambda s: hidden_log(truth, base, "ranging", effect, 200 + s), base)
    return _cut_named("cut", runs, "ranging: bias | ctx_speed >= ", 0.6, 0.1)


def two_columns(base, truth):
    effect = models.Effect("bias", {"b": 0.15}, "ctx_target_copter and ctx_speed >= 0.4")
    runs = runs_over_seeds(lambda s: hidden_log(truth, base, "sonar", effect, 300 + s), base)
    return _cut_named("two_columns", runs, "sonar: bias | ctx_target_copter and ctx_speed >= ", 0.4, 0.1)


def bad_input(base, truth, out):
    """A reading of 1e300 m is a glitch (read, counted), a negative true range is refused with its line, a
    silent sensor and a two-row log are said."""
    small = truth.select(np.arange(2000))
    rows = np.arange(len(small)) == 7
    for name, true_range, measured in (("huge_reading", small.true_range, np.where(rows, 1e300, small.true_range)),
                                       ("negative_truth", np.where(rows, -1.0, small.true_range), small.true_range)):
        write_range_log(out / f"{name}.csv", RangeLog(small.path, small.t, small.vehicle, small.sensor, small.peer,
                                                      true_range, measured, small.ctx, small.extra))
    huge = read_range_log(out / "huge_reading.csv")
    absurd = sum(c.by_type["absurd"] for c in glitches.counts(huge, glitches.classify_log(
        huge, glitches.limits(huge, base)))["kinds"])
    try:
        read_range_log(out / "negative_truth.csv")
        refused = ""
    except RangeLogError as err:
        refused = str(err)
    silent = calibrate(small, base, seed=1)
    two = calibrate(RangeLog(small.path, small.t[:2], small.vehicle[:2], small.sensor[:2], small.peer[:2],
                             small.true_range[:2], small.true_range[:2], {}, {}), base, seed=1)
    ok = (absurd == 1 and ":9:" in refused and "never reported" in silent.verdict and "too few" in two.verdict
          and not silent.effects and not two.effects)
    detail = (f"1e300 read as {absurd} absurd glitch; negative true range refused ({refused or 'NOT refused'}); "
              f"empty measured: {silent.verdict}; 2 rows: {two.verdict}")
    return ok, f"{'ok ' if ok else 'BAD'} bad_input: {detail}"
