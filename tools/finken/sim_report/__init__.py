"""make sim's report (tools/sim_report.py, tools/sim_crowd.py; docs/host.md): the figures of a run, what each is
compared with, and the targets the project keeps.

    sensor_errors      each sensor's error against the ground truth
    detector_metrics   wall detector against its baseline, and the swarm: pure functions
    detector_report    those of a detector-on and a detector-off run, printed and written as metrics.json
    metrics            make sim's figures from its two runs (also a sweep run's)
    crowd              the detector at 8 and 16 copters
    swarm_figures      what a swarm run shows of its shared arena (host and Paparazzi's NPS compared)
    arena_plot, swarm_plot   the arena at chosen moments; the trajectories
"""
