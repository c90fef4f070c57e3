#!/bin/bash
# One flipped bit in a checkpoint is a clear error and never a crash (docs/checkpoint.md,
# "Inspecting"): `polydem checkpoint info` and `polydem run --restart` on 1 and 2 ranks end with
# exit status 1 on every rank (not 134 or 139: no abort, no double free when HDF5 is closed
# before MPI_Finalize), exactly one error line that names the file, and no HDF5 error stack.
# Flipped: the attribute values of the root group, the run state text, and every 2039th byte of
# the file's first 12 kB (superblock, object headers, link and attribute messages); there a
# flip in unused padding may go unnoticed (status 0 on every rank), which is all the test then
# asks. With h5py, also the data of /particles/position and /contacts/shear_force.
# usage: checkpoint_bitflip_cli_test.sh POLYDEM MPIEXEC SCENE WORKDIR
set -u
polydem=$1; mpiexec="$2 --oversubscribe"; scene=$3; work=$4
[ "$(id -u)" = 0 ] && mpiexec="$mpiexec --allow-run-as-root"
rm -rf "$work"; mkdir -p "$work"; cd "$work" || exit 1
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

timeout 120 $mpiexec -n 2 "$polydem" run "$scene" --out good --checkpoint-every 300 \
  --no-snapshots --quiet || fail "the run that writes the checkpoint"
good=$(ls good/checkpoints/checkpoint_000000000300_*.h5 2> /dev/null | head -1)  # the run id follows the step
[ -f "$good" ] || { echo "FAIL: no checkpoint $good"; exit 1; }

# flip OFFSET: a copy of the good file with bit 4 of byte OFFSET flipped, as flipped.h5.
flip() {
  python3 -c "
import sys
data = bytearray(open(sys.argv[1], 'rb').read())
data[int(sys.argv[2])] ^= 0x10
open('flipped.h5', 'wb').write(data)" "$good" "$1"
}
# check NAME MUST_FAIL NP ARGS...: polydem on NP ranks (each rank's status in NAME.rc.RANK).
check() {
  local name=$1 must_fail=$2 np=$3 r status first
  shift 3
  rm -f "$name".rc.*
  timeout 120 $mpiexec -n "$np" bash -c '"$@"; echo $? > "'"$name"'.rc.$OMPI_COMM_WORLD_RANK"' \
    _ "$polydem" "$@" > "$name.log" 2>&1
  first=$(cat "$name.rc.0" 2> /dev/null)
  for ((r = 0; r < np; r++)); do
    status=$(cat "$name.rc.$r" 2> /dev/null)
    [ "$status" = 1 ] || { [ "$status" = 0 ] && [ "$must_fail" = no ]; } ||
      fail "$name: rank $r exit status '$status': $(grep -v '^ ' "$name.log" | head -5)"
    [ "$status" = "$first" ] || fail "$name: rank $r status $status, rank 0 $first"
  done
  if [ "$first" = 1 ]; then
    [ "$(grep -c '^error: ' "$name.log")" = 1 ] && grep -q '^error: .*flipped.h5' "$name.log" ||
      fail "$name: not one error line naming the file: $(head -5 "$name.log")"
    ! grep -q "HDF5-DIAG\|free()\|Signal:" "$name.log" || fail "$name: noise: $(head -20 "$name.log")"
  fi
}
# try NAME OFFSET MUST_FAIL: the flip read by `checkpoint info` on 1 and 2 ranks, and by a
# restart on 2 ranks where it must fail.
try() {
  flip "$2"
  check "$1_info1" "$3" 1 checkpoint info flipped.h5
  check "$1_info2" "$3" 2 checkpoint info flipped.h5
  [ "$3" = no ] ||
    check "$1_restart2" "$3" 2 run --restart flipped.h5 --out "restart_$1" --no-snapshots --quiet
}

offset_of() { python3 -c "import sys; print(open(sys.argv[1], 'rb').read().find(sys.argv[2].encode()))" "$good" "$1"; }
for text in polydem-checkpoint polydem-sum64 '"kernel"'; do
  at=$(offset_of "$text")
  [ "$at" -ge 0 ] || { fail "no '$text' in $good"; continue; }
  try "text_${at}" $((at + 3)) yes
done
size=$(stat -c %s "$good")
for ((at = 0; at < 12288 && at < size; at += 2039)); do try "byte_$at" $at no; done
if /usr/bin/python3 -c "import h5py" 2> /dev/null; then
  for dataset in /particles/position /contacts/shear_force; do
    at=$(/usr/bin/python3 -c "import h5py, sys; print(h5py.File(sys.argv[1], 'r')[sys.argv[2]].id.get_offset() + 8)" "$good" $dataset)
    try "data_${dataset//\//_}" "$at" yes
  done
else
  echo "h5py missing: the flips in dataset data are left to ctest checkpoint_errors"
fi

[ $failures = 0 ] && echo "all bit-flip checks passed"
exit $((failures > 0))
