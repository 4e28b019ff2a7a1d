"""The figure of a calibration: per sensor, each axis's Allan deviation (points), the fitted model (line) and what
Paparazzi's model with the written defines gives (dashed). matplotlib is imported here only."""
import numpy as np

from finken.atomic_output import atomic_output
from finken.imu.paparazzi import markov_drive, paparazzi_adev


def plot_calibration(cal, path):
    """Write the PNG of a finken.imu.calibration.Calibration to path."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    sensors = [s for s in ("gyro", "accel") if any(name.startswith(s) for name in cal.fits)]
    fig, panels = plt.subplots(1, len(sensors), figsize=(6.5 * len(sensors), 5), squeeze=False)
    for panel, sensor in zip(panels[0], sensors):
        for (name, fit), colour in zip([(n, f) for n, f in cal.fits.items() if n.startswith(sensor)],
                                       ("tab:red", "tab:green", "tab:blue")):
            curve = cal.curves[name]
            tau = np.geomspace(curve.tau[0], curve.tau[-1], 200)
            q = markov_drive(fit.noise(), curve.tau)[0] if sensor == "gyro" else 0.0
            panel.loglog(curve.tau, curve.adev, "o", color=colour, ms=4, label=f"{name}: log")
            panel.loglog(tau, fit.adev(tau), "-", color=colour, lw=1.2,
                         label=f"fit N={fit.white.value:.3g} B={fit.bias_instability.value:.3g} "
                               f"K={fit.rate_random_walk.value:.3g}")
            panel.loglog(tau, paparazzi_adev(sensor == "gyro", fit.white.value, q, tau), "--", color=colour, lw=1,
                         label="Paparazzi's model")
        unit = "rad/s" if sensor == "gyro" else "m/s$^2$"
        panel.set(xlabel="averaging time tau [s]", ylabel=f"Allan deviation [{unit}]",
                  title=f"{'Gyroscope' if sensor == 'gyro' else 'Accelerometer'}: {cal.log.path}")
        panel.grid(True, which="both", alpha=0.3)
        panel.legend(fontsize=7)
    fig.tight_layout()
    try:
        with atomic_output(path, "wb") as f:
            fig.savefig(f, format="png", dpi=110)
    finally:
        plt.close(fig)
