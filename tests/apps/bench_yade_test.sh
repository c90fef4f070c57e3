#!/bin/bash
# `polydem bench yade` (docs/performance.md "polydem beside its peers, one table") runs without Yade, printing polydem's figures
# only, and with a Yade it runs the generated script and puts Yade's figures beside polydem's. No
# test needs Yade: a stand-in executable checks the script it is given (the settled particles as
# free bodies, the walls fixed, the Polyhedra engines, the timed run) and answers in Yade's place.
# usage: bench_yade_test.sh POLYDEM WORKDIR
set -u
polydem=$1; work=$2
rm -rf "$work"; mkdir -p "$work"; cd "$work" || exit 1
args=(--particles 8 --layers 2 --settle 5000 --steps 3 --warmup 1 --kernels gjk-epa-ipm)

"$polydem" bench yade "${args[@]}" --yade "$work/no-such-yade" --json none.json > none.txt \
  || { echo "FAIL: without Yade, exit status $?: $(cat none.txt)"; exit 1; }
grep -q "Yade not found" none.txt || { echo "FAIL: no 'Yade not found': $(cat none.txt)"; exit 1; }

# The stand-in: -n -j1 -x SCRIPT, as bench yade calls Yade. It checks the engines and the bodies:
# 5 fixed (the floor's top at z = 0, the walls' inner faces at x = 0 and y = 0) and the free
# cubes inside the box above the floor (as polydem settled them), and answers with their count.
cat > fake-yade << 'PY'
#!/usr/bin/env python3
import re, sys
script = open(sys.argv[-1]).read()
for need in ("Ig2_Polyhedra_Polyhedra_PolyhedraGeom", "Law2_PolyhedraGeom_PolyhedraPhys_Volumetric",
             "NewtonIntegrator(damping=0.1", "O.run(3, True)", "O.dt = 0.0001"):
    if need not in script:
        sys.exit("script lacks " + need)
bodies = []
for v, fixed in re.findall(r"^body\(\[(.*)\], (True|False)\)$", script, re.M):
    points = [tuple(map(float, p.split(","))) for p in re.findall(r"\(([^()]*)\)", v)]
    bodies.append((points, fixed == "True"))
walls = [b for b, fixed in bodies if fixed]
cubes = [b for b, fixed in bodies if not fixed]
top = lambda b, k: max(p[k] for p in b)
low = lambda b, k: min(p[k] for p in b)
if len(walls) != 5 or any(len(c) != 8 for c in cubes):
    sys.exit("%d walls, cubes of %s vertices" % (len(walls), {len(c) for c in cubes}))
floor, wall_x, wall_y = walls[0], walls[1], walls[3]
if abs(top(floor, 2)) > 1e-12 or abs(top(wall_x, 0)) > 1e-12 or abs(top(wall_y, 1)) > 1e-12:
    sys.exit("walls misplaced: floor top %g, wall x %g, wall y %g"
             % (top(floor, 2), top(wall_x, 0), top(wall_y, 1)))
if any(low(c, 2) < -0.01 or low(c, 0) < -0.01 or low(c, 1) < -0.01 for c in cubes):
    sys.exit("a cube outside the box")
print("POLYDEM-YADE %d 11 3 0.25" % len(cubes))
PY
chmod +x fake-yade
"$polydem" bench yade "${args[@]}" --yade "$work/fake-yade" --keep kept --json with.json > with.txt \
  || { echo "FAIL: with the stand-in, exit status $?: $(cat with.txt)"; exit 1; }
[ -f kept/yade_comparison.py ] || { echo "FAIL: --keep kept no script"; exit 1; }
python3 - << 'PY' || exit 1
import json, sys
none, with_ = json.load(open("none.json")), json.load(open("with.json"))
def fail(msg):
    print("FAIL:", msg); sys.exit(1)
if sorted((r["code"], r["contact_model"]) for r in none) != [("polydem", "point"), ("polydem", "sub-contacts")]:
    fail("without Yade: records %s" % none)
for r in none + with_:
    if r["code"] == "polydem" and not (r["particles"] == 8 and r["particle_steps_per_second"] > 0
                                       and r["contacts"] > 0):
        fail("polydem record %s: 8 settled particles, a rate and contacts expected" % r)
yade = [r for r in with_ if r["code"] == "yade"]
# 8 free bodies in the script (counted by the stand-in), 3 steps in 0.25 s: 96 particle-steps/s.
if len(yade) != 1 or yade[0]["particles"] != 8 or yade[0]["contacts"] != 11 \
        or abs(yade[0]["particle_steps_per_second"] - 96) > 1e-9:
    fail("yade record %s" % yade)
PY
grep -q "^yade .* 1.0 " with.txt || { echo "FAIL: no Yade line with ratio 1.0: $(cat with.txt)"; exit 1; }
echo "bench yade: polydem alone without Yade, both codes with one"
