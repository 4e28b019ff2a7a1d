"""report.html: the workflow's result for a person, one self-contained file (figures as base64 PNG).

Figures: the gap per condition before and after (with the noise floor), QQ plots of residuals for the
conditions with the largest gap, and the candidate ranking of each round. Tables: the added effects with
their fitted parameters and 95 % intervals, the ranking with its margins, the localization tests.
matplotlib is imported here only, when a report is written.
"""
import base64
import html
import io

import numpy as np

from finken.discrepancy.glitches import RATE_ALPHA, RULE, TYPES
from finken.discrepancy.localize import ALPHA, RESOLUTION_M
from finken.discrepancy.selection import GAIN_ALPHA, GAIN_SEEDS, MARGIN_FLOOR, MARGIN_GAP, MIN_GAIN_SHARE
from finken.discrepancy.stability import REPLICATES, STABLE_SHARE

#: Conditions drawn in the gap figure and in the QQ plots; candidates drawn per ranking; histogram panels per kind.
GAP_FIGURE_ROWS, QQ_PANELS, RANKING_BARS, HIST_PANELS = 40, 12, 15, 16

CSS = """body{font-family:sans-serif;max-width:1100px;margin:2em auto;color:#222}
table{border-collapse:collapse;margin:1em 0;font-size:0.9em}td,th{border:1px solid #ccc;padding:3px 6px;text-align:right}
th{background:#eee}td.l,th.l{text-align:left}.verdict{font-size:1.1em;padding:0.6em;background:#f4f4e8}
img{max-width:100%}"""


def esc(x):
    return html.escape(str(x))


def fmt(x, digits=4):
    if x is None:
        return ""
    if isinstance(x, (float, np.floating)):
        return "" if not np.isfinite(x) else f"{x:.{digits}g}"
    return str(x)


def table(header, rows, left=(0,)):
    out = ["<table><tr>" + "".join(f"<th class='l'>{esc(h)}</th>" if i in left else f"<th>{esc(h)}</th>"
                                   for i, h in enumerate(header)) + "</tr>"]
    for r in rows:
        out.append("<tr>" + "".join(f"<td class='l'>{esc(fmt(c))}</td>" if i in left else f"<td>{esc(fmt(c))}</td>"
                                    for i, c in enumerate(r)) + "</tr>")
    return "\n".join(out + ["</table>"])


def png(fig):
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=90, bbox_inches="tight")
    import matplotlib.pyplot as plt
    plt.close(fig)
    return f"<img alt='figure' src='data:image/png;base64,{base64.b64encode(buf.getvalue()).decode()}'/>"


def gap_figure(result):
    """Horizontal bars: gap before and after per condition (largest before first), noise floor as ticks."""
    import matplotlib.pyplot as plt
    conds = sorted(result.conditions, key=lambda c: -c.gap_before)[:GAP_FIGURE_ROWS]
    fig, ax = plt.subplots(figsize=(10, 0.28 * len(conds) + 1.2))
    y = np.arange(len(conds))
    ax.barh(y - 0.2, [c.gap_before for c in conds], 0.4, label="before (input model)", color="#d95f02")
    ax.barh(y + 0.2, [c.gap_after for c in conds], 0.4, label="after (output model)", color="#1b9e77")
    ax.plot([c.floor for c in conds], y + 0.2, "k|", markersize=9, label="noise floor (after)")
    finish_gap_axes(ax, [f"{c.kind}: {c.label}" for c in conds], "Gap per condition, held-out rows", 8)
    return fig


def finish_gap_axes(ax, condition_labels, title, legend_size):
    """Labels, scale and legend of a figure of gaps per condition (one row of bars each, largest first)."""
    ax.set_yticks(np.arange(len(condition_labels)), condition_labels, fontsize=7)
    ax.invert_yaxis()
    ax.set_xlabel("gap: Wasserstein-1 distance [m]")
    ax.set_xscale("symlog", linthresh=1e-3)
    ax.legend(fontsize=legend_size, loc="lower right")
    ax.set_title(title)


