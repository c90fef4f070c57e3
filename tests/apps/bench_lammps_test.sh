#!/bin/bash
# `polydem bench lammps` (docs/performance.md "polydem beside its peers, one table") runs without LAMMPS,
# printing polydem's figures only, and with an `lmp` it runs the generated input and puts LAMMPS's
# figures beside polydem's. No test needs LAMMPS: a stand-in executable checks the input and data
# it is given (the settled cubes as rounded bodies inside the box, the body pair style, the three
# wall fixes at the box's faces, the timed run) and answers in LAMMPS's place.
# usage: bench_lammps_test.sh POLYDEM WORKDIR
set -u
polydem=$1; work=$2
rm -rf "$work"; mkdir -p "$work"; cd "$work" || exit 1
args=(--particles 8 --layers 2 --settle 5000 --steps 3 --warmup 1 --kernels gjk-epa-ipm)

"$polydem" bench lammps "${args[@]}" --lmp "$work/no-such-lmp" --json none.json > none.txt \
  || { echo "FAIL: without LAMMPS, exit status $?: $(cat none.txt)"; exit 1; }
grep -q "LAMMPS not found" none.txt || { echo "FAIL: no 'LAMMPS not found': $(cat none.txt)"; exit 1; }

# The stand-in: -in in.pile -log none -screen FILE, in the directory of data.pile.
cat > fake-lmp << 'PY'
#!/usr/bin/env python3
import re, sys
args = sys.argv[1:]
script = open(args[args.index("-in") + 1]).read()
screen = args[args.index("-screen") + 1]
for need in ("atom_style body rounded/polyhedron", "pair_style body/rounded/polyhedron",
             "pair_coeff * * 100000000 0", "fix 1 all nve/body", "zplane 0 NULL", "timestep 0.0001",
             "run 1\n", "run 3\n"):
    if need not in script:
        sys.exit("input lacks " + need)
width = [float(x) for x in re.findall(r"xplane 0 (\S+)", script) + re.findall(r"yplane 0 (\S+)", script)]
if len(width) != 2 or width[0] != width[1]:
    sys.exit("walls: %s" % width)
data = open("data.pile").read()
atoms = data.split("\nAtoms\n\n")[1].split("\n\nBodies\n\n")[0].strip().splitlines()
bodies = data.split("\nBodies\n\n")[1].split()
if len(atoms) != 8 or bodies.count("79") != 8:
    sys.exit("%d atoms, %d bodies of 79 doubles" % (len(atoms), bodies.count("79")))
for a in atoms:
    x, y, z = map(float, a.split()[4:7])
    if not (0 < x < width[0] and 0 < y < width[0] and z > 0):
        sys.exit("a cube outside the box: %s" % a)
open(screen, "w").write("Loop time of 0.1 on 1 procs for 1 steps with 8 atoms\n"
                        "Loop time of 0.25 on 1 procs for 3 steps with 8 atoms\n")
PY
chmod +x fake-lmp
"$polydem" bench lammps "${args[@]}" --lmp "$work/fake-lmp" --keep kept --json with.json > with.txt \
  || { echo "FAIL: with the stand-in, exit status $?: $(cat with.txt)"; exit 1; }
[ -f kept/in.pile ] && [ -f kept/data.pile ] || { echo "FAIL: --keep kept no input"; exit 1; }
python3 - << 'PY' || exit 1
import json, sys
none, with_ = json.load(open("none.json")), json.load(open("with.json"))
def fail(msg):
    print("FAIL:", msg); sys.exit(1)
if sorted((r["code"], r["contact_model"]) for r in none) != [("polydem", "point"), ("polydem", "sub-contacts")]:
    fail("without LAMMPS: records %s" % none)
for r in none + with_:
    if r["code"] == "polydem" and not (r["particles"] == 8 and r["particle_steps_per_second"] > 0
                                       and r["peak_kb"] > 0):
        fail("polydem record %s: 8 particles, a rate and a peak memory expected" % r)
lmp = [r for r in with_ if r["code"] == "lammps"]
if len(lmp) != 1 or lmp[0]["particles"] != 8 or lmp[0]["steps"] != 3 or lmp[0]["seconds"] != 0.25:
    fail("LAMMPS record %s: the timed run's loop time (3 steps, 0.25 s) expected" % lmp)
if abs(lmp[0]["particle_steps_per_second"] - 8 * 3 / 0.25) > 1e-9 or lmp[0]["peak_kb"] <= 0:
    fail("LAMMPS rate or peak memory: %s" % lmp[0])
print("bench lammps: polydem alone, and beside the stand-in: OK")
PY
