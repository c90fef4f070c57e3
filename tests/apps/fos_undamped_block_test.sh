#!/bin/bash
# F-UNDAMPED-BLOCK (BENCHMARKS.md section F): `polydem fos` on a block on an incline in a scene
# without any damping, with the default criterion, finds F = tan(phi) / tan(theta) within 1 %
# (phi = 45 deg, theta = 19.8 deg: benchmark_scenes/F-UNDAMPED-BLOCK.toml). fos.json says the
# trials ran as a static solution with local damping 0.8 by default, and gives how far each
# stable trial moved before it came to rest (below the block's size: it did not slide off).
# usage: fos_undamped_block_test.sh POLYDEM SCENE WORKDIR
set -u
polydem=$1; scene=$2; work=$3
rm -rf "$work"; mkdir -p "$work"; cd "$work" || exit 1
"$polydem" fos "$scene" --out out > fos.log 2>&1 || { echo "FAIL: exit status $?"; cat fos.log; exit 1; }
cat fos.log
grep -q "criterion: static solution with local damping 0.8" fos.log ||
  { echo "FAIL: the console does not state the criterion"; exit 1; }
/usr/bin/python3 - out/fos.json << 'EOF2'
import json, math, sys
j = json.load(open(sys.argv[1]))
analytical = math.tan(math.radians(45.0)) / math.tan(math.radians(19.8))
f = j["factor_of_safety"]
c = j["criterion"]
problems = []
if f is None or abs(f - analytical) > 0.01 * analytical:
    problems.append(f"F = {f}, analytical {analytical:.4f} ({j['note']})")
if c["local_damping"] != 0.8 or not c["local_damping_from"].startswith("default"):
    problems.append(f"criterion {c}")
for t in j["trials"]:
    if t["outcome"] == "stable" and not 0 <= t["max_displacement"] < 1.0:
        problems.append(f"stable trial F = {t['factor']} moved {t['max_displacement']} m")
print("\n".join("FAIL: " + p for p in problems) or f"F = {f}, analytical {analytical:.4f}")
sys.exit(1 if problems else 0)
EOF2
