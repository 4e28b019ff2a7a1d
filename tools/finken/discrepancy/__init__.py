"""The discrepancy workflow: find where simulation and measurement disagree, name the missing effect, add it,
show the gap shrink (shared/spec/discrepancy-report.md). Entry point: workflow.calibrate; command line:
tools/calibrate.py.

    workflow                       replay, localize, name and fit, add, repeat
    dataset, ranges                the log's rows by sensor kind; each sensor's range
    glitches                       a sensor's glitches (negative, zero, infinite, absurd readings): counted, kept
                                   out of the continuous error, modelled
    conditions, condition_search, localize   the subsets compared, where a context column is cut, which differ
    candidates, fitting, selection, stability   candidate effects, fitted and scored on held-out blocks, the one
                                   to add, how stable it is
    shape, pairs                   a candidate skewed the other way set aside; two effects named at once
    gap                            the gap: Wasserstein-1 distance per condition and overall
    evaluate, evaluate_output, evaluate_html   make evaluate: models scored side by side
    report, report_html, progress  report.json, report.html, the progress bars
    log_options                    the options that read a lab's own log
    validate, validate_scenarios, validate_real_logs, hidden, synthetic, uwb_like   make validate: hidden-effect
                                   cases, scenarios of a first real log and of real logs as they come
"""
