#!/bin/bash
# `polydem bench kernels` measures every kernel with warm pair states (kept across passes) and
# cold (none) side by side, beside the stateless libccd (docs/performance.md "Kernel throughput"): the JSON has
# a warm and a cold record per kernel and set, and the table a line for each.
# usage: bench_kernels_states_test.sh POLYDEM WORKDIR
set -u
polydem=$1; work=$2
rm -rf "$work"; mkdir -p "$work"; cd "$work" || exit 1
"$polydem" bench kernels --pairs 20 --seconds 0.02 --passes 1 --kernels fcp,gjk-epa-ipm \
  --json k.json > k.txt || { echo "FAIL: exit status $?"; exit 1; }
python3 - << 'PY' || exit 1
import json, sys
rows = json.load(open("k.json"))
seen = {(r["kernel"], r["set"], r["states"]) for r in rows}
need = {(k, s, m) for k in ("fcp", "gjk-epa-ipm") for m in ("warm", "cold")
        for s in ("face-face", "random-cubes", "random-polyhedra")}
need |= {("libccd-gjk-epa", s, "none") for s in ("face-face", "random-cubes", "random-polyhedra")}
missing = need - seen
if missing or any(not r["per_second"] > 0 for r in rows):
    print("FAIL: records missing %s or without a rate" % sorted(missing))
    sys.exit(1)
PY
for line in "fcp *warm" "fcp *cold" "gjk-epa-ipm *warm" "gjk-epa-ipm *cold" "libccd-gjk-epa *none"; do
  grep -q "^$line " k.txt || { echo "FAIL: no table line '$line': $(cat k.txt)"; exit 1; }
done
echo "bench kernels: warm and cold side by side"
