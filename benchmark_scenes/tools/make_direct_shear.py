#!/usr/bin/env python3
"""Writes the direct-shear scenes J-DIRECT-SHEAR-<LAW>.toml (BENCHMARKS.md J-DIRECT-SHEAR), one per
joint law, into the current directory (run it in benchmark_scenes/).

Each scene holds four shear boxes side by side: blocks of L = 0.1 m and 1 m, each under a normal
stress of 0.5 and 2 MPa. A box is a [[rock_mass]] whose region is an inverted T in (x, z),
extruded over L in y and cut by the horizontal joint plane z = 0: the sample above (L x L x L/2,
free) rests on a longer base below (fixed), so that the contact area stays L^2 while the sample
slides up to 1.5 L. The normal stress is the sample's weight over its base, sigma_n = rho g L/2,
with gravity 10 m/s^2 and the density chosen for it. A thin plate (L/250 thick, its lower edge
L/1000 above the joint) driven at a constant velocity pushes the sample's back face through a
frictionless contact: the push acts almost at the joint's level, so that the sample hardly tilts
(its centre of pressure stays within 0.3 % of L of the base's centre) and the normal stress stays
uniform.
`benchmark_scenes/tools/direct_shear.py SCENE` runs a scene and compares each box's shear stress
against the law's curve."""
import math

G = 10.0  # m/s^2: round densities for round stresses
SCALES = (0.1, 1.0)  # m: sample length L
STRESSES = (0.5e6, 2e6)  # Pa
SETTLE = 0.1  # s: the sample settles on its joint before the plate moves
COMMAND = "PYTHONPATH=build/python /usr/bin/python3 benchmark_scenes/tools/direct_shear.py"


def num(x):
    return f"{x:.12g}"


def vec(v):
    return "[" + ", ".join(num(x) for x in v) + "]"


def barton_peak_displacement(length, jrc0, lab_length=0.1):
    """Barton and Bandis 1982: delta_p = (L_n / 500) (JRC_n / L_n)^0.33, JRC_n scale-corrected."""
    jrc_n = jrc0 * (length / lab_length) ** (-0.02 * jrc0)
    return length / 500 * (jrc_n / length) ** 0.33


def drive_speeding_up(unit, start, travel, duration):
    """A driver's lines for a speed unit (start + O (1 - cos(pi t / duration))) that covers
    `travel` units in `duration`: O = travel / duration - start."""
    o = travel / duration - start
    return [f"velocity = [{num(unit * (start + o))}, 0, 0]",
            f"oscillation = [{num(-unit * o)}, 0, 0]  # v = {num(unit)} m/s x ({num(start)} + "
            f"{num(o)} (1 - cos(pi t / {num(duration)} s)))",
            f"frequency = {num(1 / (2 * duration))}", f'phase = "{num(math.pi / 2)} rad"',
            f"end_time = {num(SETTLE + duration)}"]


