#!/usr/bin/python3
"""Parallel snapshots of `polydem run` read back without polydem (h5py, and VTK's XDMF reader).

Runs tests/apps/snapshot_scene.toml on 1 and on 2 ranks and checks, for each run:
- one snapshot file per output time (steps 0, 25, ... 100) and nothing else in snapshots/;
  snapshots.xmf lists exactly those files with their times;
- counts: particles = the scene's 73, faces = 6 per cube and plate, topology length, contacts;
- the chosen fields and no others; values against series.csv: the monitored blocks' velocity and
  position equal the snapshot's bit for bit, and the contacts column equals the contact rows;
- each particle's contact_count and resultant force equal what its rows in /contacts give;
- the rows are in uid order, and every table but /contacts and /faces/rank of the 2-rank files
  equals the 1-rank files' bit for bit (the contacts as a set of pairs);
- ParaView's two XDMF readers (through pvpython) open snapshots.xmf and contacts.xmf and see the
  time steps, the polygons and the arrays (skipped with a message where pvpython is missing;
  Debian's python3-vtk9 has no XDMF reader);
- snapshot_format = "vtk" writes the VTK files and no HDF5 ones;
- `--picture` renders RUN/frames.png and plots RUN/series.png (PNGs) on the 1-rank run;
- an unknown field in the scene stops the run with the file, the line and the known fields;
- snapshot_migration_scene.toml (a dense pack whose particles cross rank borders in the steps
  before its snapshots) on 1 and 4 ranks: the particle tables, contact_count and force included,
  are the same bit for bit, and each particle's contact_count is that of its rows in /contacts.

Usage: snapshot_xdmf_test.py POLYDEM MPIEXEC SCENE WORKDIR
"""
import csv
import json
import os
import re
import shutil
import subprocess
import sys

import h5py
import numpy as np

STEPS = [0, 25, 50, 75, 100]
PARTICLES = 73  # 72 cubes and the plate, each 6 faces
FIELDS = ["uid", "speed", "velocity", "rank", "material", "contact_count", "force", "position"]
CONTACT_FIELDS = ["uid_a", "uid_b", "normal", "normal_force", "force"]


def fail(message):
    print("snapshot_xdmf_test: FAIL: " + message, file=sys.stderr)
    sys.exit(1)


def expect(condition, message):
    if not condition:
        fail(message)


def text(attribute):
    """A string attribute (polydem writes fixed-length strings, which h5py gives as bytes)."""
    return attribute.decode() if isinstance(attribute, bytes) else str(attribute)


def run(polydem, mpiexec, scene, out, ranks):
    shutil.rmtree(out, ignore_errors=True)
    # The 1-rank run also renders its picture (polydem run --picture -> render_frames.py).
    command = [polydem, "run", scene, "--out", out, "--quiet"] + (["--picture"] if ranks == 1 else [])
    if ranks > 1:
        command = [mpiexec, "-n", str(ranks), "--oversubscribe"] + command
    result = subprocess.run(command, capture_output=True, text=True)
    expect(result.returncode == 0, f"{ranks}-rank run failed:\n{result.stderr}")
    if ranks == 1:
        for name in ("frames.png", "series.png"):
            png = os.path.join(out, name)
            expect(f"no {name}" not in result.stderr, f"--picture warned: {result.stderr}")
            with open(png, "rb") as f:
                expect(f.read(8) == b"\x89PNG\r\n\x1a\n" and os.path.getsize(png) > 20000,
                       f"{png} is not a picture")


def read_series(out):
    with open(os.path.join(out, "series.csv")) as f:
        rows = list(csv.DictReader(f))
    return {int(float(r["step"])): r for r in rows}


