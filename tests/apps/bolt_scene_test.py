#!/usr/bin/python3
"""B-BOLTED-BLOCK against the limit-equilibrium formula, computed from the scene file.

A block of weight W on an incline theta with friction phi, held by a bolt of force T at angle beta
to the plane's inward normal (beta > 0: the bolt points up-dip), has

  F = (W cos theta + T cos beta) tan phi / (W sin theta - T sin beta)

(BENCHMARKS.md section B). `polydem fos` must find it within 2 %. Mode `yield`: the bolt slides
into its yield force, T = axial_yield (no pretension); the scene is also run with [fos]
reduce_bolts = true, where T = axial_yield / F and F solves the formula with it. Mode `pretension`: the bolt is normal to
the plane (beta = 0) and stays elastic, T = pretension (below axial_yield). Both need the bolt's
shear stiffness 0: the formula counts its axial force only.

Usage: bolt_scene_test.py POLYDEM MODE SCENE WORKDIR
"""
import json
import math
import os
import tomllib

import numpy as np

from scene_test_util import expect, fos, main_by_mode, quantity

FORCE = {"N": 1.0, "kN": 1e3, "MN": 1e6}
STIFFNESS = {"N/m": 1.0, "kN/m": 1e3, "MN/m": 1e6, "GN/m": 1e9}


def bolt_direction(bolt):
    """The unit direction of a [[bolt]]: `direction`, or trend (clockwise from +y) and plunge."""
    if "direction" in bolt:
        d = np.array(bolt["direction"], dtype=float)
        return d / np.linalg.norm(d)
    t, p = math.radians(bolt["trend"]), math.radians(bolt["plunge"])
    return np.array([math.sin(t) * math.cos(p), math.cos(t) * math.cos(p), -math.sin(p)])


def setting(scene):
    """theta, W, tan phi, beta and the bolt of the scene (the incline turned about +y by theta)."""
    fixed = next(p for p in scene["particle"] if p.get("fixed"))
    incline = next(s for s in scene["shape"] if s["name"] == fixed["shape"])
    assert incline["rotation"]["axis"] == [0, 1, 0], "the incline is turned about +y"
    theta = math.radians(incline["rotation"]["angle"])
    normal = np.array([math.sin(theta), 0.0, math.cos(theta)])  # outward
    up_dip = np.array([-math.cos(theta), 0.0, math.sin(theta)])
    free = next(p for p in scene["particle"] if not p.get("fixed"))
    cube = next(s for s in scene["shape"] if s["name"] == free["shape"])
    material = scene["material"][0]
    density = quantity(material["density"], {"kg/m^3": 1.0})
    gravity = 9.81  # the default [simulation] gravity
    assert "gravity" not in scene["simulation"]
    weight = density * cube["edge"] ** 3 * gravity
    [bolt] = scene["bolt"]
    d = bolt_direction(bolt)
    beta = math.atan2(d @ up_dip, -(d @ normal))
    expect(abs(d @ np.array([0.0, 1.0, 0.0])) < 1e-12, "the bolt lies in the dip plane")
    expect(quantity(bolt["shear_stiffness"], STIFFNESS) == 0.0, "the bolt has no shear stiffness")
    tan_phi = math.tan(math.radians(material["friction_angle"]))
    return theta, weight, tan_phi, beta, bolt


def formula(theta, weight, tan_phi, beta, force):
    return ((weight * math.cos(theta) + force * math.cos(beta)) * tan_phi /
            (weight * math.sin(theta) - force * math.sin(beta)))


def reduced_bolt_factor(theta, weight, tan_phi, beta, axial_yield):
    """F with the bolt's yield force divided by F too: the root of F - formula(T / F), bisected
    (the right side falls as F grows, so there is one root)."""
    lo, hi = 1e-3, 100.0
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if mid - formula(theta, weight, tan_phi, beta, axial_yield / mid) < 0:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def bolts_entry(workdir, out):
    with open(os.path.join(workdir, out, "fos.json")) as f:
        return json.load(f)["bolts"]


def check_reduced(polydem, scene_file, workdir):
    """[fos] reduce_bolts = true: the yield force divided by F as well."""
    scene = tomllib.loads(open(scene_file).read())
    theta, weight, tan_phi, beta, bolt = setting(scene)
    text = open(scene_file).read()
    assert text.rstrip().splitlines()[-1].startswith("max_time"), "[fos] is the file's last table"
    variant = os.path.join(workdir, "reduced.toml")
    with open(variant, "w") as f:
        f.write(text.rstrip() + "\nreduce_bolts = true\n")
    expected = reduced_bolt_factor(theta, weight, tan_phi, beta,
                                   quantity(bolt["axial_yield"], FORCE))
    measured = fos(polydem, variant, workdir, out="reduced")
    print(f"reduce_bolts: F = {measured}, expected {expected:.4f} (T = axial_yield / F)")
    expect(bolts_entry(workdir, "reduced") == "reduced", "fos.json says the bolts were reduced")
    expect(measured is not None and abs(measured - expected) <= 0.02 * expected,
           f"reduce_bolts: F = {measured}, expected {expected:.4f} within 2 %")


def check(polydem, scene_file, workdir, mode):
    scene = tomllib.loads(open(scene_file).read())
    theta, weight, tan_phi, beta, bolt = setting(scene)
    axial_yield = quantity(bolt["axial_yield"], FORCE)
    pretension = quantity(bolt.get("pretension", 0.0), FORCE)
    if mode == "yield":
        expect(pretension == 0.0, "the yield setting has no pretension")
        force = axial_yield
    else:
        expect(abs(beta) < 1e-9, "the pretension setting has the bolt normal to the plane")
        expect(pretension < axial_yield, "the pretension is below the yield force")
        force = pretension
    expected = formula(theta, weight, tan_phi, beta, force)
    measured = fos(polydem, scene_file, workdir)
    expect(bolts_entry(workdir, "fos") == "unreduced", "fos.json says the bolts were unreduced")
    print(f"{mode}: theta = {math.degrees(theta):.4g} deg, W = {weight:.6g} N, T = {force:.6g} N, "
          f"beta = {math.degrees(beta):.4g} deg: F = {measured}, expected {expected:.4f} "
          f"(unbolted {tan_phi / math.tan(theta):.4f})")
    expect(measured is not None and abs(measured - expected) <= 0.02 * expected,
           f"{mode}: F = {measured}, expected {expected:.4f} within 2 %")
    if mode == "yield":
        check_reduced(polydem, scene_file, workdir)


if __name__ == "__main__":
    main_by_mode({"yield": lambda p, s, w: check(p, s, w, "yield"),
                  "pretension": lambda p, s, w: check(p, s, w, "pretension")})
