#!/bin/bash
# Restart with the joint laws' history (docs/checkpoint.md, docs/scene-format.md "Joints"): a
# rock mass on joints of all three laws (joint_laws_restart.toml) slides for 300 steps;
#  1. the uninterrupted run has the same state hash on 1, 2, 3 and 4 ranks;
#  2. its checkpoint of step 150 holds broken coulomb-residual sub-contacts and sheared
#     barton-bandis ones (/subcontacts/law_state), so the history matters to the continuation;
#  3. checkpointed on n ranks and restarted on n ranks (n = 1..4), and written on 2 ranks and
#     restarted on 3 and on 1, every continuation ends with the uninterrupted run's state hash;
#  4. a version-4 file (before the laws' history: rewritten here without /subcontacts/law_state,
#     its digest recomputed by checkpoint_summary.py's definition) of a scene with coulomb joints
#     (COULOMB_SCENE, whose history is empty) still continues bit-exact.
# usage: joint_laws_restart_test.sh POLYDEM MPIEXEC SCENE WORKDIR COULOMB_SCENE SUMMARY_SCRIPT
set -u
polydem=$1; mpiexec="$2 --oversubscribe"; scene=$3; work=$4; coulomb=$5; summary=$6
[ "$(id -u)" = 0 ] && mpiexec="$mpiexec --allow-run-as-root"
rm -rf "$work"; mkdir -p "$work"; cd "$work" || exit 1
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
hash_of() { /usr/bin/python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['state_hash'])" "$1/summary.json" 2> /dev/null; }
run() { timeout 300 $mpiexec -n "$1" "$polydem" "${@:2}" --no-snapshots --quiet; }
ckpt() { set -- "$(printf '%s/checkpoints/checkpoint_%012d_' "$1" "$2")"; set -- "$1"*.h5; echo "$1"; }

# 1. The uninterrupted run on 1 to 4 ranks.
run 1 run "$scene" --out ref1 || fail "reference run on 1 rank"
ref=$(hash_of ref1)
[ -n "$ref" ] || fail "no state hash in ref1/summary.json"
echo "reference state hash (1 rank): $ref"
for n in 2 3 4; do
  run "$n" run "$scene" --out "ref$n" || fail "reference run on $n ranks"
  [ "$(hash_of "ref$n")" = "$ref" ] || fail "uninterrupted run on $n ranks: $(hash_of "ref$n")"
done

# 3a. Checkpointed and restarted on the same rank count.
for n in 1 2 3 4; do
  run "$n" run "$scene" --out "c$n" --checkpoint-every 150 || fail "checkpointed run on $n ranks"
  [ "$(hash_of "c$n")" = "$ref" ] || fail "checkpoints changed the run on $n ranks"
  run "$n" run --restart "$(ckpt "c$n" 150)" --out "r$n" || fail "restart on $n ranks"
  [ "$(hash_of "r$n")" = "$ref" ] || fail "restart on $n ranks: $(hash_of "r$n")"
done

# 2. The history the continuation depends on is in the checkpoint.
/usr/bin/python3 - "$(ckpt c2 150)" << 'PY' || fail "checkpoint of step 150 lacks the laws' history"
import sys
import h5py
import numpy as np
with h5py.File(sys.argv[1], "r") as f:
    assert int(f.attrs["format_version"]) >= 5, "format version"
    state = np.asarray(f["/subcontacts/law_state"])
# coulomb-residual rows hold 1 (broken) in column 0 and 0 in column 1; barton-bandis rows a
# shear displacement > 0 in column 0 and, with dilation, an opening != 0 in column 1.
broken = int(np.sum((state[:, 0] == 1.0) & (state[:, 1] == 0.0)))
sheared = int(np.sum(state[:, 1] != 0.0))
print("sub-contacts: %d, broken: %d, sheared with dilation: %d" % (len(state), broken, sheared))
assert broken > 0 and sheared > 0
PY

# 3b. Across rank counts: written on 2 ranks, restarted on 3 and on 1.
for n in 3 1; do
  run "$n" run --restart "$(ckpt c2 150)" --out "x$n" || fail "restart of the 2-rank file on $n"
  [ "$(hash_of "x$n")" = "$ref" ] || fail "2-rank checkpoint restarted on $n ranks: $(hash_of "x$n")"
done

# 4. A version-4 checkpoint of coulomb joints.
run 1 run "$coulomb" --out v4ref --steps 200 || fail "coulomb-joint reference"
run 2 run "$coulomb" --out v4 --steps 200 --checkpoint-every 100 || fail "coulomb-joint checkpoints"
cp "$(ckpt v4 100)" v4.h5
/usr/bin/python3 - v4.h5 "$summary" << 'PY' || fail "could not rewrite the file as version 4"
import importlib.util
import sys
import h5py
import numpy as np
spec = importlib.util.spec_from_file_location("summary", sys.argv[2])
summary = importlib.util.module_from_spec(spec)
spec.loader.exec_module(summary)
with h5py.File(sys.argv[1], "r+") as f:
    del f["/subcontacts/law_state"]
    del f["/bolts"]
    f.attrs["format_version"] = np.int32(4)
    stream, _ = summary.digest_walk(f)
    f.attrs["digest"] = np.uint64(summary.bytes_checksum(stream))
PY
run 3 run --restart v4.h5 --out v4r --steps 200 || fail "restart from a version-4 file"
[ "$(hash_of v4r)" = "$(hash_of v4ref)" ] || fail "version-4 restart: other bits"

[ $failures = 0 ] && echo "all joint-law restarts bit-exact"
exit $((failures > 0))
