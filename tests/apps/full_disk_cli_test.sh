#!/bin/bash
# Full disks end cleanly (docs/checkpoint.md "A full disk", docs/output-files.md): on a small
# tmpfs mounted by the test, a snapshot, a checkpoint and series.csv that do not fit end the run
# on 1 and on 2 ranks with exit status 1 on every rank (no crash, no MPI_Abort, no deadlock: each
# run has a time limit), one message that names the file and says "no space left on device", no
# temporary file left, and an earlier checkpoint in the folder intact: it verifies and a run
# continues from it once there is room again. The checkpoint is tried with the disk full before
# the write (refused from its estimate) and with the disk filling while it is written (the test
# hook POLYDEM_TEST_PAUSE holds the write after its file is created while the test fills the
# disk); the snapshot with room for its first part only. These two write a scene of 1,800 smaller
# cubes, whose files are larger than the room a file takes ahead of its data (128 KiB), so that
# they fail in the middle. Skipped (exit 77) where a tmpfs cannot be mounted (not root, no
# CAP_SYS_ADMIN).
# usage: full_disk_cli_test.sh POLYDEM MPIEXEC SCENE WORKDIR
set -u
polydem=$1; mpiexec="$2 --oversubscribe"; scene=$3; work=$4
[ "$(id -u)" = 0 ] && mpiexec="$mpiexec --allow-run-as-root"
export OMPI_MCA_mpi_yield_when_idle=1  # a rank waiting for a paused one lets it have the core
rm -rf "$work"; mkdir -p "$work/disk"; cd "$work" || exit 1
disk=disk
if ! mount -t tmpfs -o size=4m tmpfs "$disk" 2> mount.err; then
  echo "SKIP: cannot mount a tmpfs on $work/$disk: $(cat mount.err)"
  exit 77
fi
trap 'cd "$work" && umount "$disk"' EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
# The name of run DIR's checkpoint of step S, as a pattern (each run has its own run id).
ckpt() { printf '%s/checkpoints/checkpoint_%012d_[0-9a-f]*.h5' "$1" "$2"; }
free_bytes() { df --output=avail -B1 "$disk" | tail -1; }
# fill KEEP: a filler file leaves KEEP bytes of the tmpfs free.
fill() {
  rm -f "$disk/filler"
  local size=$(($(free_bytes) - $1))
  [ $size -le 0 ] || fallocate -l $size "$disk/filler" || fail "cannot fill the disk"
}
# ranks NP NAME ARGS...: runs polydem on NP ranks (at most 120 s); each rank's exit status in
# NAME.rc.RANK, the output in NAME.log.
ranks() {
  local np=$1 name=$2
  shift 2
  rm -f "$name".rc.*
  timeout 120 $mpiexec -n "$np" bash -c '"$@"; echo $? > "'"$name"'.rc.$OMPI_COMM_WORLD_RANK"' \
    _ "$polydem" "$@" > "$name.log" 2>&1
  echo $? > "$name.rc.mpirun"
}
# ended NP NAME FILE: every rank ended with exit status 1 and the message names FILE and the
# cause; no temporary file is left under the output folder DIR.
ended() {
  local np=$1 name=$2 file=$3 dir=$4 r
  [ "$(cat "$name.rc.mpirun")" != 124 ] || fail "$name: still running after 120 s (deadlock?)"
  for ((r = 0; r < np; r++)); do
    [ "$(cat "$name.rc.$r" 2> /dev/null)" = 1 ] ||
      fail "$name: rank $r exit status '$(cat "$name.rc.$r" 2> /dev/null)' (1 expected): $(tail -5 "$name.log")"
  done
  grep -i "error: .*$file.*no space left on device" "$name.log" > /dev/null ||
    fail "$name: no message naming $file and the full disk: $(tail -5 "$name.log")"
  [ "$(grep -c "^error: " "$name.log")" = 1 ] || fail "$name: not one error line: $(cat "$name.log")"
  [ -z "$(find "$dir" -name '*.tmp*')" ] || fail "$name: temporary files left: $(find "$dir" -name '*.tmp*')"
}