LAWS = {
    "COULOMB": {
        "title": "Direct shear of a Coulomb joint with cohesion at two normal stresses and two scales",
        "joint": ['law = "coulomb"', 'jkn = "100 GPa/m"', 'jks = "50 GPa/m"', "friction_angle = 30",
                  'cohesion = "0.1 MPa"'],
        "curve": [
            "The law's curve (docs/scene-format.md, 'Joints'; monotonic shear): the shear stress rises",
            "elastically, tau = jks delta, up to the peak tau_p = c + sigma_n tan(phi), and stays there",
            "while the sample slides. With c = 0.1 MPa, phi = 30 deg: tau_p = 0.3887 MPa at",
            "sigma_n = 0.5 MPa and 1.2547 MPa at 2 MPa, at both scales (the elastic rise ends at",
            "delta = tau_p / jks = 7.8 and 25.1 um)."],
        "drive": lambda length: [f"velocity = [{num(3e-5)}, 0, 0]  # slow: inertia below 0.1 %"],
        "dt": 1e-4,
        "end_time": 3.6,
    },
    "COULOMB-RESIDUAL": {
        "title": "Direct shear of a Coulomb joint with residual strength at two normal stresses and "
                 "two scales",
        "joint": ['law = "coulomb-residual"', 'jkn = "100 GPa/m"', 'jks = "50 GPa/m"',
                  "friction_angle = 35", 'cohesion = "0.2 MPa"', "residual_friction_angle = 25"],
        "curve": [
            "The law's curve (3DEC's Coulomb slip with residual strength; monotonic shear): the shear",
            "stress rises elastically, tau = jks delta, up to the peak tau_p = c + sigma_n tan(phi);",
            "there the joint slips, loses its cohesion for good and slides at the residual",
            "tau_r = sigma_n tan(phi_r). With c = 0.2 MPa, phi = 35 deg, phi_r = 25 deg: tau_p = 0.5501",
            "and 1.6004 MPa, tau_r = 0.2332 and 0.9326 MPa at sigma_n = 0.5 and 2 MPa, at both scales.",
            "The drop releases the sample, which runs ahead of the plate until the plate's spring has",
            "relaxed to tau_r: the residual is checked once the sample has slid two elastic rises",
            "(2 tau_p / jks) past the peak."],
        "drive": lambda length: [f"velocity = [{num(3e-5)}, 0, 0]"],
        "dt": 1e-4,
        "end_time": 6.0,
    },
    "BARTON-BANDIS": {
        "title": "Direct shear of a Barton-Bandis joint at two normal stresses and two scales",
        "joint": ['law = "barton-bandis"', 'jkn = "100 GPa/m"', 'jks = "50 GPa/m"', "jrc = 10",
                  'jcs = "50 MPa"', "residual_friction_angle = 30"],
        "curve": [
            "The law's curve (Barton 1973, Barton and Choubey 1977, Barton and Bandis 1982; monotonic",
            "shear): with L_n = sqrt(A) = L (field_length 0) and L_0 = 0.1 m (lab_length's default),",
            "JRC_n = JRC_0 (L_n / L_0)^(-0.02 JRC_0), JCS_n = JCS_0 (L_n / L_0)^(-0.03 JRC_0),",
            "i = JRC_n log10(JCS_n / sigma_n), delta_p = (L_n / 500) (JRC_n / L_n)^0.33 and",
            "tau = sigma_n tan(min(phi_r + (JRC_mob / JRC_n) i, 70 deg)), JRC_mob / JRC_n linear in",
            "delta / delta_p between Barton's points (0, -phi_r / i), (0.3, 0), (0.6, 0.75), (1, 1),",
            "(2, 0.85), (4, 0.7), (10, 0.5), (100, 0). JRC_0 = 10, JCS_0 = 50 MPa, phi_r = 30 deg:",
            "L = 0.1 m: JRC_n = 10, JCS_n = 50 MPa, delta_p = 0.914 mm, peak 0.5959 MPa (i = 20.0 deg)",
            "  at 0.5 MPa and 1.9300 MPa (i = 13.98 deg) at 2 MPa;",
            "L = 1 m: JRC_n = 6.310, JCS_n = 25.06 MPa, delta_p = 3.673 mm, peak 0.4305 MPa",
            "  (i = 10.73 deg) at 0.5 MPa and 1.5031 MPa (i = 6.93 deg) at 2 MPa;",
            "residual sigma_n tan(phi_r) = 0.2887 and 1.1547 MPa from delta = 100 delta_p on."],
        # The plate speeds up smoothly: delta_p (0.3 + O (1 - cos(pi t / T))) per second, O such that
        # the sample slides 125 delta_p in T = 24 s. Slow through the table's first points, where
        # the slope of the curve changes most (the inertial force there is below 0.1 % only at
        # about 0.3 delta_p per second), fast towards the residual.
        "drive": lambda length: drive_speeding_up(barton_peak_displacement(length, 10), 0.3, 125,
                                                  24.0),
        "dt": 1.4e-4,  # below the rotational stability limit polydem estimates (1.48e-4 s)
        "end_time": SETTLE + 24.0,
    },
}


