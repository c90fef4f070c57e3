#!/usr/bin/python3
"""Direct-shear test of a joint law: runs a J-DIRECT-SHEAR-<LAW>.toml scene (written by
make_direct_shear.py) with the polydem Python package and compares, for each of its shear boxes,
the joint's shear stress against the sample's shear displacement with the law's own curve.

The expected curve is computed here from the joint-law specification's equations and the scene's
inputs only (the [[joint]], the sample's density, gravity, the box's profile), never from
polydem's code or figures of a run. Read from the run, each box:
  - shear displacement delta: of the centre of the sample's base (x), from its position and
    orientation, so that a tilt of the sample does not count;
  - normal and shear stress: the sample/base contact's normal_force and shear_force over the
    sample's base area L x W (the base is longer than the sample, so the area stays L x W);
  - the centre of pressure (the contact's point) against the base's centre: a tilt moves it;
  - the sample's acceleration (two consecutive leapfrog velocities), for its inertial force.
Checks, at the points each law checks (the curve where the sample slides or rises quasi-
statically, not the dynamic drop of a brittle joint): the contact takes the scene's joint; the
normal stress is the sample's weight over its area within 0.1 %; the centre of pressure stays
within 0.5 % of L of the base's centre; the sample never moves back; its inertial force is below
0.1 % of the shear force; the shear stress is within 1 % of the law's curve at every point, but
more than 1 % off the same law with a (residual) friction angle 1 deg larger somewhere (so that
the check could fail); and each law's figures (elastic slope, peak, residual, Barton-Bandis's
table points) are within 1 % of the law's. Exit status 1 on a failed check.

Usage: direct_shear.py SCENE [--samples N] [--csv PREFIX] [--plot PNG]
"""
import argparse
import bisect
import math
import re
import sys
import time
import tomllib

import numpy as np

TOLERANCE = 0.01  # the law's curve, relative (issue 24: within 1 %)
NORMAL_TOLERANCE = 1e-3  # the normal stress against the weight over the area
INERTIA_LIMIT = 1e-3  # inertial force over shear force: quasi-static
PRESSURE_OFFSET_LIMIT = 5e-3  # centre of pressure from the base's centre, over L

# Units of the strings these scenes use (docs/scene-format.md); angles are degrees.
UNITS = {"": 1.0, "Pa": 1.0, "kPa": 1e3, "MPa": 1e6, "GPa": 1e9, "Pa/m": 1.0, "MPa/m": 1e6,
         "GPa/m": 1e9, "m": 1.0, "mm": 1e-3, "s": 1.0, "ms": 1e-3, "m/s": 1.0, "mm/s": 1e-3,
         "kg/m^3": 1.0, "deg": 1.0, "N/m": 1.0, "GN/m": 1e9, "m/s^2": 1.0}


def value(x):
    """A scene value in SI units (degrees for angles): a number or "<number> <unit>"."""
    if isinstance(x, (int, float)):
        return float(x)
    m = re.fullmatch(r"\s*([-+0-9.eE]+)\s*(\S*)\s*", x)
    if not m or m.group(2) not in UNITS:
        sys.exit(f"direct_shear.py: cannot read the value '{x}'")
    return float(m.group(1)) * UNITS[m.group(2)]


# ---- The laws' curves under monotonic shear at a constant normal stress sigma (Pa), from the
# joint-law specification; delta (m) is the shear displacement, area (m^2) the contact's.
class Coulomb:
    """tau = min(jks delta, c + sigma tan(phi)): the elastic rise, then the peak, held."""

    def __init__(self, joint, sigma, area):
        self.jks = value(joint["jks"])
        self.peak = value(joint.get("cohesion", 0)) + sigma * math.tan(
            math.radians(value(joint["friction_angle"])))
        self.elastic_end = self.peak / self.jks

    def tau(self, delta):
        return min(self.jks * delta, self.peak)

    def checked(self, delta):
        # Near delta = 0 the stress is too small for a relative figure.
        return delta >= 0.2 * self.elastic_end

    def figures(self, delta, tau):
        rise = (delta >= 0.2 * self.elastic_end) & (delta <= 0.8 * self.elastic_end)
        slope = np.polyfit(delta[rise], tau[rise], 1)[0] if rise.sum() >= 2 else float("nan")
        held = delta >= 2 * self.elastic_end
        return [("elastic slope (Pa/m)", slope, self.jks),
                ("peak (Pa)", tau.max(), self.peak),
                ("sliding, mean (Pa)", tau[held].mean() if held.any() else float("nan"),
                 self.peak)]


