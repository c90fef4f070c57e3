#!/bin/bash
# A stop signal while `polydem run` cuts a large rock mass (docs/scene-format.md, "Long cuts"):
# the cut prints progress lines, and SIGTERM sent after the first one ends the run at once with
# a non-zero exit status, a message naming the scene line and the plane reached, and no output
# folder. (Before, the cut ignored SIGTERM and ran on for minutes.) The wait for the exit is
# bounded by 60 s only so that a regression fails instead of hanging; the run, undisturbed,
# would cut for minutes.
# usage: rock_mass_signal_test.sh POLYDEM WORKDIR
set -u
polydem=$1; work=$2
rm -rf "$work"; mkdir -p "$work"; cd "$work" || exit 1
cat > long_cut.toml << 'SCENE'
[scene]
id = "T-LONG-CUT"
[simulation]
dt = "1e-5 s"
steps = 2
[[material]]
name = "rock"
density = "2000 kg/m^3"
kn = "5e3 GN/m"
[[rock_mass]]                    # line 10: named in the message
name = "slope"
material = "rock"
region = { type = "box", min = [0, 0, 0], max = [30, 4, 4] }
[[rock_mass.joint_set]]          # 15,000 planes, within the limits, cut one by one
name = "J"
dip = 90
dip_direction = 90
spacing = "2 mm"
SCENE
"$polydem" run long_cut.toml --out out --no-snapshots > run.log 2>&1 &
pid=$!
for _ in $(seq 1200); do grep -q "cutting, plane" run.log && break; sleep 0.1; done
if ! grep -q "cutting, plane" run.log; then
  echo "FAIL: no progress line within 120 s"; cat run.log; kill -KILL $pid; exit 1
fi
kill -TERM $pid
start=$(date +%s.%N)
for _ in $(seq 600); do kill -0 $pid 2> /dev/null || break; sleep 0.1; done
if kill -0 $pid 2> /dev/null; then
  echo "FAIL: still cutting 60 s after SIGTERM"; kill -KILL $pid; exit 1
fi
wait $pid
rc=$?
echo "exit status $rc, $(echo "$(date +%s.%N) - $start" | bc) s after SIGTERM"
cat run.log
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
[ $rc != 0 ] || fail "exit status 0"
grep -q "long_cut.toml:10: \[\[rock_mass\]\] 'slope': stopped by SIGTERM while cutting the rock mass (plane [0-9]* of [0-9]*, [0-9]* blocks so far); nothing was written" run.log ||
  fail "no message naming the scene line and the plane"
[ ! -e out ] || fail "the output folder was created"
[ $failures = 0 ] && echo PASS
exit $failures
