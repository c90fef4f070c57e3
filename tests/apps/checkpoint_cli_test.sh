#!/bin/bash
# Checkpoint/restart through the polydem executable (docs/checkpoint.md):
#  1. checkpoints every 50 steps, pruned to --checkpoint-keep; restarts from the equilibrium and
#     the main stage on other rank counts end with the state hash of an uninterrupted run;
#  2. `polydem checkpoint info` verifies a file on any rank count;
#  3. a scene that differs (other than its stop settings) is refused, nothing is written;
#  4. kill -9 between the collective write and the rename leaves the previous checkpoint intact,
#     and the next start takes over the killed run's lock of the folder and removes the temporary
#     file it left (and nothing else);
#  5. corrupt files (truncated, flipped byte, wrong version, missing dataset) are refused;
# (Signals: signal_cli_test.sh.)
# usage: checkpoint_cli_test.sh POLYDEM MPIEXEC SCENE WORKDIR
set -u
polydem=$1; mpiexec="$2 --oversubscribe"; scene=$3; work=$4
[ "$(id -u)" = 0 ] && mpiexec="$mpiexec --allow-run-as-root"
rm -rf "$work"; mkdir -p "$work"; cd "$work" || exit 1
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
field() { python3 -c "import json,sys; print(json.load(open(sys.argv[1]))[sys.argv[2]])" "$@"; }
hash_of() { field "$1/summary.json" state_hash 2> /dev/null; }
mp() { timeout 120 $mpiexec -n "$1" "$polydem" "${@:2}"; }
run() { mp "$@" --no-snapshots --quiet; }
# The checkpoint of step $2 in $1/checkpoints, whatever the id of the run that wrote it (one run
# per folder here); the pattern itself, which names no file, if there is none.
ckpt() { set -- "$(printf '%s/checkpoints/checkpoint_%012d_' "$1" "$2")"; set -- "$1"*.h5; echo "$1"; }

# 1. Reference and checkpoints (eq. stage: 100 steps, then 200 main steps = 300 in all).
run 2 run "$scene" --out ref || fail "reference run"
# Its particles cross the rank border: summary.json reports the communication volume.
python3 -c "import json,sys; c=json.load(open(sys.argv[1]))['communication']; sys.exit(not (c['bytes_sent'] > 0 and c['particles_sent'] > 0))" ref/summary.json ||
  fail "summary.json: no communication volume on 2 ranks"
run 2 run "$scene" --out a --checkpoint-every 50 --checkpoint-keep 4 || fail "checkpointed run"
[ "$(hash_of a)" = "$(hash_of ref)" ] || fail "checkpoints changed the run"
n=$(ls a/checkpoints | wc -l)
[ "$n" = 4 ] || fail "expected 4 checkpoints after pruning, found $n"
[ -f "$(ckpt a 150)" ] && [ ! -f "$(ckpt a 100)" ] || fail "pruning kept the wrong files"
run 1 run --restart "$(ckpt a 250)" --out r1 || fail "restart on 1 rank"
[ "$(hash_of r1)" = "$(hash_of ref)" ] || fail "restart on 1 rank: other bits"
# The checks' values (accumulated over the whole run, restored from /run/state) agree too.
[ "$(field r1/summary.json checks)" = "$(field ref/summary.json checks)" ] ||
  fail "restart on 1 rank: check values differ"
run 2 run --checkpoint-keep 100 --checkpoint-every 50 --out eq "$scene" --steps 1 > /dev/null
cp "$(ckpt eq 50)" eq50.h5 || fail "no checkpoint in the equilibrium stage"
run 3 run --restart eq50.h5 "$scene" --out r3 || fail "restart on 3 ranks from the equilibrium stage"
[ "$(hash_of r3)" = "$(hash_of ref)" ] || fail "restart from the equilibrium stage: other bits"
# A longer run continued by --steps.
run 1 run "$scene" --out long --steps 260 || fail "longer reference"
run 2 run --restart "$(ckpt a 300)" --out ext --steps 260 || fail "extended restart"
[ "$(hash_of ext)" = "$(hash_of long)" ] || fail "extended restart: other bits"

# 2. info
mp 3 checkpoint info "$(ckpt a 300)" > info.txt || fail "checkpoint info"
grep -q "^step: 200" info.txt || fail "checkpoint info does not show the step"

# 3. A scene that differs in dt: refused, no output written.
sed 's/^dt = .*/dt = "5e-5 s"/' "$scene" > other.toml
run 2 run --restart "$(ckpt a 300)" other.toml --out bad > bad.log 2>&1 && fail "other dt accepted"
grep -q "\[simulation\] dt" bad.log || fail "mismatch message does not name the key: $(cat bad.log)"
[ ! -e bad/summary.json ] || fail "a refused restart wrote output"
sed 's/^steps = .*/steps = 260/' "$scene" > longer.toml
run 1 run --restart "$(ckpt a 300)" longer.toml --out ext2 || fail "longer scene refused"
[ "$(hash_of ext2)" = "$(hash_of long)" ] || fail "restart with a longer scene: other bits"

# 4. kill -9 between the collective write and the rename.
mkdir -p k/checkpoints; cp "$(ckpt a 250)" k/checkpoints/; before=$(cksum < "$(ckpt k 250)")
POLYDEM_TEST_PAUSE=before-rename:60 "$polydem" run "$scene" --out k --checkpoint-every 50 \
  --checkpoint-keep 1 --no-snapshots --quiet 2> k.log &
