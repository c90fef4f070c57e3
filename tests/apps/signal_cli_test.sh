#!/bin/bash
# Stopping a run with a signal (docs/checkpoint.md, "Stopping on a signal"):
# SIGTERM and SIGUSR1, sent to mpirun, to every rank, or to the launch wrapper
# scripts/polydem-mpirun, during the start-up (before any file is read), while a checkpoint is
# being written, and after the last step: every time exit status 0, a complete checkpoint that
# `polydem checkpoint info` verifies, no temporary file left, and summary.json saying so. The
# test hook POLYDEM_TEST_PAUSE (core/test_pause.h) holds the run at each point for 3 s, and so
# every checkpoint write, longer than Open MPI's mpirun, signalled itself, waits by default
# before it SIGKILLs its ranks (1 s after it passes SIGTERM on): the write takes as long as that
# of a large scene. The wrapper's grace period is set to 20 s here (default 60 s) to keep the
# test short: with 6 s, on a loaded 2-core machine (ctest -j2 beside validation runs) the ranks
# did not finish their stop, a step and the paused 3 s write, within it and mpirun killed them. Continuing from such checkpoints reaches the same bits as an uninterrupted run.
# By default each target, signal and moment is tried at least once (4 runs); "full" tries every
# combination (14 runs, about 3 minutes: ctest apps_signal_cli_full, a validation test).
# usage: signal_cli_test.sh POLYDEM MPIEXEC WRAPPER SCENE WORKDIR [full]
set -u
polydem=$1; wrapper=$3; scene=$4; work=$5; mode=${6:-quick}
export MPIRUN="$2 --oversubscribe"
[ "$(id -u)" = 0 ] && MPIRUN="$MPIRUN --allow-run-as-root"
export OMPI_MCA_mpi_yield_when_idle=1  # a rank held in a pause lets the other one sleep
export POLYDEM_STOP_GRACE_SECONDS=${POLYDEM_STOP_GRACE_SECONDS:-20}
rm -rf "$work"; mkdir -p "$work"; cd "$work" || exit 1
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
field() { python3 -c "import json,sys; print(json.load(open(sys.argv[1])).get(sys.argv[2]))" "$@"; }
hash_of() { field "$1/summary.json" state_hash 2> /dev/null; }
launch() { timeout 120 "$wrapper" -n "$1" "$polydem" "${@:2}" --no-snapshots --quiet; }
waitfor() {  # log pattern: up to 60 s
  for _ in $(seq 600); do grep -q "$2" "$1" && return 0; sleep 0.1; done
  return 1
}

# case NAME TARGET SIGNAL WHEN: TARGET wrapper | mpirun | ranks; WHEN startup | write | after.
signal_case() {
  local name=$1 target=$2 sig=$3 when=$4 args pause pattern
  case $when in
    startup) pause=startup:3 pattern="test pause: startup"
      args=(--steps 100000000) ;;
    write) pause=checkpoint-write:3 pattern="test pause: checkpoint-write"
      args=(--steps 100000000 --checkpoint-every 40) ;;
    after) pause=after-run:3 pattern="test pause: after-run"
      args=(--steps 30) ;;
  esac
  # mpirun, signalled itself, passes SIGTERM on only after the grace period: to reach the ranks
  # before their end, the pause after the last step must outlast it.
  [ "$target$sig$when" = mpirunTERMafter ] && pause=after-run:$((POLYDEM_STOP_GRACE_SECONDS + 3))
  POLYDEM_TEST_PAUSE=$pause timeout -s KILL 300 "$wrapper" -n 2 "$polydem" run "$scene" --out "$name" "${args[@]}" \
    --no-snapshots > "$name.log" 2>&1 &
  local pid=$!
  waitfor "$name.log" "$pattern" || fail "$name: the run never reached the pause: $(cat "$name.log")"
  local mpirun ranks
  mpirun=$(pgrep -P "$(pgrep -P $pid)" | head -1)  # timeout -> wrapper -> mpirun
  ranks=$(pgrep -P "$mpirun")
  case $target in
    wrapper) kill -"$sig" "$(pgrep -P $pid)" ;;
    mpirun) kill -"$sig" "$mpirun" ;;
    ranks) [ "$(echo $ranks | wc -w)" = 2 ] || fail "$name: ranks '$ranks'"; kill -"$sig" $ranks ;;
  esac
  wait $pid
  local rc=$?
  [ $rc = 0 ] || fail "$name: exit status $rc: $(tail -5 "$name.log")"
  local key=stopped_by_signal expect=SIG$sig
  [ "$when" = after ] && key=signal_after_end
  [ "$target" = wrapper ] && expect=SIGUSR1  # what the wrapper sends on
  [ "$(field "$name/summary.json" $key)" = "$expect" ] || fail "$name: summary.json $key"
  local file
  file=$(field "$name/summary.json" checkpoint)
  [ -f "$file" ] || { fail "$name: no checkpoint ($file)"; return; }
  "$polydem" checkpoint info "$file" > "$name.info" 2>&1 || fail "$name: checkpoint does not verify"
  [ -z "$(ls "$name/checkpoints" | grep tmp)" ] || fail "$name: temporary files left"
  grep -q "to continue: mpirun -n 2 .*polydem run --restart $file" "$name.log" ||
    fail "$name: no restart command printed"
}

if [ "$mode" = full ]; then  # every target, signal and moment: about 3 minutes
  for sig in TERM USR1; do
    for when in startup write after; do
      signal_case "mpirun_${sig}_$when" mpirun $sig $when
      signal_case "ranks_${sig}_$when" ranks $sig $when
    done
  done
  signal_case wrapper_TERM_write wrapper TERM write
  signal_case wrapper_HUP_startup wrapper HUP startup
else  # each target, signal and moment at least once
  signal_case mpirun_TERM_write mpirun TERM write
  signal_case ranks_USR1_startup ranks USR1 startup
  signal_case ranks_USR1_after ranks USR1 after
  signal_case wrapper_TERM_startup wrapper TERM startup
fi

# The checkpoints continue the run with the same bits, on another rank count.
steps=$(field mpirun_TERM_write/summary.json steps)
launch 1 run --restart "$(field mpirun_TERM_write/summary.json checkpoint)" --out cont \
  --steps $((steps + 20)) || fail "restart after SIGTERM to mpirun"
launch 2 run "$scene" --out ref --steps $((steps + 20)) || fail "reference run"
[ "$(hash_of cont)" = "$(hash_of ref)" ] || fail "restart after SIGTERM: other bits"
launch 1 run --restart "$(field ranks_USR1_after/summary.json checkpoint)" --out cont2 \
  --steps 50 || fail "restart from the final state"
launch 2 run "$scene" --out ref2 --steps 50 || fail "reference run of 50 steps"
[ "$(hash_of cont2)" = "$(hash_of ref2)" ] || fail "restart from the final state: other bits"

[ $failures = 0 ] && echo "all signal checks passed"
exit $((failures > 0))