def qq_figure(result):
    """QQ plots (measured vs simulated quantiles) of the conditions with the largest gap before."""
    import matplotlib.pyplot as plt
    conds = [c for c in sorted(result.conditions, key=lambda c: -c.gap_before) if c.qq][:QQ_PANELS]
    cols = 4
    rows = max(1, int(np.ceil(len(conds) / cols)))
    fig, axes = plt.subplots(rows, cols, figsize=(12, 3 * rows), squeeze=False)
    for ax in axes.ravel()[len(conds):]:
        ax.axis("off")
    for ax, c in zip(axes.ravel(), conds):
        m = c.qq["measured"]
        ax.plot(m, c.qq["before"], ".", color="#d95f02", markersize=3, label="before")
        ax.plot(m, c.qq["after"], ".", color="#1b9e77", markersize=3, label="after")
        lo, hi = float(np.min([m, c.qq["before"], c.qq["after"]])), float(np.max([m, c.qq["before"], c.qq["after"]]))
        ax.plot([lo, hi], [lo, hi], "k-", lw=0.6)
        ax.set_title(f"{c.kind}: {c.label}", fontsize=7)
        ax.tick_params(labelsize=6)
    if conds:
        axes[0, 0].legend(fontsize=7)
    what = "residual (reading - true range) [m]; the reading views: reading [m]"
    fig.suptitle(f"QQ plots, held-out rows: measured (x) vs simulated (y) quantiles of the {what}", fontsize=9)
    fig.tight_layout()
    return fig


def histogram_figure(result, kind):
    """The error's histogram, measured against simulated before and after, per condition of one kind: all rows,
    each sensor and vehicle, then the conditions with the largest gap before (HIST_PANELS in all): where an effect
    acts its shape shows (skew, tails), not only its mean and spread."""
    import matplotlib.pyplot as plt
    conds = [c for c in result.conditions if c.kind == kind and c.hist is not None]
    first = [c for c in conds if c.view in ("all", "sensor", "vehicle")]
    rest = sorted((c for c in conds if c not in first), key=lambda c: -c.gap_before)
    conds = (first + rest)[:HIST_PANELS]
    if not conds:
        return None
    cols = 4
    rows = int(np.ceil(len(conds) / cols))
    fig, axes = plt.subplots(rows, cols, figsize=(12, 2.6 * rows), squeeze=False)
    for ax in axes.ravel()[len(conds):]:
        ax.axis("off")
    for ax, c in zip(axes.ravel(), conds):
        edges = c.hist["edges"]
        for name, color in (("measured", "k"), ("before", "#d95f02"), ("after", "#1b9e77")):
            ax.stairs(c.hist[name], edges, color=color, label=name, lw=1.2 if name == "measured" else 1.0)
        ax.set_title(c.label, fontsize=7)
        ax.tick_params(labelsize=6)
    axes[0, 0].legend(fontsize=7)
    fig.suptitle(f"{kind}: histograms of the error (reading - true range [m]; the reading views: reading [m]), "
                 "held-out rows", fontsize=9)
    fig.tight_layout()
    return fig


def ranking_figure(sel, round_no):
    """Held-out gap of the best candidates of one kind in one round, with the current model and the margin."""
    import matplotlib.pyplot as plt
    fits = [f for f in sel.ranking if np.isfinite(f.heldout_gap)][:RANKING_BARS]
    fig, ax = plt.subplots(figsize=(9, 0.3 * len(fits) + 1.3))
    y = np.arange(len(fits))
    colors = ["#1b9e77" if sel.added and f is sel.winner else ("#7570b3" if f is sel.winner else "#999999")
              for f in fits]
    ax.barh(y, [f.heldout_gap for f in fits], color=colors)
    ax.axvline(sel.current_gap, color="#d95f02", label="current model")
    ax.axvline(sel.floor_gap, color="k", ls=":", label="noise floor")
    if sel.winner is not None:
        ax.axvspan(sel.winner.heldout_gap, sel.winner.heldout_gap + sel.margin, color="#1b9e77", alpha=0.15,
                   label="winner + margin")
    ax.set_yticks(y, [f.candidate.label for f in fits], fontsize=7)
    ax.invert_yaxis()
    ax.set_xlabel("held-out gap [m]")
    ax.legend(fontsize=7)
    ax.set_title(f"Round {round_no}, {sel.kind}: candidate ranking", fontsize=9)
    return fig


