#!/bin/bash
# Water in the joints is a load on each free block that depends only on that block and the time
# (sim/water.h): a jointed rock mass (J-JOINTED-MASS) with a moving inclined phreatic surface
# ends with the same state hash on 1 and 3 ranks and after a restart on another rank count, and
# with another one than the dry mass (the water acts).
# usage: water_ranks_test.sh POLYDEM MPIEXEC SCENE WORKDIR
set -u
polydem=$(realpath "$1"); mpiexec="$2 --oversubscribe"; dry_scene=$(realpath "$3"); work=$4
[ "$(id -u)" = 0 ] && mpiexec="$mpiexec --allow-run-as-root"
rm -rf "$work"; mkdir -p "$work"; cd "$work" || exit 1
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
hash_of() { python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['state_hash'])" \
  "$1/summary.json" 2> /dev/null; }
run() { timeout 300 $mpiexec -n "$1" "$polydem" "${@:2}" --no-snapshots --quiet --steps 300; }
ckpt() { set -- "$(printf '%s/checkpoints/checkpoint_%012d_' "$1" "$2")"; set -- "$1"*.h5; echo "$1"; }

scene=wet.toml
cp "$dry_scene" "$scene"
cat >> "$scene" << 'TOML'

[water]
unit_weight = "9.81 kN/m^3"
points = [[0, 0], [10, 0], [0, 10]]
table = [[0, 3.0, 1.0, 2.0], [0.01, 4.0, 0.0, 2.5]]
TOML

run 1 run "$scene" --out one || fail "wet run on 1 rank"
run 3 run "$scene" --out three || fail "wet run on 3 ranks"
run 1 run "$dry_scene" --out dry || fail "dry run"
run 2 run "$scene" --out a --checkpoint-every 150 || fail "checkpointed run on 2 ranks"
run 3 run --restart "$(ckpt a 150)" --out r3 || fail "restart on 3 ranks"
echo "wet 1 rank $(hash_of one), 3 ranks $(hash_of three), 2 ranks $(hash_of a)," \
  "restarted on 3 $(hash_of r3); dry $(hash_of dry)"
[ -n "$(hash_of one)" ] || fail "no state hash"
[ "$(hash_of three)" = "$(hash_of one)" ] || fail "3 ranks: other bits than 1 rank"
[ "$(hash_of a)" = "$(hash_of one)" ] || fail "2 ranks: other bits than 1 rank"
[ "$(hash_of r3)" = "$(hash_of one)" ] || fail "restart on 3 ranks: other bits"
[ "$(hash_of dry)" != "$(hash_of one)" ] || fail "the water changed nothing"
[ $failures = 0 ] && echo "all checks passed"
exit $((failures > 0))
