"""The Python side of the FINken toolkit (tools/*.py are its command lines; docs/simulator-map.md maps it).

Parts, each a subpackage with its own docstring:
    sim_report    make sim's report: sensor errors, the wall detector and the swarm, the crowd, plots
    discrepancy   the calibration workflow (make calibrate, make evaluate, make validate)
    imu           inertial-sensor errors from a log at rest (make imu-calibrate)
    sweep         Monte-Carlo sweeps on Dask (make sweep)
    bench         make bench's stages and report
    paparazzi     our modules in a real Paparazzi tree: overlay, checks, a swarm in its NPS, its ground segment
    can           the ranging units on CAN: frames, candump logs, candump to range log
    conf          Paparazzi's configuration files as Paparazzi reads them: airframes, module descriptors

Shared helpers, here at the top:
    rangelog, rangelog_columns   range logs (shared/spec/range-log.md): read, validate, write; a lab's own columns
    run_logs      the other logs of a run: detections.csv, poses.csv
    models        sensor models from Python, through _native (cffi binding of the one C implementation)
    atomic_output, text_numbers, cli_types, xml_errors, progress_line   outputs that lose nothing, numbers as
                  text and as options, XML errors with file and line, one line of progress
"""
