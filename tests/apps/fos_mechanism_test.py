#!/usr/bin/python3
"""The mechanism `polydem fos` reports, and the joints it reduces.

planar SCENE (J-PLANAR-COHESION): the failed trial just above F is kept in DIR/mechanism
  (XDMF snapshots, series.csv, blocks.csv, frames.png); its one block slides down the base
  plane's dip (its displacement within 2 deg of the dip vector read from the scene, its rotation
  small), the summary is plane sliding of 1 block on the joint the base plane names, and that
  joint governs. fos.json gives each reduced joint's critical strength, atan(tan(phi) / F) and
  c / F from the scene's [[joint]]. With [fos] joints = ["<base joint>"] only that joint is
  reduced and listed (no release joint, no material pair) and F stays within 2 % of Hoek and
  Bray's formula; an unknown joint name is refused with the file, line and name, nothing written.
wedge SCENE (J-WEDGE-JOINTS): wedge sliding of 1 block on both joints, down their line of
  intersection (within 2 deg of the cross product of the planes' normals from the scene).
topple SCENE (examples/fos-topple.toml): a column that topples at any friction: every trial
  fails, the mechanism is toppling of 1 block: its centroid moves downhill (+x, not along y),
  rotation carries it (theta R > |d| / 2) and its base slips less than half its displacement.

Usage: fos_mechanism_test.py POLYDEM MODE SCENE WORKDIR
"""
import csv
import glob
import json
import math
import os
import subprocess
import sys
import tomllib

import numpy as np
from scene_test_util import expect, main_by_mode

from joint_scenes_test import limit_equilibrium, normal_from_dip

def fos(polydem, scene, workdir, out, expect_status=0):
    proc = subprocess.run([polydem, "fos", scene, "--out", out], cwd=workdir, capture_output=True,
                          text=True)
    print(proc.stdout[-2500:])
    if proc.returncode != expect_status:
        print(proc.stderr[-3000:])
        sys.exit(f"polydem fos {scene}: exit status {proc.returncode}, expected {expect_status}")
    return proc


def read_outputs(workdir, out):
    with open(os.path.join(workdir, out, "fos.json")) as f:
        result = json.load(f)
    with open(os.path.join(workdir, out, "mechanism", "blocks.csv")) as f:
        blocks = list(csv.DictReader(f))
    return result, blocks


def check_files(workdir, out):
    mech = os.path.join(workdir, out, "mechanism")
    snapshots = glob.glob(os.path.join(mech, "snapshots", "snapshot_*.h5"))
    expect(len(snapshots) >= 2, f"{len(snapshots)} HDF5 snapshots of the mechanism")
    expect(os.path.isfile(os.path.join(mech, "snapshots.xmf")) or
           glob.glob(os.path.join(mech, "**", "*.xmf"), recursive=True), "an XDMF index")
    expect(os.path.isfile(os.path.join(mech, "series.csv")), "series.csv of the mechanism")
    expect(os.path.isfile(os.path.join(mech, "frames.png")), "frames.png of the mechanism")


def dip_vector(dip, dip_direction):
    """Unit vector down the dip (x east, y north, z up)."""
    d, a = math.radians(dip), math.radians(dip_direction)
    return np.array([math.cos(d) * math.sin(a), math.cos(d) * math.cos(a), -math.sin(d)])