def box(index, length, stress):
    """The lines of one shear box: its materials, rock mass, plate and where it stands (y)."""
    name = f"box{index}"
    height = length / 2
    y = 2.0 * index * max(SCALES)  # boxes 2 m apart and more
    density = stress / (G * height)
    stiffness = 5e10 * length**2  # N/m: the plate's push, as stiff as the joint's shear springs
    base = length / 2
    profile = [(-0.3 * length, -base), (2.5 * length, -base), (2.5 * length, 0), (length, 0),
               (length, height), (0, height), (0, 0), (-0.3 * length, 0)]
    plate = (0.1 * length, 0.8 * length, 0.004 * length)
    lines = [
        f"# {name}: L = {num(length)} m, sigma_n = {num(stress / 1e6)} MPa "
        f"(density = sigma_n / (g L/2) = {num(density)} kg/m^3)",
        "[[material]]", f'name = "{name}-sample"', f"density = {num(density)}",
        f"kn = {num(stiffness)}", f"ks = {num(stiffness)}", "normal_damping = 0.3", "",
        "[[interaction]]  # critically damped: the sample follows the plate without ringing",
        f'materials = ["{name}-sample", "plate"]', "normal_damping = 1", "",
        "[[rock_mass]]", f'name = "{name}"', f'material = "{name}-sample"', 'fixed_material = "base"',
        f'label_prefix = "{name}"',
        "region = { type = \"profile\", profile = ["
        + ", ".join(vec(p) for p in profile) + f"], y = {vec((y - length / 2, y + length / 2))} }}",
        "", "[[rock_mass.plane]]", 'name = "joint"', "dip = 0", "dip_direction = 0",
        f"point = {vec((0, y, 0))}", 'fixed = "below"', 'joint = "joint"', "",
        "[[particle]]", f'label = "{name}_push"', f'shape = "plate-{num(length)}m"',
        'material = "plate"', f'driver = "push-{num(length)}m"',
        f"position = {vec((-plate[0] / 2, y, 0.001 * length + plate[2] / 2))}", ""]
    return lines


def scene(law):
    spec = LAWS[law]
    ident = f"J-DIRECT-SHEAR-{law}"
    out = [f"# {ident}: {spec['title']}.", "#",
           "# Written by tools/make_direct_shear.py; edit that, not this.", "#"]
    out += ["# " + line for line in __doc__.split("\n\n")[1].split("\n")]
    out += ["#"] + ["# " + line for line in spec["curve"]]
    out += ["#", f"#   {COMMAND} benchmark_scenes/{ident}.toml", "#",
            "# prints each box's curve against the law's, computed from this file's inputs, and exits",
            f"# non-zero when a point is off by more than 1 % (ctest python_direct_shear_{law.lower()}).",
            "", "[scene]", f'id = "{ident}"', f'title = "{spec["title"]}"',
            'source = "BENCHMARKS.md J-DIRECT-SHEAR; the joint-law specification"', "",
            "[simulation]", 'kernel = "gjk-epa-ipm"', f'dt = "{num(spec["dt"])} s"',
            f'end_time = "{num(spec["end_time"])} s"', f"gravity = [0, 0, -{num(G)}]", "",
            "[[material]]", 'name = "base"', "density = 2600", 'kn = "1 GN/m"', 'ks = "1 GN/m"',
            "normal_damping = 0.3", "",
            "[[material]]  # the plates: frictionless, the sample's stiffness (the pair takes the smaller)",
            'name = "plate"', "density = 2600", 'kn = "1e20 N/m"', 'ks = "1e20 N/m"',
            "friction_angle = 0", "normal_damping = 0.3", "",
            "[[joint]]", 'name = "joint"'] + spec["joint"] + [""]
    for length in SCALES:
        out += ["[[driver]]", f'name = "push-{num(length)}m"',
                *spec["drive"](length), f"start_time = {num(SETTLE)}", "",
                "[[shape]]", f'name = "plate-{num(length)}m"', 'type = "box"',
                f"size = {vec((0.1 * length, 0.8 * length, 0.004 * length))}", ""]
    index = 0
    for length in SCALES:
        for stress in STRESSES:
            out += box(index, length, stress)
            index += 1
    out += ["[output]", "series_every = 1000", ""]
    return "\n".join(out)


if __name__ == "__main__":
    for law in LAWS:
        with open(f"J-DIRECT-SHEAR-{law}.toml", "w") as f:
            f.write(scene(law))