def check_run(out, ranks):
    files = sorted(os.listdir(os.path.join(out, "snapshots")))
    expect(files == [f"snapshot_{s:010d}.h5" for s in STEPS],
           f"{ranks} ranks: snapshots/ holds {files}")
    xmf = open(os.path.join(out, "snapshots.xmf")).read()
    listed = re.findall(r"(snapshots/snapshot_\d+\.h5):/mesh/points", xmf)
    expect(listed == ["snapshots/" + f for f in files], f"snapshots.xmf lists {listed}")
    series = read_series(out)
    snapshots = {}
    for step, name in zip(STEPS, files):
        with h5py.File(os.path.join(out, "snapshots", name), "r") as h:
            expect(text(h.attrs["format"]) == "polydem-snapshot", "format attribute")
            expect(text(h.attrs["fields"]).split(",") == FIELDS, "fields attribute")
            expect(int(h.attrs["step"]) == step, f"{name}: step {h.attrs['step']}")
            expect(int(h.attrs["writer_ranks"]) == ranks, f"{name}: writer_ranks")
            time = float(h.attrs["time"])
            expect(f'<Time Value="{time!r}"/>' in xmf or f'<Time Value="{time:.17g}"/>' in xmf,
                   f"{name}: time {time} not in snapshots.xmf")
            uid = h["particles/uid"][:]
            faces = h["particles/face_count"][:]
            expect(len(uid) == PARTICLES and len(set(uid)) == PARTICLES,
                   f"{name}: {len(uid)} particles ({len(set(uid))} distinct), expected {PARTICLES}")
            expect(np.all(faces == 6) and faces.sum() == 6 * PARTICLES, f"{name}: face counts")
            expect(sorted(h["faces"].keys()) == sorted(FIELDS), f"{name}: fields {list(h['faces'])}")
            expect(sorted(h["contacts"].keys()) == sorted(CONTACT_FIELDS + ["point", "vertex"]),
                   f"{name}: contact fields {list(h['contacts'])}")
            topology = h["mesh/topology"][:]
            expect(len(topology) == 6 * PARTICLES * (2 + 4), f"{name}: topology length")
            expect(np.all(topology.reshape(-1, 6)[:, :2] == [3, 4]), f"{name}: cubes' faces")
            expect(topology.reshape(-1, 6)[:, 2:].max() < len(h["mesh/points"]),
                   f"{name}: face vertex out of range")
            face = {k: h["faces/" + k][:] for k in FIELDS}
            first = np.concatenate([[0], np.cumsum(faces)[:-1]])
            expect(np.all(face["uid"][first] == uid), f"{name}: /faces/uid against /particles/uid")
            expect(np.array_equal(face["velocity"][first], h["particles/velocity"][:]),
                   f"{name}: /faces/velocity against /particles/velocity")
            expect(np.allclose(face["speed"], np.linalg.norm(face["velocity"], axis=1), rtol=1e-15,
                               atol=0), f"{name}: speed is not |velocity|")
            expect(set(face["rank"]) <= set(range(ranks)), f"{name}: ranks {set(face['rank'])}")
            if ranks == 2:
                free = face["rank"][face["uid"] != 1]
                expect(len(set(free)) == 2, f"{name}: the particles are not on both ranks")
            contacts = {k: h["contacts/" + k][:] for k in CONTACT_FIELDS + ["point"]}
            count = len(contacts["uid_a"])
            expect(count == int(float(series[step]["contacts"])),
                   f"{name}: {count} contacts, series.csv says {series[step]['contacts']}")
            expect(np.all(contacts["uid_a"] < contacts["uid_b"]), f"{name}: uid_a < uid_b")
            for label in ("c_0_0_0", "u_5_5_0"):
                row = series[step]
                position = np.array([float(row[f"{label}_{a}"]) for a in "xyz"])
                velocity = np.array([float(row[f"{label}_v{a}"]) for a in "xyz"])
                hits = np.flatnonzero(np.all(h["particles/position"][:] == position, axis=1))
                expect(len(hits) == 1, f"{name}: {label}'s position from series.csv not found")
                expect(np.array_equal(h["particles/velocity"][hits[0]], velocity),
                       f"{name}: {label}'s velocity differs from series.csv")
            # contact_count and force of each free particle from the contact rows.
            fixed_uid = 1  # the plate: the first particle of the scene (uids count from 1)
            total = {u: np.zeros(3) for u in uid}
            number = {u: 0 for u in uid}
            for a, b, f in zip(contacts["uid_a"], contacts["uid_b"], contacts["force"]):
                total[a] += f
                total[b] -= f
                number[a] += 1
                number[b] += 1
            for i, u in enumerate(uid):
                if u == fixed_uid:
                    continue
                expect(face["contact_count"][first[i]] == number[u],
                       f"{name}: uid {u} contact_count {face['contact_count'][first[i]]}, "
                       f"contacts table {number[u]}")
                scale = 1e-12 * max(1.0, np.abs(contacts["force"]).max() if count else 1.0)
                expect(np.allclose(face["force"][first[i]], total[u], rtol=0, atol=scale),
                       f"{name}: uid {u} force {face['force'][first[i]]}, contacts {total[u]}")
            expect(np.all(np.diff(uid.astype(np.int64)) > 0), f"{name}: rows not in uid order")
            # Every table but the contacts and the rank field, as stored: compared across runs.
            tables = {}
            h.visititems(lambda path, node: tables.__setitem__(path, node[:]) if isinstance(
                node, h5py.Dataset) and not path.startswith("contacts") and path != "faces/rank"
                else None)
            order = np.argsort(uid)
            snapshots[step] = {
                "tables": tables,
                "uid": uid[order],
                "position": h["particles/position"][:][order],
                "velocity": h["particles/velocity"][:][order],
                "contacts": sorted(zip(contacts["uid_a"], contacts["uid_b"])),
                "speed_max": float(face["speed"].max()),
            }
    return snapshots, xmf