# The scene with 1,800 cubes of 0.3 m instead of 72 of 1 m (checkpoint 260 kB, snapshot 2.3 MB).
sed -e 's/^edge = "1 m"/edge = "0.3 m"/' -e 's/^spacing = 1.002/spacing = 0.3006/' \
  -e 's/^count = \[6, 6, 1\]/count = [30, 30, 1]/' -e 's/^origin = \[0.5, 0.5, 0.5002\]/origin = [0.5, 0.5, 0.1502]/' \
  -e 's/^origin = \[0.5, 0.5, 1.5006\]/origin = [0.5, 0.5, 0.4508]/' "$scene" > big.toml
[ "$(grep -c '0.3006\|0.3 m\|30, 30' big.toml)" = 5 ] || fail "big.toml: $(cat big.toml)"

# An earlier checkpoint, from a run on a disk with room.
timeout 120 $mpiexec -n 1 "$polydem" run "$scene" --out pre --checkpoint-every 100 --checkpoint-keep 3 \
  --no-snapshots --quiet || fail "the run that writes the earlier checkpoint"
earlier=$(ls pre/checkpoints/checkpoint_000000000100_*.h5)
earlier_name=$(basename "$earlier")

for np in 1 2; do
  # A snapshot that does not fit (parallel HDF5 + XDMF): the first one, at the start.
  rm -rf "$disk"/*
  fill $((1024 * 1024))
  ranks $np snap$np run big.toml --out "$disk/snap$np" --steps 20 --quiet
  ended $np snap$np "snapshot $disk/snap$np/snapshots/snapshot_0000000000.h5" "$disk/snap$np"

  # A checkpoint on a disk without room for it: refused before its file is created.
  rm -rf "$disk"/*
  mkdir -p "$disk/pre$np/checkpoints"
  cp "$earlier" "$disk/pre$np/checkpoints/$earlier_name"
  fill $((64 * 1024))
  ranks $np pre$np run --restart "$disk/pre$np/checkpoints/$earlier_name" --out "$disk/pre$np" \
    --checkpoint-every 50 --no-snapshots --quiet
  ended $np pre$np "checkpoint $(ckpt "$disk/pre$np" 150)" "$disk/pre$np"
  cmp -s "$earlier" "$disk/pre$np/checkpoints/$earlier_name" || fail "pre$np: the earlier checkpoint changed"

  # A checkpoint on a disk that fills while it is written.
  rm -rf "$disk"/*
  out=$disk/during$np
  mkdir -p "$out/checkpoints"
  cp "$earlier" "$out/checkpoints/$earlier_name"
  rm -f during$np.rc.*
  (
    export POLYDEM_TEST_PAUSE=checkpoint-write:4
    ranks $np during$np run big.toml --out "$out" --checkpoint-every 50 --no-snapshots --quiet
  ) &
  pid=$!
  for _ in $(seq 600); do grep -q "test pause: checkpoint-write" during$np.log 2> /dev/null && break; sleep 0.1; done
  grep -q "test pause: checkpoint-write" during$np.log || fail "during$np: the write never paused"
  fill 0
  wait $pid
  ended $np during$np "checkpoint $(ckpt $out 50)" "$out"
  cmp -s "$earlier" "$out/checkpoints/$earlier_name" || fail "during$np: the earlier checkpoint changed"
  # Once there is room again, the earlier checkpoint verifies and the run continues from it.
  rm -f "$disk/filler"
  timeout 120 $mpiexec -n $np "$polydem" checkpoint info "$out/checkpoints/$earlier_name" > during$np.info 2>&1 ||
    fail "during$np: the earlier checkpoint does not verify: $(cat during$np.info)"
  timeout 120 $mpiexec -n $np "$polydem" run --restart "$out/checkpoints/$earlier_name" --out "$out" \
    --checkpoint-every 50 --no-snapshots --quiet > during$np.cont.log 2>&1 ||
    fail "during$np: no run continues from the earlier checkpoint: $(tail -5 during$np.cont.log)"

  # series.csv that does not fit: its header does (one page of the tmpfs), its rows do not.
  rm -rf "$disk"/*
  sed 's/^series_every = .*/series_every = 1/' "$scene" > series.toml
  fill 4096
  ranks $np series$np run series.toml --out "$disk/series$np" --no-snapshots --quiet
  ended $np series$np "$disk/series$np/series.csv" "$disk/series$np"
done

[ $failures = 0 ] && echo "all full-disk checks passed"
exit $((failures > 0))