def _params_ci(fit):
    parts = []
    for p, v in fit.params.items():
        ci = fit.ci.get(p)
        parts.append(f"{p} = {v:.4g}" + (f" [{ci[0]:.4g}, {ci[1]:.4g}]" if ci else ""))
    return "; ".join(parts)


def _tests_table(tests, only_significant):
    rows = []
    for t in sorted(tests, key=lambda t: (t.kind, t.p_adjusted)):
        if only_significant and not t.significant:
            continue
        lag = f"{t.lag_s[0]:.3g} / {t.lag_s[1]:.3g}" if t.lag_s else ""
        rows.append([f"{t.kind}: {t.label}", t.n, t.gap, t.floor, t.p.get("shape"), t.p.get("tail"),
                     t.p.get("missing"), t.p.get("max"), t.p.get("lag"), lag, t.ad_stat, t.ad_p, t.p_adjusted,
                     "yes" if t.significant else "no"])
    if not rows:
        return "<p>None.</p>"
    return table(["condition", "n", "gap [m]", "floor [m]", "p shape (KS)", "p tail", "p missing", "p max",
                   "p lag", "lag meas/sim [s]", "AD stat", "AD p (0.001-0.25)", "Holm p", "stands out"], rows)


def _sensors_section(r):
    """The sensors of the log against the model's range, the ranges used and the sensors left out."""
    out = ["<h2>Sensors and ranges</h2>",
           table(["sensor", "rows", "readings", "true range beyond the model's range",
                   "readings beyond the model's range"],
                  [[s.sensor, s.rows, s.readings, s.true_beyond, s.readings_beyond] for s in r.sensors])]
    if r.ranges:
        out.append(table(["kind", "model's range [m]", "range used [m]", "how", "rows outside the model's range"],
                          [[k.kind, f"[{k.min_in:.4g}, {k.max_in:.4g}]", f"[{k.min_out:.4g}, {k.max_out:.4g}]",
                            k.source, k.rows_affected] for k in r.ranges.values()], left=(0, 1, 2, 3)))
        out.append(f"<p>The fitted ranges removed {r.range_gap_reduction:.1%} of the gap before.</p>")
    out += [f"<p>{esc(n)}</p>" for n in r.notes]
    return "\n".join(out)


def _glitches_section(r):
    """The glitches: the rule, per kind (with the models' rates and the effect set), per sensor, per stream."""
    counts = r.glitch_counts
    if not counts:
        return ""
    tests = {t.kind: t for t in r.glitch_tests}
    overall = {c.kind: c.glitch_rates for c in r.conditions if c.view == "all" and c.glitch_rates}
    kinds = []
    for c in counts["kinds"]:
        t, o = tests.get(c.label), overall.get(c.label, {})
        effect = ("" if t is None or not t.changed else
                  f"set: p = {t.effect.params['p']:.4g}, {len(t.effect.values)} values" if t.effect is not None
                  else "removed")
        kinds.append([c.label, c.rows, c.glitches, *c.by_type.values(), c.rate, t.model_rate if t else None,
                      t.p if t else None, effect, o.get("before"), o.get("after")])
    types = [n.replace("_", "-") for n in TYPES]
    glitchy = [c for c in counts["streams"] if c.glitches]
    out = ["<h2>Glitches</h2>",
           f"<p>{esc(RULE[0].upper() + RULE[1:])}. Glitches are kept out of the fit and the gap of the continuous "
           f"error; each kind's glitch effect is set when the log's glitch count is not the model's on the same "
           f"rows (Fisher's exact test of the two proportions, two-sided, level {RATE_ALPHA}).</p>",
           table(["kind", "rows", "glitches", *types, "rate", "input model's rate", "test p", "glitch effect",
                  "held-out rate before", "held-out rate after"], kinds, left=(0, 10)),
           table(["sensor", "rows", "glitches", *types, "rate"],
                 [[c.label, c.rows, c.glitches, *c.by_type.values(), c.rate] for c in counts["sensors"]]),
           f"<p>Streams with a glitch: {len(glitchy)} of {len(counts['streams'])}.</p>"]
    if glitchy:
        out.append(table(["stream", "rows", "glitches", *types, "rate"],
                         [[c.label, c.rows, c.glitches, *c.by_type.values(), c.rate] for c in glitchy]))
    return "\n".join(out)