def check_paraview(out, last):
    """ParaView's XDMF readers (XDMFReader and Xdmf3ReaderS) through pvpython. Debian's VTK
    (python3-vtk9) is built without XDMF; ParaView's python3-paraview has both readers."""
    pvpython = shutil.which("pvpython")
    if not pvpython:
        print("snapshot_xdmf_test: SKIPPED the ParaView reader check: no pvpython on PATH "
              "(apt-get install python3-paraview)")
        return
    helper = os.path.join(os.path.dirname(os.path.abspath(__file__)), "snapshot_xdmf_paraview.py")
    files = [os.path.join(out, "snapshots.xmf"), os.path.join(out, "contacts.xmf")]
    result = subprocess.run([pvpython, "--force-offscreen-rendering", helper] + files,
                            capture_output=True, text=True, timeout=240)
    expect(result.returncode == 0, f"pvpython failed:\n{result.stderr}")
    seen = [json.loads(line) for line in result.stdout.splitlines() if line.startswith("{")]
    expect(len(seen) == 4, f"pvpython printed {result.stdout}")
    for s in seen:
        where = f"ParaView {s['reader']} on {os.path.basename(s['file'])}"
        if s["file"].endswith("snapshots.xmf"):
            expect(len(s["times"]) == len(STEPS), f"{where}: {len(s['times'])} time steps")
            expect(s["cells"] == 6 * PARTICLES and s["cell_type"] == 7,  # 7: VTK_POLYGON
                   f"{where}: {s['cells']} cells of type {s['cell_type']}")
            expect(set(FIELDS) <= set(s["cell_arrays"]), f"{where}: arrays {s['cell_arrays']}")
            expect(s["speed_max"] == last["speed_max"],
                   f"{where}: speed max {s['speed_max']}, h5py {last['speed_max']}")
        else:
            expect(s["points"] == last["contacts"] and s["cells"] == last["contacts"],
                   f"{where}: {s['points']} points, {s['cells']} cells, "
                   f"expected {last['contacts']}")
            expect(set(CONTACT_FIELDS) <= set(s["point_arrays"]),
                   f"{where}: arrays {s['point_arrays']}")
        print(f"{where}: {len(s['times'])} times, {s['cells']} cells at the last; arrays OK")


def check_unknown_field(polydem, scene, work):
    text = open(scene).read()
    bad = text.replace('"contact_count", "force"', '"contact_count",\n  "forse"')
    path = os.path.join(work, "bad_fields.toml")
    with open(path, "w") as f:
        f.write(bad)
    line = bad[:bad.index('"forse"')].count("\n") + 1
    result = subprocess.run([polydem, "run", path, "--out", os.path.join(work, "bad")],
                            capture_output=True, text=True)
    expect(result.returncode != 0, "a scene with an unknown field ran")
    expect(f"{path}:{line}" in result.stderr and "unknown field 'forse'" in result.stderr and
           "contact_count" in result.stderr, f"message for an unknown field: {result.stderr}")
    expect(not os.path.exists(os.path.join(work, "bad")), "the bad scene wrote its --out")


def check_vtk_format(polydem, scene, work):
    """snapshot_format = "vtk" keeps the VTK files (1 + P per snapshot and kind) and no HDF5;
    --picture then warns (it reads HDF5 snapshots only) and the run still succeeds."""
    text = open(scene).read().replace('snapshot_format = "xdmf"', 'snapshot_format = "vtk"')
    path = os.path.join(work, "vtk_format.toml")
    with open(path, "w") as f:
        f.write(text)
    out = os.path.join(work, "vtk")
    shutil.rmtree(out, ignore_errors=True)
    result = subprocess.run([polydem, "run", path, "--out", out, "--picture"],
                            capture_output=True, text=True)
    expect(result.returncode == 0, f"the VTK-format run failed:\n{result.stderr}")
    files = sorted(os.listdir(os.path.join(out, "snapshots")))
    expect(len(files) == 4 * len(STEPS) and all(f.endswith((".vtp", ".pvtp")) for f in files),
           f"VTK format: snapshots/ holds {files}")
    expect(os.path.isfile(os.path.join(out, "snapshots.pvd")) and
           not os.path.exists(os.path.join(out, "snapshots.xmf")), "VTK format: collections")
    expect("no frames.png" in result.stderr and not os.path.exists(os.path.join(out, "frames.png")),
           f"VTK format with --picture: {result.stderr}")
    expect(os.path.isfile(os.path.join(out, "series.png")),
           "VTK format with --picture: series.csv is still plotted to series.png")


