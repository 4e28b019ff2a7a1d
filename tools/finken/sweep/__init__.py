"""Monte-Carlo sweeps on Dask (make sweep, tools/sweep.py; docs/sweeps.md).

    spec, yaml_lines, values, points   the sweep file: keys with their lines, each parameter's values, the points
    hosts, worker, engine              the host builds and files, one run on a worker, the runs on a cluster
    metrics, store                     a run's figures (make sim's, flattened); runs.sqlite
    stats, plot, summary_page, report  intervals per point, plots, summary.html, the report in OUT
"""