def _mixture_summary(e):
    """A fitted mixture in numbers: excess over the true range where it acts, overall and per range bin."""
    return (f"<p>{esc(e.fit.candidate.label)}: what the mixture does to a reading (simulated, training rows)</p>"
            + table(["where", "n", "excess mean [m]", "excess median [m]", "spread [m] (16-84 % / 2)"],
                     [[x["condition"], x["n"], x["excess_mean"], x["excess_median"], x["excess_spread"]]
                      for x in e.fit.summary]))


def render_html(result):
    """The whole report as one HTML string."""
    r = result
    parts = [f"<!DOCTYPE html><html><head><meta charset='utf-8'><title>Discrepancy report</title>"
             f"<style>{CSS}</style></head><body>",
             "<h1>Discrepancy report</h1>",
             f"<p class='verdict'>{esc(r.verdict)}</p>",
             table(["", "value"], [
                 ["measured log", r.measured_path],
                 ["input model", r.model_in.source or r.model_in.name or ""],
                 ["rows (held-out) per kind", "; ".join(f"{k}: {n} ({h})" for k, (n, h) in r.rows.items())],
                 ["gap before [m]", r.gap_before], ["gap after [m]", r.gap_after],
                 ["noise floor [m]", r.gap_floor], ["seed", r.seed], ["run time [s]", f"{r.elapsed_s:.1f}"]]),
             f"<p><b>Gap:</b> {esc(r.metric)}. Held-out data only.</p>",
             _sensors_section(r),
             _glitches_section(r),
             "<h2>Added effects</h2>"]
    if r.effects:
        parts.append(table(["effect", "sensor", "condition", "parameters [95 % bootstrap interval]",
                             "gap reduction", "stability", "fitted by", "round"],
                            [[e.fit.candidate.name, e.fit.candidate.kind, e.fit.candidate.condition or "",
                              _params_ci(e.fit), e.gap_reduction,
                              (e.stability.text() if e.stability else "")
                              + (f"; undecided: tied with {e.undecided.candidate.label}" if e.undecided else ""),
                              e.fit.method, e.round] for e in r.effects],
                            left=(0, 1, 2, 3, 5, 6)))
        parts += [_mixture_summary(e) for e in r.effects if e.fit.summary]
    else:
        parts.append("<p>None: nothing is missing from the model, or nothing met the selection rule "
                     "(see the verdict).</p>")
    histograms = [f for f in (histogram_figure(r, kind) for kind in r.rows) if f is not None]
    parts += ["<h2>Gap per condition</h2>", png(gap_figure(r)), png(qq_figure(r)), *map(png, histograms),
              table(["sensor", "condition", "n", "gap before [m]", "gap after [m]", "floor [m]",
                     "glitch rate: measured", "before", "after"],
                     [[c.kind, c.label, c.n, c.gap_before, c.gap_after, c.floor,
                       *((c.glitch_rates or {}).get(k) for k in ("measured", "before", "after"))]
                      for c in r.conditions], left=(0, 1))]
    parts.append("<h2>Rounds</h2>")
    parts.append(f"<p>Each round localizes the disagreement of the current model (tests corrected together by "
                 f"Holm's method, family-wise error {ALPHA}; a condition stands out when a test is significant "
                 f"and its gap exceeds its noise floor; values rounded to {RESOLUTION_M} m for the tests), then "
                 f"fits every candidate effect on training time blocks and ranks them by their gap on held-out "
                 f"blocks. Margin = max({MARGIN_FLOOR} x noise floor, {MARGIN_GAP} x current gap); the simplest "
                 f"candidate within the margin of the best wins (a mixture only when no library effect, alone or "
                 f"with a second one refitted on top, gets within the margin of it); it is added when "
                 f"it beats the current model and the best rival explanation by the margin and passes the gain "
                 f"test: a paired one-sided t-test over {GAIN_SEEDS} seeds at level {GAIN_ALPHA}, a gain above the "
                 f"noise floor and at least {MIN_GAIN_SHARE:.0%} of the gap at the start. Stability: the share of "
                 f"{REPLICATES} resamples (new held-out blocks, bootstrapped training blocks, new seeds) that "
                 f"choose the same effect; below {STABLE_SHARE:.0%} the data cannot tell it from the rivals named."
                 f"</p>")
    for rnd in r.rounds:
        parts.append(f"<h3>Round {rnd.number}</h3>")
        parts.append("<p>Conditions standing out:</p>" + _tests_table(rnd.tests, True))
        for kind, sel in rnd.selections.items():
            parts.append(f"<h4>{esc(kind)}: {esc(sel.reason)}</h4>")
            notes = [f"Mixture set aside: {sel.mixture_set_aside}." if sel.mixture_set_aside else "",
                     *(f"Set aside, the mirror of the measured shape: {why}." for _, why in sel.mirrored),
                     f"Gain test: gain {sel.gain_test.gain:.4g} m, p = {sel.gain_test.p:.2g}, noise floor "
                     f"{sel.gain_test.floor:.4g} m, gap at the start {sel.gain_test.start_gap:.4g} m."
                     if sel.gain_test else "",
                     f"Stability: {sel.stability.text()}." if sel.stability else ""]
            parts.append("<p>" + " ".join(esc(n) for n in notes if n) + "</p>")
            parts.append(png(ranking_figure(sel, rnd.number)))
            rows = []
            for i, f in enumerate(sel.ranking, start=1):
                tag = "winner" if f is sel.winner else ("runner-up" if f is sel.runner_up else "")
                rows.append([i, f.candidate.label, tag, f.heldout_gap, sel.current_gap - f.heldout_gap,
                             _params_ci(f), f.method, f.note])
            parts.append(f"<p>Current held-out gap {sel.current_gap:.4g} m, noise floor {sel.floor_gap:.4g} m, "
                         f"margin {sel.margin:.4g} m; winner beats the current model by "
                         f"{fmt(sel.margin_over_current)} m and the runner-up by {fmt(sel.margin_over_runner_up)} m."
                         + "".join(f" {esc(f.candidate.label)} still lowers the gap to {g:.4g} m once the winner "
                                   f"is added: another part of the disagreement, not a rival."
                                   for f, g in sel.complementary)
                         + "</p>")
            parts.append(table(["rank", "candidate", "", "held-out gap [m]", "gain [m]", "parameters",
                                 "fitted by", "note"], rows, left=(1, 2, 5, 6, 7)))
            if rnd.skipped.get(kind):
                parts.append("<p>Not fitted: " + "; ".join(f"{esc(l)} ({esc(why)})"
                                                            for l, why in rnd.skipped[kind]) + "</p>")
    parts.append("<h2>Final localization (output model, all tests)</h2>")
    parts.append(_tests_table(r.final_tests, False))
    parts.append("</body></html>")
    return "\n".join(parts)
