#!/bin/bash
# Numeric options of every polydem sub-command are parsed strictly: a value beyond 64 bits, a
# negative count, trailing characters, nan or inf end the command with exit status 2 and a
# message naming the option, before anything is written; good values (also "+3") still work.
# An unknown --picture-field is refused the same way.
# usage: cli_numbers_test.sh POLYDEM SCENE FOS_SCENE WORKDIR
set -u
polydem=$1; scene=$2; fos_scene=$3; work=$4
rm -rf "$work"; mkdir -p "$work"; cd "$work" || exit 1
failures=0
checked=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

# refused OPTION VALUE COMMAND...: the command with --OPTION VALUE appended exits 2, names the
# option on stderr and leaves no out/ behind. Each runs in a folder of its own, eight at a time
# (most of a refusal's second is MPI's start-up), and reports to ./failures.
refused() {
  local option=$1 value=$2; shift 2
  checked=$((checked + 1))
  local dir=case$checked
  (
    mkdir "$dir" && cd "$dir" || exit 1
    "$@" --"$option" "$value" > log 2>&1
    status=$?
    what="$* --$option '$value'"
    [ $status = 2 ] || echo "$what: exit status $status: $(tail -2 log)" >> ../failures
    grep -q -- "--$option" log || echo "$what: message: $(cat log)" >> ../failures
    [ ! -e out ] || echo "$what: out/ was written" >> ../failures
  ) &
  while [ "$(jobs -r | wc -l)" -ge 8 ]; do wait -n; done
}
# Each option gets one bad value, the kinds taken in turn (ctest apps_args checks every kind
# against the parser itself; this checks that every option goes through it, with its range).
bad_integers=(99999999999999999999 -1 7x 1.5 -99999999999999999999)
bad_numbers=(1e999 nan 2s inf 0x10)
turn=0
integer_option() {
  local option=$1; shift
  refused "$option" "${bad_integers[turn % ${#bad_integers[@]}]}" "$@"
  turn=$((turn + 1))
}
number_option() {
  local option=$1; shift
  refused "$option" "${bad_numbers[turn % ${#bad_numbers[@]}]}" "$@"
  turn=$((turn + 1))
}

run=("$polydem" run "$scene" --out out --quiet --no-snapshots)
for o in steps progress checkpoint-every checkpoint-keep; do integer_option $o "${run[@]}"; done
for o in end-time checkpoint-seconds; do number_option $o "${run[@]}"; done
refused steps 99999999999999999999 "${run[@]}"  # was clamped to 2^63 - 1
refused progress -1 "${run[@]}"                  # was taken
refused checkpoint-keep 4294967297 "${run[@]}"   # would be 1 as an int
number_option picture-azimuth "${run[@]}"
refused picture-field velocity "${run[@]}"       # not a field the frames can show

fos=("$polydem" fos "$fos_scene" --out out --quiet)
integer_option ranks-per-trial "${fos[@]}"
for o in resolution f-min f-max max-time; do number_option $o "${fos[@]}"; done

report=("$polydem" report contact-types --out out)
for o in poses seed; do integer_option $o "${report[@]}"; done
refused seed 4294967296 "${report[@]}"  # would be 0 as an unsigned

checkpoint=("$polydem" bench checkpoint --dir out)
for o in histories-per-particle repeat; do integer_option $o "${checkpoint[@]}"; done
refused particles 1000,-5 "${checkpoint[@]}"
number_option round-mib "${checkpoint[@]}"

if "$polydem" bench kernels --help > /dev/null 2>&1; then  # built with the benchmarks
  kernels=("$polydem" bench kernels --json out/k.json)
  for o in pairs passes; do integer_option $o "${kernels[@]}"; done
  number_option seconds "${kernels[@]}"
  scaling=("$polydem" bench scaling --json out/s.json)
  for o in per-rank particles layers steps warmup ranks; do integer_option $o "${scaling[@]}"; done
  for o in gap floor-width; do number_option $o "${scaling[@]}"; done
  refused ranks 1,2x "${scaling[@]}"
  model=("$polydem" bench contact-model --json out/m.json)
  for o in particles steps rounds; do integer_option $o "${model[@]}"; done
  yade=("$polydem" bench yade --keep out)
  for o in particles layers settle steps warmup seed; do integer_option $o "${yade[@]}"; done
fi

wait
if [ -s failures ]; then
  while read -r line; do fail "$line"; done < failures
fi

# Good values: a sign, and the full range of a count.
"$polydem" run "$scene" --out good --quiet --no-snapshots --steps +3 --progress 1 \
  --checkpoint-every 0 > good.log 2>&1 || fail "run --steps +3: exit status $?: $(tail -3 good.log)"
grep -q '"steps": 3,' good/summary.json 2>/dev/null || fail "run --steps +3: not 3 steps"

[ $failures = 0 ] && echo "all $checked refused values refused with the option named"
exit $((failures > 0))