pid=$!
for _ in $(seq 600); do grep -q "test pause: before-rename" k.log && break; sleep 0.1; done
grep -q "test pause: before-rename" k.log || fail "the writer never reached the rename"
kill -9 $pid; wait $pid 2> /dev/null
[ "$(cksum < "$(ckpt k 250)")" = "$before" ] || fail "kill -9 changed the previous checkpoint"
[ ! -e "$(ckpt k 50)" ] || fail "a half-written checkpoint has the final name"
mp 2 checkpoint info "$(ckpt k 250)" > /dev/null || fail "previous checkpoint does not verify"
# The next start removes the killed write's temporary file, and only that: files of other names,
# and a temporary file of a writer that still runs (this shell), stay.
stale=$(ls k/checkpoints/checkpoint_000000000050_*.h5.tmp.$pid 2> /dev/null)
[ -f "$stale" ] || fail "kill -9 left no temporary file k/checkpoints/checkpoint_000000000050_*.h5.tmp.$pid"
alive="k/checkpoints/checkpoint_000000000060_0badcafe.h5.tmp.$$"
not_tmp="k/checkpoints/checkpoint_000000000050_0badcafe.h5.tmp.x$pid"
for f in "$alive" k/checkpoints/notes.tmp.$pid "$not_tmp" k/checkpoints/other.h5; do
  echo keep > "$f"
done
run 1 run "$scene" --out k --steps 10 > k2.log 2>&1 || fail "run after kill -9: $(cat k2.log)"
[ ! -e "$stale" ] || fail "the stale temporary file $stale is left"
grep -q "took over k/polydem.lock from process $pid on host .*, which is gone" k2.log ||
  fail "the killed run's lock was not taken over with a message: $(cat k2.log)"
[ ! -e k/polydem.lock ] || fail "the lock of the folder is left after the run"
grep -q "removed $stale" k2.log || fail "no message about the removed file: $(cat k2.log)"
grep -q "left $alive: .* by process $$, which is still running" k2.log ||
  fail "no message about the live writer's file: $(cat k2.log)"
[ "$(cat "$alive" k/checkpoints/notes.tmp.$pid "$not_tmp" k/checkpoints/other.h5)" = \
  "$(printf 'keep\nkeep\nkeep\nkeep')" ] || fail "files of other names were touched"

# 5. Corrupt files: non-zero exit, the file named, nothing written.
good=$(ckpt a 300)
refuse() {  # name file
  run 2 run --restart "$2" --out "c_$1" > "c_$1.log" 2>&1 && fail "$1 accepted"
  grep -q "$2" "c_$1.log" || fail "$1: message does not name the file: $(cat "c_$1.log")"
  [ ! -e "c_$1/summary.json" ] || fail "$1: output written"
  mp 1 checkpoint info "$2" > /dev/null 2>&1 && fail "$1: checkpoint info accepted it"
}
head -c $(( $(stat -c %s "$good") / 2 )) "$good" > truncated.h5; refuse truncated truncated.h5
# Damaged metadata (an object header's checksum fails): one error line, nothing from HDF5 after it
# (HDF5 1.10 reports "infinite loop closing library" at exit unless polydem closes it quietly).
python3 - "$good" header.h5 << 'PY'
import sys
data = bytearray(open(sys.argv[1], "rb").read())
at = data.find(b"polydem-checkpoint")
data[at + 3] ^= 0x10
open(sys.argv[2], "wb").write(data)
PY
refuse header header.h5
for np in 1 2; do
  mp $np checkpoint info header.h5 > /dev/null 2> header_$np.err
  grep -q "^error: checkpoint header.h5: cannot read attribute format of /" header_$np.err ||
    fail "damaged metadata on $np ranks: $(cat header_$np.err)"
  ! grep -q -i "hdf5" header_$np.err || fail "HDF5 noise on $np ranks: $(cat header_$np.err)"
done
# A directory and a FIFO are named as what they are.
mkdir dir.h5; mkfifo fifo.h5
run 1 run --restart dir.h5 --out c_dir > c_dir.log 2>&1 && fail "a directory accepted"
grep -q "checkpoint dir.h5: is a directory" c_dir.log || fail "directory: $(cat c_dir.log)"
run 1 run --restart fifo.h5 --out c_fifo > c_fifo.log 2>&1 && fail "a FIFO accepted"
grep -q "checkpoint fifo.h5: is a FIFO" c_fifo.log || fail "FIFO: $(cat c_fifo.log)"
if /usr/bin/python3 -c "import h5py" 2> /dev/null; then
  /usr/bin/python3 - "$good" << 'PY'
import shutil, sys, h5py
good = sys.argv[1]
for name in ("flipped", "version", "missing"):
    shutil.copy(good, name + ".h5")
with h5py.File("flipped.h5", "r") as f:
    offset = f["/particles/position"].id.get_offset()
with open("flipped.h5", "r+b") as f:
    f.seek(offset + 8); b = f.read(1); f.seek(offset + 8); f.write(bytes([b[0] ^ 0x10]))
with h5py.File("version.h5", "r+") as f:
    f.attrs["format_version"] = f.attrs["format_version"] + 1
with h5py.File("missing.h5", "r+") as f:
    del f["/contacts/shear_force"]
PY
  refuse flipped flipped.h5; refuse version version.h5; refuse missing missing.h5
else
  echo "h5py missing: flipped byte, version and missing dataset cases left to checkpoint_errors"
fi

[ $failures = 0 ] && echo "all checkpoint CLI checks passed"
exit $((failures > 0))