class CoulombResidual:
    """The elastic rise tau = jks delta to the peak c + sigma tan(phi); once the joint slips it is
    broken for good and slides at the residual sigma tan(phi_r)."""

    def __init__(self, joint, sigma, area):
        self.jks = value(joint["jks"])
        phi = value(joint["friction_angle"])
        self.peak = value(joint.get("cohesion", 0)) + sigma * math.tan(math.radians(phi))
        self.residual = sigma * math.tan(math.radians(value(joint.get("residual_friction_angle",
                                                                      phi))))
        self.elastic_end = self.peak / self.jks

    def tau(self, delta):
        return self.jks * delta if delta < self.elastic_end else self.residual

    def checked(self, delta):
        # The rise from 0.2 of the peak displacement; the residual once the sample, released
        # by the drop, has slid past the plate's relaxed spring (the drop over jks) and is
        # pushed again (another elastic rise's length on).
        # The rise stops at 0.95 of it: a sample that tilts a little (its centre of pressure
        # 0.2 % of L off) loads its corners a little apart, the first to slip breaks and sheds
        # its load, so the joint fails progressively, just before the uniform peak; the peak
        # itself is checked as a figure.
        return (0.2 * self.elastic_end <= delta < 0.95 * self.elastic_end or
                delta >= self.elastic_end + 2 * self.peak / self.jks)

    def figures(self, delta, tau):
        rise = (delta >= 0.2 * self.elastic_end) & (delta <= 0.8 * self.elastic_end)
        slope = np.polyfit(delta[rise], tau[rise], 1)[0] if rise.sum() >= 2 else float("nan")
        after = delta >= self.elastic_end + 2 * self.peak / self.jks
        return [("elastic slope (Pa/m)", slope, self.jks),
                ("peak (Pa)", tau.max(), self.peak),
                ("residual, mean (Pa)", tau[after].mean() if after.any() else float("nan"),
                 self.residual)]


class BartonBandis:
    """Barton-Bandis with Bandis' scale correction and Barton's mobilization table (the joint-law
    specification): tau = sigma tan(min(phi_r + (JRC_mob / JRC_n) i, 70 deg)),
    i = JRC_n log10(JCS_n / sigma), JRC_mob / JRC_n interpolated in delta / delta_p."""

    TABLE_X = (0.0, 0.3, 0.6, 1.0, 2.0, 4.0, 10.0, 100.0)
    TABLE_Y = (None, 0.0, 0.75, 1.0, 0.85, 0.70, 0.50, 0.0)  # None: -phi_r / i

    def __init__(self, joint, sigma, area):
        jrc0 = value(joint["jrc"])
        jcs0 = value(joint["jcs"])
        self.phi_r = value(joint["residual_friction_angle"])
        lab = value(joint.get("lab_length", 0.1))
        field = value(joint.get("field_length", 0.0)) or math.sqrt(area)
        self.jrc = jrc0 * (field / lab) ** (-0.02 * jrc0)  # Bandis: JRC_n, JCS_n
        self.jcs = jcs0 * (field / lab) ** (-0.03 * jrc0)
        self.sigma = sigma
        self.i = self.jrc * math.log10(self.jcs / sigma) if sigma < self.jcs else 0.0
        self.delta_p = field / 500 * (self.jrc / field) ** 0.33  # Barton and Bandis 1982
        self.peak = sigma * math.tan(math.radians(min(self.phi_r + self.i, 70.0)))
        self.residual = sigma * math.tan(math.radians(self.phi_r))

    def ratio(self, x):
        """JRC_mob / JRC_n at delta / delta_p = x: the table, linear between its points."""
        ys = [(-self.phi_r / self.i if self.i > 0 else 0.0) if y is None else y
              for y in self.TABLE_Y]
        if x >= self.TABLE_X[-1]:
            return 0.0
        k = bisect.bisect_right(self.TABLE_X, x) - 1
        x0, x1 = self.TABLE_X[k], self.TABLE_X[k + 1]
        return ys[k] + (ys[k + 1] - ys[k]) * (x - x0) / (x1 - x0)

    def tau(self, delta):
        angle = self.phi_r + self.ratio(delta / self.delta_p) * self.i
        return self.sigma * math.tan(math.radians(min(angle, 70.0)))

    def checked(self, delta):
        # From a tenth of the way to phi_r (below it the stress is too small for a relative
        # figure).
        return delta >= 0.03 * self.delta_p

    def figures(self, delta, tau):
        out = []
        for x in self.TABLE_X[1:-1]:
            # The point nearest to the table's, against the law at that point's delta.
            k = int(np.argmin(np.abs(delta - x * self.delta_p)))
            out.append((f"tau at {delta[k] / self.delta_p:.3g} delta_p (Pa)", tau[k],
                        self.tau(delta[k])))
        out.append(("peak (Pa)", tau.max(), self.peak))
        after = delta >= 100 * self.delta_p
        out.append(("residual, mean (Pa)", tau[after].mean() if after.any() else float("nan"),
                    self.residual))
        return out


