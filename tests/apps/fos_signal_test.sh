#!/bin/bash
# `polydem fos` stopped by a signal and continued (docs/scene-format.md, "Stopping and
# continuing"): SIGTERM or SIGINT to the process on 1 rank, SIGTERM to scripts/polydem-mpirun on
# 2 ranks (two trials at a time), each sent once the first round of trials is done, and SIGUSR1
# in the middle of the first trial (held there by the test hook POLYDEM_TEST_PAUSE=fos-trial,
# core/test_pause.h), which then ends after its step and is not kept. Every time:
# exit status 0, fos.json with the finished trials and "complete": false, the command that
# continues printed; `polydem fos --resume DIR` then finds the same factor of safety, bit for
# bit, as a search that was never stopped (trials are deterministic and the continuation tries
# the same factors). A scene file changed in between is refused, as is resuming a complete search.
# usage: fos_signal_test.sh POLYDEM MPIEXEC WRAPPER SCENE WORKDIR
set -u
polydem=$1; wrapper=$3; scene=$4; work=$5
export MPIRUN="$2 --oversubscribe"
[ "$(id -u)" = 0 ] && MPIRUN="$MPIRUN --allow-run-as-root"
export OMPI_MCA_mpi_yield_when_idle=1
export POLYDEM_STOP_GRACE_SECONDS=${POLYDEM_STOP_GRACE_SECONDS:-20}
rm -rf "$work"; mkdir -p "$work"; cd "$work" || exit 1
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
field() {  # repr() of a field of a JSON file: floats with every digit
  /usr/bin/python3 -c "import json,sys; print(repr(json.load(open(sys.argv[1]))[sys.argv[2]]))" "$@"
}
waitfor() {  # log pattern: up to 120 s
  for _ in $(seq 1200); do grep -q "$2" "$1" && return 0; sleep 0.1; done
  return 1
}
cp "$scene" scene.toml
options=(--resolution 0.05)  # a few rounds: enough to stop in the middle of the search

# stopped NAME SIGNAL RANKS [mid-trial]: a search stopped by SIGNAL after its first round (or
# during its first trial), then continued.
stopped() {
  # After a round, every trial waits 1 s before its first step, so that the signal is sure to
  # arrive while the search goes on (this scene's trials take a hundredth of a second each: a
  # signal sent after the first round could otherwise find the search, and the mechanism's
  # rerun, over).
  local name=$1 sig=$2 ranks=$3 when=${4:-after-round} launch=() pause=fos-trial:1 pattern="  F = "
  [ "$ranks" -gt 1 ] && launch=("$wrapper" -n "$ranks")
  [ "$when" = mid-trial ] && pause=fos-trial:2 pattern="test pause: fos-trial"
  POLYDEM_TEST_PAUSE=$pause "${launch[@]}" "$polydem" fos scene.toml --out "$name" "${options[@]}" \
    > "$name.log" 2>&1 &
  local pid=$!
  waitfor "$name.log" "$pattern" || fail "$name: never reached '$pattern': $(cat "$name.log")"
  kill -"$sig" $pid
  wait $pid
  local rc=$?
  [ $rc = 0 ] || fail "$name: exit status $rc after SIG$sig: $(tail -5 "$name.log")"
  [ "$(field "$name/fos.json" complete)" = False ] || fail "$name: fos.json not marked incomplete"
  local expect=SIG$sig
  [ "$ranks" -gt 1 ] && expect=SIGUSR1  # what the wrapper sends on
  [ "$(field "$name/fos.json" stop_signal)" = "'$expect'" ] || fail "$name: stop_signal"
  local kept
  kept=$(/usr/bin/python3 -c "import json,sys; print(len(json.load(open(sys.argv[1]))['trials']))" \
    "$name/fos.json")
  if [ "$when" = mid-trial ]; then
    [ "$kept" = 0 ] || fail "$name: the interrupted trial was kept ($kept trials)"
    grep -q "^  F = " "$name.log" && fail "$name: a trial was reported"
  else
    [ "$kept" -gt 0 ] || fail "$name: no finished trial kept"
  fi
  grep -q "to continue: mpirun -n $ranks .*polydem fos --resume $name" "$name.log" ||
    fail "$name: no resume command printed: $(tail -3 "$name.log")"
  "${launch[@]}" "$polydem" fos --resume "$name" > "$name.resume.log" 2>&1 ||
    fail "$name: --resume: $(tail -3 "$name.resume.log")"
  [ "$(field "$name/fos.json" complete)" = True ] || fail "$name: not complete after --resume"
}

"$polydem" fos scene.toml --out ref1 "${options[@]}" > ref1.log 2>&1 || fail "reference, 1 rank"
"$wrapper" -n 2 "$polydem" fos scene.toml --out ref2 "${options[@]}" > ref2.log 2>&1 ||
  fail "reference, 2 ranks"
f1=$(field ref1/fos.json factor_of_safety)
f2=$(field ref2/fos.json factor_of_safety)
[ "$f1" != None ] && [ "$f2" != None ] || fail "references not bracketed: $f1, $f2"

stopped term1 TERM 1
stopped int1 INT 1
stopped wrapper2 TERM 2
stopped usr1_mid USR1 1 mid-trial
for name in term1 int1 usr1_mid; do
  [ "$(field $name/fos.json factor_of_safety)" = "$f1" ] ||
    fail "$name: F = $(field $name/fos.json factor_of_safety), uninterrupted $f1"
done
[ "$(field wrapper2/fos.json factor_of_safety)" = "$f2" ] ||
  fail "wrapper2: F = $(field wrapper2/fos.json factor_of_safety), uninterrupted $f2"

# Resuming a complete search, or with a scene file changed since the trials: refused.
"$polydem" fos --resume term1 > complete.log 2>&1
[ $? = 2 ] && grep -q "complete: there is nothing to resume" complete.log ||
  fail "resuming a complete search: $(cat complete.log)"
POLYDEM_TEST_PAUSE=fos-trial:1 "$polydem" fos scene.toml --out changed "${options[@]}" > changed.log 2>&1 &
pid=$!
waitfor changed.log "  F = " || fail "changed: no trial finished"
kill -TERM $pid
wait $pid
echo "# edited" >> scene.toml
cp changed/fos.json changed.before
"$polydem" fos --resume changed > changed.resume.log 2>&1
[ $? = 1 ] && grep -q "scene.toml: the scene file changed since the trials" changed.resume.log ||
  fail "changed scene: $(cat changed.resume.log)"
cmp -s changed/fos.json changed.before || fail "changed scene: fos.json was rewritten"

[ $failures = 0 ] && echo "all fos signal checks passed (F = $f1 on 1 rank, $f2 on 2)"
exit $((failures > 0))
