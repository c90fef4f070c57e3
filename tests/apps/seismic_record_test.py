#!/usr/bin/python3
"""The acceleration record of [seismic] (docs/scene-format.md "Earthquakes"), checked against
integrals computed here from the scene file and its record, independently of polydem.

Modes (SCRIPT POLYDEM MODE SCENE WORKDIR):
  newmark  E-NEWMARK: the block's permanent displacement relative to the shaken incline equals
           Newmark's sliding-block integral within 3 %, and the incline moved by the ground
           displacement of the record.
  ride     a fixed rock mass cut by joints (several fixed blocks) moves with a record given as one
           file per axis, every block by the ground displacement; a free block resting on it with
           high friction rides along (moves with the ground within 1e-3 of its size).
  errors   bad records are refused with the scene's line and the record's; a record that ends
           with the ground moving warns; polydem fos refuses a record.
"""
import bisect
import csv
import math
import os
import subprocess
import tomllib

import h5py
import numpy as np

from scene_test_util import expect, main_by_mode, run


def read_rows(path):
    """The rows of numbers of a record file: '#' comments, blank lines and a header left out."""
    rows = []
    for line in open(path):
        line = line.split("#")[0].replace(",", " ").split()
        if not line:
            continue
        try:
            rows.append([float(x) for x in line])
        except ValueError:
            assert not rows, "only the first line may be a header"
    return rows


def record(scene_file, scene):
    """(times, accelerations (n, 3) in m/s^2) of the scene's [seismic] record."""
    seismic = scene["seismic"]
    folder = os.path.dirname(scene_file)
    g = np.linalg.norm(scene["simulation"].get("gravity", [0, 0, -9.81]))
    factor = seismic.get("scale", 1.0) * (g if seismic.get("units", "m/s^2") == "g" else 1.0)
    if "record" in seismic:
        rows = np.array(read_rows(os.path.join(folder, seismic["record"])))
        return rows[:, 0], factor * rows[:, 1:4]
    dt = float(seismic["time_step"].split()[0])
    columns = {}
    for axis, key in enumerate(("record_x", "record_y", "record_z")):
        if key in seismic:
            columns[axis] = np.concatenate(read_rows(os.path.join(folder, seismic[key])))
    n = len(next(iter(columns.values())))
    acc = np.zeros((n, 3))
    for axis, values in columns.items():
        acc[:, axis] = values
    return dt * np.arange(n), factor * acc


def ground_displacement(times, acc, t):
    """u(t) of the piecewise-linear acceleration, from rest at the first sample: per segment the
    exact polynomial of a linear acceleration (zero before the first and after the last sample)."""
    v = np.zeros(3)
    u = np.zeros(3)
    for i in range(len(times) - 1):
        h = times[i + 1] - times[i]
        tau = min(max(t - times[i], 0.0), h)
        da = acc[i + 1] - acc[i]
        u_end = u + v * tau + acc[i] * tau**2 / 2 + da * tau**3 / (6 * h)
        v_end = v + acc[i] * tau + da * tau**2 / (2 * h)
        if tau < h:
            return u_end
        u, v = u_end, v_end
    return u + v * (t - times[-1])


def incline(scene):
    """theta, the fixed incline's outward normal n and down-dip unit vector d (turned about +y)."""
    fixed = next(p for p in scene["particle"] if p.get("fixed"))
    shape = next(s for s in scene["shape"] if s["name"] == fixed["shape"])
    assert shape["rotation"]["axis"] == [0, 1, 0], "the incline is turned about +y"
    theta = math.radians(shape["rotation"]["angle"])
    n = np.array([math.sin(theta), 0.0, math.cos(theta)])
    d = np.array([math.cos(theta), 0.0, -math.sin(theta)])
    return theta, n, d


def newmark_displacement(times, acc, gravity, n, d, tan_phi, h=1e-5):
    """Newmark's sliding block on the plane of normal n: in the ground's frame the block feels
    g - a(t); it slides down-dip (along d) while the down-dip load exceeds friction on the normal
    load, and until its relative velocity returns to zero:
      s'' = (g - a).d - tan(phi) (-(g - a).n)   while s' > 0 or that is > 0.
    Integrated with steps h (the trapezoid rule on s'', the stop found within the step)."""
    def a_at(t):
        if t <= times[0] or t >= times[-1]:
            return np.zeros(3)
        i = bisect.bisect_right(times, t) - 1
        s = (t - times[i]) / (times[i + 1] - times[i])
        return acc[i] + s * (acc[i + 1] - acc[i])

    def drive(t):
        g_eff = gravity - a_at(t)
        normal = -g_eff @ n
        assert normal > 0, "the block would leave the plane"
        assert g_eff @ d > -tan_phi * normal, "the block would slide up the plane"
        return g_eff @ d - tan_phi * normal

    t, v, s = float(times[0]), 0.0, 0.0
    a0 = drive(t)
    while t < times[-1] or v > 0:
        a1 = drive(t + h)
        if v == 0.0 and a0 <= 0.0 and a1 <= 0.0:
            t, a0 = t + h, a1
            continue
        v_next = v + 0.5 * (a0 + a1) * h
        if v_next < 0.0:  # stops within the step (velocity linear in it)
            s += 0.5 * v * (v / (v - v_next)) * h
            v = 0.0
        else:
            s += 0.5 * (v + v_next) * h
            v = v_next
        t, a0 = t + h, a1
    return s


