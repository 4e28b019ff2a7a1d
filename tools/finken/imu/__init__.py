"""Inertial-sensor errors from a log of the copter at rest (make imu-calibrate, tools/imu_calibrate.py).

    imu_log      read the static log (columns, units, at-rest check); errors name the file, line and column
    allan        overlapping Allan deviation of one axis (AllanTools)
    noise_fit    white noise, bias instability and rate random walk fitted to it, with bootstrap intervals
    synthetic    seeded logs of known noise (tests, the example airframe's log)
    calibration  the whole calibration of a static log: every axis's Allan deviation and fit, the defines
    paparazzi    the SIMULATOR defines of Paparazzi's NPS gyro and accelerometer models, as an airframe fragment
    report       the JSON report;  plot: the figure (matplotlib, imported only there)

Units: SI. A gyro's white noise N [rad/s/sqrt(Hz)] is its angle random walk (the Allan deviation at 1 s), its bias
instability B [rad/s] the flicker floor (Allan deviation 0.664 B), its rate random walk K [rad/s^2/sqrt(Hz)] (Allan
deviation K sqrt(tau/3)); an accelerometer's the same with m/s^2 for rad/s.
"""
