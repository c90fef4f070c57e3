#!/bin/bash
# Files polydem did not write are never touched (docs/checkpoint.md, 'One run per output folder'):
#  1. a second run into a folder that a running run holds is refused, on 1 and on 2 ranks, with
#     a message naming the holder and a non-zero exit, and the first run's files stay as they were;
#  2. the lock the first run leaves when it is killed (kill -9) is recognised as stale and taken
#     over with a message by the next run into the folder;
#  3. checkpoint rotation (--checkpoint-keep) deletes only the current run's checkpoints: the
#     checkpoints of an earlier run into the same folder (killed, or finished), and of the run a
#     --restart into the same folder continues, stay, byte for byte, also those of the same steps.
# usage: output_folder_cli_test.sh POLYDEM MPIEXEC SCENE WORKDIR
set -u
polydem=$1; mpiexec="$2 --oversubscribe"; scene=$3; work=$4
[ "$(id -u)" = 0 ] && mpiexec="$mpiexec --allow-run-as-root"
rm -rf "$work"; mkdir -p "$work"; cd "$work" || exit 1
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
field() { python3 -c "import json,sys; print(json.load(open(sys.argv[1]))[sys.argv[2]])" "$@"; }
mp() { timeout 120 $mpiexec -n "$1" "$polydem" "${@:2}"; }
run() { mp "$@" --no-snapshots --quiet; }
# Every file of a folder with its checksum, one per line (to see that nothing changed).
sums() { (cd "$1" && find . -type f -print0 | sort -z | xargs -0 -r cksum); }
count() { find "$1" -maxdepth 1 -name "$2" | wc -l; }

# 1. A run that holds busy/ (paused after its last step, its checkpoints written) ...
POLYDEM_TEST_PAUSE=after-run:120 "$polydem" run "$scene" --out busy --checkpoint-every 50 \
  --checkpoint-keep 2 --no-snapshots --quiet 2> busy.log &
holder=$!
for _ in $(seq 1200); do grep -q "test pause: after-run" busy.log && break; sleep 0.1; done
grep -q "test pause: after-run" busy.log || fail "the first run never reached its pause"
[ -f busy/polydem.lock ] || fail "no lock file in the folder of a running run"
grep -q "^pid $holder$" busy/polydem.lock || fail "the lock does not name the run: $(cat busy/polydem.lock)"
[ "$(count busy/checkpoints 'checkpoint_*.h5')" = 2 ] || fail "expected the first run's 2 checkpoints"
before=$(sums busy)
# ... refuses a second run, on 1 and on 2 ranks: non-zero exit, the holder named, nothing touched.
for np in 1 2; do
  run $np run "$scene" --out busy --checkpoint-every 50 --checkpoint-keep 1 > second_$np.log 2>&1 &&
    fail "a second run into a busy folder on $np rank(s) was accepted"
  grep -q "error: output folder busy is in use: busy/polydem.lock names process $holder on host .*, which is still running" \
    second_$np.log || fail "second run on $np rank(s): $(cat second_$np.log)"
  [ "$(grep -c "is in use" second_$np.log)" = 1 ] || fail "the message is not printed once: $(cat second_$np.log)"
  [ "$(sums busy)" = "$before" ] || fail "the refused run on $np rank(s) changed the first run's files"
done
# A restart into the busy folder is refused too.
run 1 run --restart "$(ls busy/checkpoints/checkpoint_*.h5 | head -1)" --out busy > restart_busy.log 2>&1 &&
  fail "a restart into a busy folder was accepted"
grep -q "is in use" restart_busy.log || fail "restart into a busy folder: $(cat restart_busy.log)"
[ "$(sums busy)" = "$before" ] || fail "the refused restart changed the first run's files"

# 2. The first run killed: its lock is stale and the next run takes it over.
kill -9 $holder; wait $holder 2> /dev/null
grep -q "^pid $holder$" busy/polydem.lock || fail "kill -9 should leave the lock behind"
first_sums=$(cd busy/checkpoints && cksum checkpoint_*.h5)
run 1 run "$scene" --out busy --checkpoint-every 50 --checkpoint-keep 1 > third.log 2>&1 ||
  fail "the run after the killed one: $(cat third.log)"
grep -q "took over busy/polydem.lock from process $holder on host .*, which is gone" third.log ||
  fail "no message about the stale lock: $(cat third.log)"
[ ! -e busy/polydem.lock ] || fail "the lock is left after the run"
# 3. It kept 1 of its own checkpoints and left both of the killed run's (steps 250 and 300; its
# own step-300 file has another name).
id=$(field busy/summary.json checkpoint_run_id)
[ "$(count busy/checkpoints "checkpoint_*_$id.h5")" = 1 ] || fail "the run kept other than 1 of its own"
[ -f busy/checkpoints/checkpoint_000000000300_$id.h5 ] || fail "the run's last checkpoint is missing"
[ "$(cd busy/checkpoints && cksum $(echo "$first_sums" | awk '{print $3}'))" = "$first_sums" ] ||
  fail "rotation touched the killed run's checkpoints: $(ls busy/checkpoints)"
[ "$(count busy/checkpoints 'checkpoint_*.h5')" = 3 ] || fail "expected 2 + 1 checkpoints: $(ls busy/checkpoints)"

# Two finished runs in sequence into one folder: the second prunes only its own.
run 2 run "$scene" --out seq --checkpoint-every 100 --checkpoint-keep 3 || fail "first finished run"
first_id=$(field seq/summary.json checkpoint_run_id)
first_sums=$(cd seq/checkpoints && cksum checkpoint_*.h5)
[ "$(count seq/checkpoints "checkpoint_*_$first_id.h5")" = 3 ] || fail "first run: not 3 checkpoints"
run 1 run "$scene" --out seq --checkpoint-every 50 --checkpoint-keep 2 || fail "second finished run"
second_id=$(field seq/summary.json checkpoint_run_id)
[ "$second_id" != "$first_id" ] || fail "two runs with the same id $first_id"
[ "$(count seq/checkpoints "checkpoint_*_$second_id.h5")" = 2 ] || fail "second run: not 2 kept"
[ "$(cd seq/checkpoints && cksum checkpoint_*_$first_id.h5)" = "$first_sums" ] ||
  fail "the second run touched the first run's checkpoints"

# A restart into the folder of the run it continues: a new run id, the old run's files stay.
cp -r seq cont
old_sums=$(cd cont/checkpoints && cksum checkpoint_*.h5)
run 2 run --restart cont/checkpoints/checkpoint_000000000200_$first_id.h5 --out cont \
  --checkpoint-every 20 --checkpoint-keep 1 || fail "restart into its own folder"
cont_id=$(field cont/summary.json checkpoint_run_id)
[ "$cont_id" != "$first_id" ] && [ "$cont_id" != "$second_id" ] || fail "the restart reused a run id"
[ "$(count cont/checkpoints "checkpoint_*_$cont_id.h5")" = 1 ] || fail "restart: not 1 of its own kept"
[ "$(cd cont/checkpoints && cksum $(echo "$old_sums" | awk '{print $3}'))" = "$old_sums" ] ||
  fail "the restart's rotation touched the checkpoints of the earlier runs"

[ $failures = 0 ] && echo "all output folder checks passed"
exit $((failures > 0))