def particle_tables(out):
    """Every snapshot's /faces tables but rank, by file name, and its contact pairs."""
    tables = {}
    for name in sorted(os.listdir(os.path.join(out, "snapshots"))):
        with h5py.File(os.path.join(out, "snapshots", name), "r") as h:
            faces = {k: h["faces"][k][()] for k in h["faces"] if k != "rank"}
            pairs = np.stack([h["contacts"]["uid_a"][()], h["contacts"]["uid_b"][()]], axis=1)
            tables[name] = (faces, pairs)
    return tables


def check_migration(polydem, mpiexec, scene, work):
    """Snapshots taken after particles changed rank equal a 1-rank run's (see the docstring)."""
    runs = {}
    for ranks in (1, 4):
        out = os.path.join(work, f"migration{ranks}")
        shutil.rmtree(out, ignore_errors=True)
        command = [polydem, "run", scene, "--out", out, "--quiet"]
        if ranks > 1:
            command = [mpiexec, "-n", str(ranks), "--oversubscribe"] + command
        result = subprocess.run(command, capture_output=True, text=True)
        expect(result.returncode == 0, f"{ranks}-rank migration run failed:\n{result.stderr[-3000:]}")
        runs[ranks] = particle_tables(out)
    expect(sorted(runs[1]) == sorted(runs[4]) and len(runs[1]) == 3,
           f"migration scene: snapshot files {sorted(runs[1])} vs {sorted(runs[4])}")
    for name, (faces, pairs) in runs[1].items():
        other, _ = runs[4][name]
        for key, values in faces.items():
            expect(np.array_equal(values, other[key]), f"{name}: /faces/{key} differs, 1 vs 4 ranks")
        # contact_count per face row (one row per face) against the contact rows (the plate, uid 1,
        # is not counted).
        counts = {}
        for a, b in pairs:
            counts[a] = counts.get(a, 0) + 1
            counts[b] = counts.get(b, 0) + 1
        uid, count = faces["uid"], faces["contact_count"]
        expect(all(count[k] == counts.get(uid[k], 0) for k in range(len(uid)) if uid[k] != 1),
               f"{name}: contact_count disagrees with the contact rows")
        expect(count.max() >= 10, f"{name}: the dense pack has no dense contacts: a weak test")


def main():
    if len(sys.argv) != 5:
        fail("usage: snapshot_xdmf_test.py POLYDEM MPIEXEC SCENE WORKDIR")
    polydem, mpiexec, scene, work = sys.argv[1:]
    os.makedirs(work, exist_ok=True)
    runs = {}
    for ranks in (1, 2):
        out = os.path.join(work, f"run{ranks}")
        run(polydem, mpiexec, scene, out, ranks)
        runs[ranks], _ = check_run(out, ranks)
    for step in STEPS:
        one, two = runs[1][step], runs[2][step]
        for key in ("uid", "position", "velocity"):
            expect(np.array_equal(one[key], two[key]), f"step {step}: {key} differs, 1 vs 2 ranks")
        # Rows in uid order: the mesh, particle and face tables are the same on any rank count.
        expect(sorted(one["tables"]) == sorted(two["tables"]), f"step {step}: datasets differ")
        for path, values in one["tables"].items():
            expect(np.array_equal(values, two["tables"][path]),
                   f"step {step}: /{path} differs between 1 and 2 ranks")
        expect(one["contacts"] == two["contacts"], f"step {step}: contact pairs differ")
    expect(any(len(runs[2][s]["contacts"]) for s in STEPS), "no contacts at all: a weak test")
    last = runs[2][STEPS[-1]]
    check_paraview(os.path.join(work, "run2"),
                   {"speed_max": last["speed_max"], "contacts": len(last["contacts"])})
    check_unknown_field(polydem, scene, work)
    check_vtk_format(polydem, scene, work)
    check_migration(polydem, mpiexec,
                    os.path.join(os.path.dirname(scene), "snapshot_migration_scene.toml"), work)
    print(f"snapshot_xdmf_test: OK ({len(STEPS)} snapshots on 1 and 2 ranks)")


if __name__ == "__main__":
    main()