def planar(polydem, scene_file, workdir):
    scene = tomllib.load(open(scene_file, "rb"))
    planes = scene["rock_mass"][0]["plane"]
    base = min(planes, key=lambda p: p["dip"])  # the sliding plane: the release plane is steeper
    joint_name = base["joint"]
    joint = next(j for j in scene["joint"] if j["name"] == joint_name)
    proc = fos(polydem, scene_file, workdir, "all")
    result, blocks = read_outputs(workdir, "all")
    f = result["factor_of_safety"]
    m = result["mechanism"]
    check_files(workdir, "all")
    expect(m["same_bits_as_search"], "the mechanism's trial is the search's, bit for bit")
    expect(m["factor"] == result["bracket"]["failed"], "the mechanism is the smallest failed F's")
    expect(m["summary"] == f"plane sliding of 1 block on '{joint_name}'",
           f"summary '{m['summary']}'")
    expect(f"mechanism: {m['summary']}" in proc.stdout, "the summary is printed")
    expect(result["governing"] == joint_name, f"governing '{result['governing']}'")
    expect(len(blocks) == 1 and blocks[0]["mode"] == "sliding", f"blocks.csv: {blocks}")
    d = np.array([float(blocks[0][k]) for k in ("dx", "dy", "dz")])
    angle = math.degrees(math.acos(min(1.0, d @ dip_vector(base["dip"], base["dip_direction"]) /
                                       np.linalg.norm(d))))
    expect(angle < 2.0, f"the block moved {angle:.3f} deg off the base's dip")
    expect(m["stopped_by"] in ("window", "size") and m["moving_blocks"] == m["free_blocks"] == 1,
           f"ran on past the decision ({m['stopped_by']}), the free block moves")
    expect(float(blocks[0]["rotation_deg"]) < 1.0, f"rotation {blocks[0]['rotation_deg']} deg")
    by_name = {j["name"]: j for j in result["joints"]}
    j = by_name.get(joint_name)
    expect(j is not None, f"joint '{joint_name}' listed among the reduced joints")
    if j:
        phi = math.degrees(math.atan(math.tan(math.radians(joint["friction_angle"])) / f))
        expect(abs(j["critical_friction_angle_deg"] - phi) < 1e-9,
               f"critical friction angle {j['critical_friction_angle_deg']} = atan(tan/F) {phi}")
        c = float(joint["cohesion"].split()[0]) * {"kPa": 1e3, "Pa": 1.0,
                                                   "MPa": 1e6}[joint["cohesion"].split()[1]]
        expect(abs(j["critical"]["cohesion"] - c / f) <= 1e-9 * c,
               f"critical cohesion {j['critical']['cohesion']} Pa = c / F = {c / f}")
    expect(abs(result["critical_friction_angle_deg"] - by_name[joint_name]
               ["critical_friction_angle_deg"]) == 0, "the top-level angle is the governing's")

    # Only the base joint reduced.
    text = open(scene_file).read().replace("[fos]\n", f'[fos]\njoints = ["{joint_name}"]\n', 1)
    only = os.path.join(workdir, "only-base.toml")
    open(only, "w").write(text)
    fos(polydem, only, workdir, "only")
    result, _ = read_outputs(workdir, "only")
    expect([j["name"] for j in result["joints"]] == [joint_name],
           f"joints reduced: {[j['name'] for j in result['joints']]}")
    expect(result["interactions"] == [], "no material pair reduced")
    f_le = limit_equilibrium(scene_file)  # joint_scenes_test.py: Hoek and Bray's formula
    expect(abs(result["factor_of_safety"] - f_le) <= 0.02 * f_le,
           f"F {result['factor_of_safety']} with only '{joint_name}' reduced, formula {f_le:.4f}")

    # An unknown joint refused: file:line, the name, nothing written.
    bad = os.path.join(workdir, "unknown-joint.toml")
    lines = open(scene_file).read().split("\n")
    k = lines.index("[fos]")
    lines.insert(k + 1, 'joints = ["bsae"]')
    open(bad, "w").write("\n".join(lines))
    proc = subprocess.run([polydem, "fos", bad, "--out", "bad"], cwd=workdir, capture_output=True,
                          text=True)
    expect(proc.returncode == 1, f"unknown joint: exit status {proc.returncode}")
    expect(f"unknown-joint.toml:{k + 2}" in proc.stderr and "'bsae'" in proc.stderr,
           f"unknown joint: message names the file, line {k + 2} and the name: {proc.stderr!r}")
    expect(not os.path.exists(os.path.join(workdir, "bad")), "nothing written for a refused scene")


def wedge(polydem, scene_file, workdir):
    scene = tomllib.load(open(scene_file, "rb"))
    a, b = scene["rock_mass"][0]["plane"]
    i = np.cross(normal_from_dip(a["dip"], a["dip_direction"]),
                 normal_from_dip(b["dip"], b["dip_direction"]))
    i /= np.linalg.norm(i)
    if i[2] > 0:
        i = -i  # down the line of intersection
    proc = fos(polydem, scene_file, workdir, "wedge")
    result, blocks = read_outputs(workdir, "wedge")
    m = result["mechanism"]
    names = sorted([a["joint"], b["joint"]])
    expect(m["summary"] in [f"wedge sliding of 1 block on '{x}' and '{y}'" for x, y in
                            (names, names[::-1])], f"summary '{m['summary']}'")
    expect(f"mechanism: {m['summary']}" in proc.stdout, "the summary is printed")
    expect(result["governing"] in names, f"governing '{result['governing']}'")
    expect(len(blocks) == 1 and blocks[0]["mode"] == "sliding", f"blocks.csv: {blocks}")
    d = np.array([float(blocks[0][k]) for k in ("dx", "dy", "dz")])
    angle = math.degrees(math.acos(min(1.0, d @ i / np.linalg.norm(d))))
    expect(angle < 2.0, f"the wedge moved {angle:.3f} deg off the line of intersection")


def topple(polydem, scene_file, workdir):
    proc = fos(polydem, scene_file, workdir, "topple")
    result, blocks = read_outputs(workdir, "topple")
    check_files(workdir, "topple")
    m = result["mechanism"]
    expect(result["factor_of_safety"] is None and result["bracket"]["failed"] == result["f_min"],
           "fails at f_min: the column topples whatever its friction")
    expect(m["summary"].startswith("toppling of 1 block"), f"summary '{m['summary']}'")
    expect(f"mechanism: {m['summary']}" in proc.stdout, "the summary is printed")
    expect(len(blocks) == 1 and blocks[0]["mode"] == "toppling", f"blocks.csv: {blocks}")
    b = blocks[0]
    d = np.array([float(b[k]) for k in ("dx", "dy", "dz")])
    expect(d[0] > 0 and abs(d[1]) < 0.01 * np.linalg.norm(d), f"it falls downhill (+x): {d}")
    expect(float(b["seat_slip"]) < 0.5 * np.linalg.norm(d),
           f"its base slips {b['seat_slip']} m, its centroid moves {np.linalg.norm(d)} m")
    turn = float(b["reach"]) - float(b["displacement"])  # theta R
    expect(turn > 0.5 * np.linalg.norm(d), f"rotation carries it: theta R = {turn} m, |d| = "
           f"{np.linalg.norm(d)} m ({b['rotation_deg']} deg)")


if __name__ == "__main__":
    main_by_mode({"planar": planar, "wedge": wedge, "topple": topple})