LAWS = {"coulomb": Coulomb, "coulomb-residual": CoulombResidual, "barton-bandis": BartonBandis}


# ---- The scene's shear boxes.
class Box:
    """One [[rock_mass]] of the scene: sample (free), base (fixed), plate (label <name>_push)."""

    def __init__(self, mass, scene, gravity):
        self.name = mass["name"]
        region = mass["region"]
        profile = np.array([[value(x), value(z)] for x, z in region["profile"]])
        y0, y1 = (value(y) for y in region["y"])
        above = profile[profile[:, 1] > 0]  # the sample's corners above the joint z = 0
        self.length = above[:, 0].max() - above[:, 0].min()
        self.height = above[:, 1].max()
        self.width = y1 - y0
        self.area = self.length * self.width
        material = next(m for m in scene["material"] if m["name"] == mass["material"])
        self.density = value(material["density"])
        volume = self.area * self.height  # the sample is a box: L x W x H
        self.mass = self.density * volume
        self.sigma = self.mass * gravity / self.area  # Pa: its weight over its base
        self.base_centre = np.array([(above[:, 0].max() + above[:, 0].min()) / 2,
                                     (y0 + y1) / 2, 0.0])


def quaternion_matrix(q):
    w, x, y, z = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def run(scene_path, samples):
    import polydem

    polydem.set_log_level("warning")
    scene = tomllib.load(open(scene_path, "rb"))
    gravity = -value(scene["simulation"]["gravity"][2])
    joints = scene["joint"]
    assert len(joints) == 1, "a direct-shear scene has one [[joint]]"
    joint = joints[0]
    law_name = joint.get("law", "coulomb")
    boxes = [Box(m, scene, gravity) for m in scene["rock_mass"]]

    sim = polydem.Simulation(scene_path)
    p = sim.particles(gather=True)
    labels = list(p["label"])
    for box in boxes:
        blocks = [i for i, label in enumerate(labels) if label.startswith(box.name + "_")
                  and label != box.name + "_push"]
        free = [i for i in blocks if not p["flags"][i] & polydem.FLAG_FIXED]
        fixed = [i for i in blocks if p["flags"][i] & polydem.FLAG_FIXED]
        assert len(free) == 1 and len(fixed) == 1, f"{box.name}: one sample and one base"
        box.sample, box.base = int(p["uid"][free[0]]), int(p["uid"][fixed[0]])
        box.row = free[0]
        # The base's centre in the sample's body frame, to follow it as the sample moves.
        r0 = quaternion_matrix(p["orientation"][free[0]])
        box.base_body = r0.T @ (box.base_centre - p["position"][free[0]])
        box.law = LAWS[law_name](joint, box.sigma, box.area)
        # The same law with its friction angle 1 deg larger (the residual one where there is
        # one: it governs most checked points): the check must tell them apart.
        key = "friction_angle" if law_name == "coulomb" else "residual_friction_angle"
        box.other_key = key.replace("_", " ")
        box.other = LAWS[law_name]({**joint, key: value(joint[key]) + 1}, box.sigma, box.area)
        box.rows = []

    total = int(round(value(scene["simulation"]["end_time"]) / sim.dt))
    every = max(2, total // samples)
    start = time.time()
    while sim.step_count + every <= total:
        sim.step(every - 1)
        # The contact table of a step belongs to the positions it started from (positions of
        # time - dt): the sample's base is taken there, with the velocity of time - 3 dt / 2.
        before = sim.particles(gather=True)
        sim.step(1)
        p = sim.particles(gather=True)
        c = sim.contacts()
        pairs = [tuple(sorted(u)) for u in c["uids"].tolist()]
        for box in boxes:
            i = box.row
            centre = before["position"][i] + quaternion_matrix(
                before["orientation"][i]) @ box.base_body
            delta = centre[0] - box.base_centre[0]
            k = pairs.index(tuple(sorted((box.sample, box.base)))) if tuple(
                sorted((box.sample, box.base))) in pairs else -1
            if k < 0:
                box.rows.append((sim.time, delta, 0, 0, -1, 0, 0, 0))
                continue
            inertia = box.mass * (p["velocity"][i][0] - before["velocity"][i][0]) / sim.dt
            offset = np.linalg.norm((c["point"][k] - centre)[:2]) / box.length
            box.rows.append((sim.time, delta, c["normal_force"][k] / box.area,
                             c["shear_force"][k] / box.area, c["joint"][k], inertia, offset,
                             p["velocity"][i][0]))
    wall = time.time() - start
    return law_name, boxes, sim.step_count, wall


def check(law_name, boxes, steps, wall, csv):
    failures = []

    def expect(ok, message):
        if not ok:
            failures.append(message)
            print("FAIL:", message)

    print(f"law {law_name}: {len(boxes)} boxes, {steps} steps, {wall:.1f} s wall")
    for box in boxes:
        rows = np.array(box.rows)
        t, delta, sigma, tau, joint, inertia, offset, velocity = rows.T
        law = box.law
        moving = delta > 0
        checked = np.array([law.checked(d) for d in delta]) & moving
        expected = np.array([law.tau(d) for d in delta])
        error = np.abs(tau - expected) / np.maximum(expected, 1e-300)
        print(f"\n{box.name}: L = {box.length:g} m, sigma_n = {box.sigma / 1e6:g} MPa "
              f"(weight over {box.area:g} m^2), {checked.sum()} points checked, "
              f"largest delta {delta.max():.4g} m")
        figures = law.figures(delta[moving], tau[moving])
        box.final = figures[-1]
        for name, measured, exp in figures:
            print(f"  {name:28s} {measured:12.6g}  law {exp:12.6g}  ({(measured - exp) / exp:+.3%})")
        worst = int(np.argmax(np.where(checked, error, -1)))
        box.figures, box.worst = figures, (error[worst], delta[worst])
        print(f"  largest error of tau: {error[worst]:.3%} at delta = {delta[worst]:.4g} m "
              f"(tau {tau[worst]:.6g} Pa, law {expected[worst]:.6g} Pa)")
        normal_error = np.abs(sigma[checked] - box.sigma).max() / box.sigma
        print(f"  normal stress within {normal_error:.2e} of sigma_n; centre of pressure within "
              f"{offset[checked].max():.2e} L of the base's centre; inertial force at most "
              f"{(np.abs(inertia[checked]) / (tau[checked] * box.area)).max():.2e} of the shear")
        expect(checked.sum() >= 20, f"{box.name}: only {checked.sum()} points to check")
        expect((joint[moving] == 0).all(), f"{box.name}: the contact does not take the joint")
        expect(normal_error <= NORMAL_TOLERANCE,
               f"{box.name}: normal stress off by {normal_error:.2e} of sigma_n")
        expect(offset[checked].max() <= PRESSURE_OFFSET_LIMIT,
               f"{box.name}: the centre of pressure moved {offset[checked].max():.2e} L: the "
               "sample tilts")
        for name, measured, exp in figures:
            expect(abs(measured - exp) <= TOLERANCE * abs(exp),
                   f"{box.name}: {name} {measured:.6g}, the law's {exp:.6g}, not within 1 %")
        expect((velocity[moving] >= 0).all(), f"{box.name}: the sample moved back")
        ratio = np.abs(inertia[checked]) / (tau[checked] * box.area)
        expect(ratio.max() <= INERTIA_LIMIT,
               f"{box.name}: inertial force {ratio.max():.2e} of the shear force: not quasi-static")
        expect(error[checked].max() <= TOLERANCE,
               f"{box.name}: tau off the law's curve by {error[worst]:.3%} at delta = "
               f"{delta[worst]:.4g} m")
        other = np.array([box.other.tau(d) for d in delta[checked]])
        apart = (np.abs(tau[checked] - other) / other).max()
        print(f"  the law with its {box.other_key} 1 deg larger: off by up to {apart:.2%}")
        expect(apart > TOLERANCE, f"{box.name}: the check cannot tell a friction angle 1 deg off")
        if csv:
            with open(f"{csv}.{box.name}.csv", "w") as f:
                f.write("time,delta,sigma,tau,tau_law,joint,inertia,pressure_offset,velocity\n")
                for r, e in zip(box.rows, expected):
                    f.write(",".join(f"{x:.10g}" for x in (*r[:4], e, *r[4:])) + "\n")
    strength_fit(boxes)
    summary(law_name, boxes)
    return failures


def strength_fit(boxes):
    """The normal-stress dependence: the line through the final strengths (the last figure of
    each law: held peak, residual) of the two stresses at each scale, measured and the law's."""
    for length in sorted({box.length for box in boxes}):
        pair = sorted((b for b in boxes if b.length == length), key=lambda b: b.sigma)
        if len(pair) != 2:
            continue
        lines = []
        for which in (1, 2):  # measured, law
            (s1, t1), (s2, t2) = ((b.sigma, b.final[which]) for b in pair)
            slope = (t2 - t1) / (s2 - s1)
            lines.append((math.degrees(math.atan(slope)), t1 - s1 * slope))
        (phi, c), (phi_law, c_law) = lines
        print(f"L = {length:g} m, final strength through sigma_n = {pair[0].sigma / 1e6:g} and "
              f"{pair[1].sigma / 1e6:g} MPa: friction angle {phi:.4f} deg (law {phi_law:.4f}), "
              f"intercept {c:.6g} Pa (law {c_law:.6g})")


def summary(law_name, boxes):
    """The figures as a Markdown table, one row per box (docs/validation.md, J-DIRECT-SHEAR):
    each figure as polydem / the law's, stresses in MPa, stiffnesses in GPa/m."""

    def shown(name, x):
        scale, unit = (1e9, "GPa/m") if "(Pa/m)" in name else (1e6, "MPa")
        return f"{x / scale:.5g}", unit

    print(f"\n| {law_name}: box | L (m) | sigma_n (MPa) | polydem / law | largest error of tau |")
    print("|---|---|---|---|---|")
    for box in boxes:
        cells = []
        for name, measured, exp in box.figures:
            (m, unit), (e, _) = shown(name, measured), shown(name, exp)
            cells.append(f"{name.rsplit(' (', 1)[0]} {m} / {e} {unit}")
        print(f"| {box.name} | {box.length:g} | {box.sigma / 1e6:g} | {'; '.join(cells)} | "
              f"{box.worst[0]:.2%} at {box.worst[1] * 1e3:.3g} mm |")


def plot(law_name, boxes, path):
    """The boxes' curves (points every few samples) over the law's (lines), one panel per scale."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    scales = sorted({box.length for box in boxes})
    fig, axes = plt.subplots(1, len(scales), figsize=(5.5 * len(scales), 4), squeeze=False)
    for ax, length in zip(axes[0], scales):
        for box in (b for b in boxes if b.length == length):
            rows = np.array(box.rows)
            delta, tau = rows[:, 1], rows[:, 3]
            line = np.concatenate([[0], np.geomspace(delta.max() * 1e-4, delta.max(), 2000)])
            shown = ax.plot(line * 1e3, [box.law.tau(d) / 1e6 for d in line], lw=1,
                            label=f"law, sigma_n = {box.sigma / 1e6:g} MPa")
            step = max(1, len(delta) // 60)
            ax.plot(delta[::step] * 1e3, tau[::step] / 1e6, "o", ms=3, mfc="none",
                    color=shown[0].get_color(), label=f"polydem, {box.name}")
        if law_name == "barton-bandis":  # the table spans 0.3 to 100 delta_p
            ax.set_xscale("symlog", linthresh=0.1)
        ax.set_xlabel("shear displacement delta (mm)")
        ax.set_ylabel("shear stress tau (MPa)")
        ax.set_title(f"{law_name}, L = {length:g} m")
        ax.legend(fontsize=8)
        ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    print(f"curves drawn in {path}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("scene")
    parser.add_argument("--samples", type=int, default=2000, help="points of each curve")
    parser.add_argument("--csv", help="write PREFIX.<box>.csv with every point")
    parser.add_argument("--plot", help="draw the curves into this PNG file")
    args = parser.parse_args()
    result = run(args.scene, args.samples)
    failures = check(*result, args.csv)
    if args.plot:
        plot(result[0], result[1], args.plot)
    if failures:
        sys.exit(f"{len(failures)} failed check(s)")
    print("\nall checks passed")


if __name__ == "__main__":
    main()
