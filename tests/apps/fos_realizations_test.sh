#!/bin/bash
# `polydem fos SCENE --realizations N` (docs/scene-format.md, "Random inputs"), on F-PROBABILITY:
#  - the same study on 1 rank and on 2 (two realizations side by side) gives the same rows: each
#    realization's seed, drawn input, F and trial state hashes, bit for bit;
#  - each realization's F and trial hashes equal those of `polydem fos` run alone on the scene
#    file the study wrote for it (DIR/scenes/realization-NNNN.toml);
#  - a study stopped by SIGTERM (through scripts/polydem-mpirun, 2 ranks) after its first round
#    keeps the finished realizations (atomically written realizations.csv), prints the command
#    that continues, and that same command finishes it with the rows of an unstopped study;
#  - bad [[random]] entries are refused with the file and the entry's line, exit status 1.
# usage: fos_realizations_test.sh POLYDEM MPIEXEC WRAPPER SCENE WORKDIR
set -u
polydem=$1; wrapper=$3; scene=$4; work=$5
export MPIRUN="$2 --oversubscribe"
[ "$(id -u)" = 0 ] && MPIRUN="$MPIRUN --allow-run-as-root"
export OMPI_MCA_mpi_yield_when_idle=1
export POLYDEM_STOP_GRACE_SECONDS=${POLYDEM_STOP_GRACE_SECONDS:-20}
rm -rf "$work"; mkdir -p "$work"; cd "$work" || exit 1
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
waitfor() {  # log pattern: up to 120 s
  for _ in $(seq 1200); do grep -q "$2" "$1" && return 0; sleep 0.1; done
  return 1
}
# The rows without the wall time and group (which differ from run to run by design).
rows() {
  /usr/bin/python3 -c "
import csv, sys
for r in csv.DictReader(open(sys.argv[1])):
    r.pop('wall_seconds'); r.pop('group'); print(sorted(r.items()))" "$1"
}
cp "$scene" scene.toml
n=4

"$polydem" fos scene.toml --realizations $n --out ref1 > ref1.log 2>&1 || fail "1 rank: $(tail -3 ref1.log)"
"$wrapper" -n 2 "$polydem" fos scene.toml --realizations $n --out ref2 > ref2.log 2>&1 ||
  fail "2 ranks: $(tail -3 ref2.log)"
[ "$(rows ref1/realizations.csv | wc -l)" = $n ] || fail "1 rank: not $n rows"
[ "$(rows ref1/realizations.csv)" = "$(rows ref2/realizations.csv)" ] ||
  fail "1 and 2 ranks differ: $(diff <(rows ref1/realizations.csv) <(rows ref2/realizations.csv))"

# Each realization alone: the same F and trial hashes as in the study.
for i in 0 3; do
  alone=alone$i
  "$polydem" fos ref2/scenes/realization-000$i.toml --out $alone --quiet > $alone.log 2>&1 ||
    fail "realization $i alone: $(tail -3 $alone.log)"
  /usr/bin/python3 - ref2/realizations.csv $alone/fos.json $i <<'PY' || fail "realization $i alone"
import csv, json, sys
row = [r for r in csv.DictReader(open(sys.argv[1])) if r["realization"] == sys.argv[3]][0]
alone = json.load(open(sys.argv[2]))
hashes = " ".join(t["state_hash"] for t in alone["trials"])
ok = float(row["factor_of_safety"]) == alone["factor_of_safety"] and row["trial_hashes"] == hashes
print("study:", row["factor_of_safety"], row["trial_hashes"])
print("alone:", repr(alone["factor_of_safety"]), hashes)
sys.exit(0 if ok else 1)
PY
done

# Stopped after its first round (each trial held 0.2 s so that the signal finds it running).
POLYDEM_TEST_PAUSE=fos-trial:0.2 "$wrapper" -n 2 "$polydem" fos scene.toml --realizations $n \
  --out stopped > stopped.log 2>&1 &
pid=$!
waitfor stopped.log "(2 of $n)" || fail "the first round never finished: $(tail -5 stopped.log)"
kill -TERM $pid
wait $pid
rc=$?
[ $rc = 0 ] || fail "stopped: exit status $rc: $(tail -5 stopped.log)"
kept=$(rows stopped/realizations.csv | wc -l)
[ "$kept" -ge 2 ] && [ "$kept" -lt $n ] || fail "stopped: $kept realizations kept, not 2 or 3"
grep -q "\"complete\": false" stopped/realizations.json || fail "stopped: not marked incomplete"
grep -q "to continue: mpirun -n 2 polydem fos scene.toml --realizations $n --out stopped" \
  stopped.log || fail "stopped: no command to continue: $(tail -3 stopped.log)"
"$wrapper" -n 2 "$polydem" fos scene.toml --realizations $n --out stopped > continued.log 2>&1 ||
  fail "continued: $(tail -3 continued.log)"
grep -q "$kept already in stopped/realizations.csv" continued.log ||
  fail "continued: the kept realizations were not taken: $(head -3 continued.log)"
grep -q "\"complete\": true" stopped/realizations.json || fail "continued: not complete"
[ "$(rows stopped/realizations.csv)" = "$(rows ref2/realizations.csv)" ] ||
  fail "stopped and continued differs from the unstopped study"

# Bad entries: the file and the entry's line.
bad() {  # NAME EXPECTED-MESSAGE ENTRY...
  local name=$1 message=$2
  shift 2
  grep -v -e '^\[\[random\]\]' -e '^parameter = ' -e '^distribution = ' -e '^mean = ' \
    -e '^sd = ' scene.toml > $name.toml
  printf '%s\n' "[[random]]" "$@" >> $name.toml
  "$polydem" fos $name.toml --realizations 2 --out $name > $name.log 2>&1
  local rc=$?
  [ $rc = 1 ] || fail "$name: exit status $rc, not 1: $(cat $name.log)"
  grep -q "$name.toml:[0-9][0-9]*:.*$message" $name.log || fail "$name: $(cat $name.log)"
  [ -e $name/realizations.csv ] && fail "$name: realizations.csv written"
}
bad distribution "gamma" 'parameter = "material.rock.friction_angle"' 'distribution = "gamma"'
bad unknown_entry "no \[\[material\]\] entry is named 'granite'" \
  'parameter = "material.granite.friction_angle"' 'distribution = "normal"' 'mean = 30' 'sd = 2'
bad unknown_key "frictoin_angle" 'parameter = "material.rock.frictoin_angle"' \
  'distribution = "normal"' 'mean = 30' 'sd = 2'
bad sd "sd.*must be > 0" 'parameter = "material.rock.friction_angle"' 'distribution = "normal"' \
  'mean = 30' 'sd = 0'
bad bounds "must exceed min" 'parameter = "material.rock.friction_angle"' \
  'distribution = "truncated"' 'mean = 30' 'sd = 2' 'min = 35' 'max = 25'
bad lognormal "mean must be > 0" 'parameter = "material.rock.cohesion"' \
  'distribution = "lognormal"' 'mean = 0' 'sd = 2'
bad not_a_number "not one number" 'parameter = "particle.block.position"' \
  'distribution = "uniform"' 'min = 0' 'max = 1'

[ $failures = 0 ] && echo "all realizations checks passed"
exit $((failures > 0))
