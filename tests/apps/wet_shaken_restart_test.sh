#!/bin/bash
# A bolted, wet slope shaken by an acceleration record restarts bit-exact on another rank count
# (wet_shaken_slope.toml: water in the joints, the fixed rock moved by a record, free blocks held
# by a bolt):
#  1. the uninterrupted run ends with the same state hash on 1 and 2 ranks;
#  2. written on 2 ranks with a checkpoint at step 200 (the ground still moving), restarted on 1
#     and on 3 ranks, it ends with that hash: the ground's motion is a function of the time alone
#     and the fixed blocks' positions and velocities are in the checkpoint (sim/ground_motion.h);
#  3. without its [seismic] record, or without its bolt, the run ends with another hash (each
#     acts).
# usage: wet_shaken_restart_test.sh POLYDEM MPIEXEC SCENE WORKDIR
set -u
polydem=$(realpath "$1"); mpiexec="$2 --oversubscribe"; scene=$(realpath "$3"); work=$4
[ "$(id -u)" = 0 ] && mpiexec="$mpiexec --allow-run-as-root"
rm -rf "$work"; mkdir -p "$work"; cd "$work" || exit 1
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
hash_of() { /usr/bin/python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['state_hash'])" \
  "$1/summary.json" 2> /dev/null; }
run() { timeout 300 $mpiexec -n "$1" "$polydem" "${@:2}" --no-snapshots --quiet; }
ckpt() { set -- "$(printf '%s/checkpoints/checkpoint_%012d_' "$1" "$2")"; set -- "$1"*.h5; echo "$1"; }

run 1 run "$scene" --out ref1 || fail "uninterrupted run on 1 rank"
ref=$(hash_of ref1)
[ -n "$ref" ] || fail "no state hash in ref1/summary.json"
echo "uninterrupted (1 rank): $ref"
run 2 run "$scene" --out c2 --checkpoint-every 200 || fail "checkpointed run on 2 ranks"
[ "$(hash_of c2)" = "$ref" ] || fail "2 ranks with checkpoints: $(hash_of c2)"
for n in 1 3; do
  run "$n" run --restart "$(ckpt c2 200)" --out "r$n" || fail "restart on $n ranks"
  echo "restarted on $n ranks: $(hash_of "r$n")"
  [ "$(hash_of "r$n")" = "$ref" ] || fail "2-rank checkpoint restarted on $n ranks: $(hash_of "r$n")"
done

# The same slope without the record, and without the bolt (each section runs to a blank line).
sed '/^\[seismic\]/,/^$/d' "$scene" > still.toml
sed '/^\[\[bolt\]\]/,/^$/d' "$scene" > unbolted.toml
cp "$(dirname "$scene")/wet_shaken_record.csv" .  # the record, beside the copies that use it
run 1 run still.toml --out still || fail "run without the record"
echo "without the record: $(hash_of still)"
[ -n "$(hash_of still)" ] && [ "$(hash_of still)" != "$ref" ] || fail "the record changed nothing"
grep -q '^\[\[bolt\]\]' "$scene" || fail "the scene has no bolt"
run 1 run unbolted.toml --out unbolted || fail "run without the bolt"
echo "without the bolt: $(hash_of unbolted)"
[ -n "$(hash_of unbolted)" ] && [ "$(hash_of unbolted)" != "$ref" ] || fail "the bolt changed nothing"

[ $failures = 0 ] && echo "the wet shaken slope restarts bit-exact"
exit $((failures > 0))
