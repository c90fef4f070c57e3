#!/usr/bin/python3
"""Tilt test with polydem from Python: load a scene, run it, plot a monitored particle.

A block rests on a platform that tilts at a constant rate w about a horizontal axis
(tilt_table.toml beside this script). It sticks until the tilt angle theta reaches the friction
angle phi, then slides with the acceleration g sin(theta - phi) / cos(phi) along the platform;
with theta = phi + w tau after the onset, integrating twice gives the slip
    s(theta) = g (D - sin D) / (w^2 cos phi),   D = theta - phi > 0,
(Coulomb friction with one coefficient; the forces of the rotating frame, of order w^2 r / g,
about 1e-3 here, are left out). The script runs the scene with polydem.run, reads the block's
monitored position from series.csv, takes away the platform's rigid rotation to get the slip,
and plots slip and block rotation against theta beside the analytical curve (matplotlib, Agg).

    PYTHONPATH=build/python /usr/bin/python3 python_coupling/examples/tilt_and_plot.py \\
        [--scene tilt_table.toml] [--out tilt_run] [--kernel NAME]

writes OUT/series.csv, OUT/summary.json and OUT/tilt.png. Also runs under
mpirun -n N (every rank runs the scene, rank 0 plots).
"""
import argparse
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402  (after the backend is chosen)
import numpy as np  # noqa: E402

import polydem  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
ONSET_SLIP = 1e-3  # m: "the block slides" once it has slipped this far


def rotation_matrix(axis, angle):
    """Rotation by `angle` about the unit vector `axis` (Rodrigues)."""
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + math.sin(angle) * k + (1 - math.cos(angle)) * (k @ k)


def tilt_angle(driver, t):
    """Angle the driver has turned the platform by at times t [rad]."""
    active = np.clip(t - driver["start_time"], 0.0, driver["end_time"] - driver["start_time"])
    return np.linalg.norm(driver["angular_velocity"]) * active


def analytical_slip(theta, phi, rate, g):
    """s(theta) of the module docstring [m]."""
    d = np.maximum(theta - phi, 0.0)
    return g * (d - np.sin(d)) / (rate**2 * math.cos(phi))


def slip_of(scene, series, label):
    """Distance of the particle `label` from where the platform's rotation alone would carry it."""
    driver = scene.drivers[0]
    if np.any(driver["velocity"] != 0) or np.any(driver["oscillation"] != 0):
        raise ValueError("this example handles a platform that only turns")
    start = scene.particles["position"][scene.particles["label"].index(label)]
    w = driver["angular_velocity"]
    axis = w / np.linalg.norm(w)
    position = np.column_stack([series[label + "_" + c] for c in "xyz"])
    carried = np.array([driver["pivot"] + rotation_matrix(axis, a) @ (start - driver["pivot"])
                        for a in tilt_angle(driver, series["time"])])
    return np.linalg.norm(position - carried, axis=1)


def plot(theta_deg, slip, analytic, rotation, phi_deg, title, path):
    fig, (top, bottom) = plt.subplots(2, 1, sharex=True, figsize=(7.5, 6.5))
    top.plot(theta_deg, 1e3 * slip, color="C0", lw=1.8, label="polydem")
    top.plot(theta_deg, 1e3 * analytic, color="k", lw=1.2, ls="--",
             label="rigid block, Coulomb friction")
    top.axvline(phi_deg, color="C3", lw=0.9, ls=":", label="friction angle %.4g deg" % phi_deg)
    top.set_ylabel("slip along the platform [mm]")
    top.legend(fontsize=8, loc="upper left")
    bottom.plot(theta_deg, rotation, color="C1", lw=1.4)
    bottom.set_ylabel("block rotation [rad]")
    bottom.set_xlabel("tilt angle [deg]")
    bottom.ticklabel_format(axis="y", style="sci", scilimits=(-2, 3))
    for ax in (top, bottom):
        ax.grid(True, alpha=0.35)
    fig.suptitle(title, fontsize=11)
    fig.tight_layout()
    fig.savefig(path, dpi=150)
    plt.close(fig)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--scene", default=os.path.join(HERE, "tilt_table.toml"))
    parser.add_argument("--out", default="tilt_run", help="output directory")
    parser.add_argument("--kernel", help="contact kernel (polydem.kernels() lists them)")
    parser.add_argument("--label", default="block", help="the monitored particle that slides")
    args = parser.parse_args(argv)

    scene = polydem.read_scene(args.scene)
    if args.kernel:
        scene.kernel = args.kernel
    result = polydem.run(scene, out=args.out, snapshots=False)
    if polydem.mpi_rank() != 0:
        return None

    _, series = polydem.plots.read_series(os.path.join(args.out, "series.csv"))
    driver = scene.drivers[0]
    rate = float(np.linalg.norm(driver["angular_velocity"]))
    phi = math.radians(scene.materials[0]["friction_angle"])
    g = float(np.linalg.norm(scene.gravity))
    theta = tilt_angle(driver, series["time"])
    slip = slip_of(scene, series, args.label)
    analytic = analytical_slip(theta, phi, rate, g)

    sliding = np.nonzero(slip > ONSET_SLIP)[0]
    onset = math.degrees(theta[sliding[0]]) if sliding.size else float("nan")
    # The analytical angle at which the slip reaches ONSET_SLIP (s grows monotonically).
    fine = np.linspace(phi, phi + math.radians(10), 100001)
    onset_analytic = math.degrees(fine[np.searchsorted(analytical_slip(fine, phi, rate, g),
                                                       ONSET_SLIP)])
    png = os.path.join(args.out, "tilt.png")
    plot(np.degrees(theta), slip, analytic, series[args.label + "_rotation"],
         math.degrees(phi), "%s, kernel %s" % (scene.title, scene.kernel), png)

    print("slip reaches %.3g mm at a tilt of %.3f deg (analytical %.3f deg, friction angle %.3g)"
          % (1e3 * ONSET_SLIP, onset, onset_analytic, math.degrees(phi)))
    print("final slip %.5g m at %.3f deg (analytical %.5g m); state hash %s"
          % (slip[-1], math.degrees(theta[-1]), analytic[-1], result["state_hash"]))
    print("wrote " + png)
    return {"png": png, "theta": theta, "slip": slip, "analytic": analytic,
            "rotation": series[args.label + "_rotation"], "onset_deg": onset,
            "onset_analytic_deg": onset_analytic, "friction_angle_deg": math.degrees(phi),
            "state_hash": result["state_hash"], "steps": result["steps"], "time": result["time"]}


if __name__ == "__main__":
    main()
    sys.exit(0)
