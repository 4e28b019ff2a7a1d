"""The discrepancy workflow: find where simulation and measurement disagree, name the missing effect, add it,
show the gap shrink (shared/spec/discrepancy-report.md). Entry point: workflow.calibrate; command line:
tools/calibrate.py."""