def series(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def position(row, label):
    return np.array([float(row[label + "_" + q]) for q in "xyz"])


def check_newmark(polydem, scene_file, workdir):
    scene = tomllib.load(open(scene_file, "rb"))
    times, acc = record(scene_file, scene)
    gravity = np.array(scene["simulation"].get("gravity", [0, 0, -9.81]), dtype=float)
    theta, n, d = incline(scene)
    phi = math.radians(scene["material"][0]["friction_angle"])
    expected = newmark_displacement(times, acc, gravity, n, d, math.tan(phi))
    g = np.linalg.norm(gravity)
    a_c = g * math.tan(phi - theta)
    print(f"theta = {math.degrees(theta):.4g} deg, phi = {math.degrees(phi):.4g} deg: a_c = "
          f"{a_c:.4f} m/s^2 ({a_c / g:.4f} g), peak |a| = {np.abs(acc).max():.4f} m/s^2; Newmark's "
          f"permanent displacement {1000 * expected:.3f} mm")

    run([polydem, "run", scene_file, "--out", "out", "--no-snapshots", "--quiet"], workdir)
    rows = series(os.path.join(workdir, "out", "series.csv"))
    first, last = rows[0], rows[-1]
    end = float(last["time"])

    def relative(row):
        return (position(row, "block") - position(row, "incline")) - \
            (position(first, "block") - position(first, "incline"))
    measured = relative(last) @ d
    # The displacement is permanent: it no longer changed over the last 0.1 s of the run.
    before = next(r for r in reversed(rows) if float(r["time"]) <= end - 0.1)
    expect(abs(measured - relative(before) @ d) <= 1e-3 * expected,
           f"the block still slides at the end: {relative(before) @ d} m at "
           f"{before['time']} s, {measured} m at {end} s")
    print(f"polydem: the block moved {1000 * measured:.3f} mm down-dip relative to the incline "
          f"(across: {1000 * np.linalg.norm(relative(last) - measured * d):.4f} mm) by t = {end} s; "
          f"{100 * (measured / expected - 1):+.2f} % of Newmark's")
    expect(abs(measured - expected) <= 0.03 * expected,
           f"permanent displacement {measured} m, Newmark's {expected} m, not within 3 %")

    ground = ground_displacement(times, acc, end)
    moved = position(last, "incline") - position(first, "incline")
    print(f"incline moved {moved} m, the record's ground displacement at {end} s: {ground} m")
    expect(np.linalg.norm(moved - ground) <= 1e-9 * max(np.linalg.norm(ground), 1e-3),
           f"the incline moved by {moved}, the ground by {ground}")


def check_ride(polydem, scene_file, workdir):
    scene = tomllib.load(open(scene_file, "rb"))
    times, acc = record(scene_file, scene)
    run([polydem, "run", scene_file, "--out", "out", "--quiet"], workdir)
    snaps = sorted(os.listdir(os.path.join(workdir, "out", "snapshots")))

    def state(name):
        """Time, uids, centroids and fixed flags of a snapshot (fixed: the flag of a first face)."""
        with h5py.File(os.path.join(workdir, "out", "snapshots", name)) as h:
            uid = h["particles/uid"][:]
            pos = h["particles/position"][:]
            counts = h["particles/face_count"][:]
            fixed_faces = h["faces/fixed"][:]
            first_face = np.concatenate([[0], np.cumsum(counts)[:-1]])
            fixed = fixed_faces[first_face].astype(bool)
            return float(h.attrs["time"]), uid, pos, fixed
    t0, uid0, pos0, fixed0 = state(snaps[0])
    t1, uid1, pos1, fixed1 = state(snaps[-1])
    assert t0 == 0.0 and (uid0 == uid1).all()
    ground = ground_displacement(times, acc, t1)
    moved = pos1 - pos0
    print(f"{fixed0.sum()} fixed blocks, {(~fixed0).sum()} free; at t = {t1} s the ground moved "
          f"{ground} m")
    expect(fixed0.sum() >= 4, f"the rock mass has {fixed0.sum()} fixed blocks, expected several")
    error = np.linalg.norm(moved[fixed0] - ground, axis=1).max()
    print(f"fixed blocks: largest distance from the ground displacement {error:.3g} m")
    expect(error <= 1e-9 * np.linalg.norm(ground), "a fixed block did not move with the ground")
    edge = 1.0
    for u, m in zip(uid0[~fixed0], moved[~fixed0]):
        print(f"free block {u}: moved {m} m, off the ground by {np.linalg.norm(m - ground):.3g} m")
        expect(np.linalg.norm(m - ground) <= 1e-3 * edge,
               f"free block {u} did not ride with the ground: moved {m}, ground {ground}")
    expect(np.linalg.norm(ground) > 0.02 * edge, "the record moved the ground too little to test")


SCENE = """
[scene]
id = "record-errors"
[simulation]
dt = "1e-4 s"
steps = 20
[[material]]
name = "rock"
density = "2650 kg/m^3"
kn = "1 GN/m"
ks = "0.5 GN/m"
friction_angle = 35
[[shape]]
name = "cube"
type = "cube"
edge = 1
[[particle]]
shape = "cube"
material = "rock"
fixed = true
[[particle]]
shape = "cube"
material = "rock"
position = [0, 0, 1]
[seismic]
"""


def polydem_fails(polydem, workdir, name, seismic, record_text, *needles, command="run"):
    """Writes NAME.toml with [seismic] `seismic` and the record rec.csv; polydem COMMAND must
    exit 1 with every needle in its message."""
    with open(os.path.join(workdir, "rec.csv"), "w") as f:
        f.write(record_text)
    scene = os.path.join(workdir, name + ".toml")
    with open(scene, "w") as f:
        f.write(SCENE + seismic)
    out = subprocess.run([polydem, command, scene, "--out", name], cwd=workdir,
                         capture_output=True, text=True)
    message = out.stderr + out.stdout
    expect(out.returncode == 1, f"{name}: exit status {out.returncode}, expected 1: {message}")
    for needle in needles:
        expect(needle in message, f"{name}: '{needle}' not in the message: {message}")
    print(f"{name}: {message.strip().splitlines()[-1] if message.strip() else ''}")
    return message


def check_errors(polydem, scene_file, workdir):
    good = "time,ax,ay,az\n0,0,0,0\n0.001,1,0,0\n0.002,0,0,0\n"
    line = SCENE.count("\n") + 1  # the line of the first key under [seismic]
    polydem_fails(polydem, workdir, "short_row", 'record = "rec.csv"\n',
                  "t,ax,ay,az\n0,0,0,0\n# comment\n0.01,1,0\n", f"short_row.toml:{line}",
                  "rec.csv:4", "expected 4 numbers")
    polydem_fails(polydem, workdir, "times", 'record = "rec.csv"\n',
                  "0,0,0,0\n0.01,1,0,0\n0.01,0,0,0\n", "rec.csv:3", "times must increase")
    polydem_fails(polydem, workdir, "text", 'record = "rec.csv"\n',
                  "0,0,0,0\n0.01,x,0,0\n", "rec.csv:2", "not a row of numbers")
    polydem_fails(polydem, workdir, "missing", 'record = "none.csv"\n', good,
                  "cannot open the record", "none.csv")
    polydem_fails(polydem, workdir, "both", 'record = "rec.csv"\nkh = 0.1\nazimuth = 90\n', good,
                  "kh", "give either kh/kv or a record")
    polydem_fails(polydem, workdir, "no_step", 'record_x = "rec.csv"\n', "0\n1\n0\n",
                  "time_step")
    polydem_fails(polydem, workdir, "units", 'record = "rec.csv"\nunits = "gal"\n', good, "units")
    polydem_fails(polydem, workdir, "fos", 'record = "rec.csv"\n', good, "polydem fos",
                  "pseudo-static", command="fos")
    # A record whose ground ends moving: the run goes on and warns.
    with open(os.path.join(workdir, "rec.csv"), "w") as f:
        f.write("0,0,0,0\n0.001,1,0,0\n0.002,1,0,0\n")
    scene = os.path.join(workdir, "drift.toml")
    with open(scene, "w") as f:
        f.write(SCENE + 'record = "rec.csv"\n')
    out = run([polydem, "run", scene, "--out", "drift", "--no-snapshots"], workdir)
    message = out.stderr + out.stdout
    expect("no baseline correction" in message and "drift" in message,
           f"no warning of the drifting ground: {message}")


if __name__ == "__main__":
    main_by_mode({"newmark": check_newmark, "ride": check_ride, "errors": check_errors})
