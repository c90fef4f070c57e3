#!/bin/bash
# polydem fos from the command line: --kernel and --contact-model reach the trials and fos.json
# records them; the block on an incline (F = tan 40 deg / tan 30 deg = 1.4534) is found within
# 2 % with sub-contacts and with the point model of gjk-epa-ipm (whose block rocks and creeps
# by a millionth of its size, docs/dynamics.md, which the criterion does not call failure); an unknown contact model is a usage error that writes nothing. Settings a
# trial cannot answer are refused with the file and line, exit status 1 and nothing written: an
# interaction no contact uses (every trial would be stable: "above f_max"), a max_time of a few
# steps (every trial undecided), a check_every beyond the trial (no time limit at all). A second
# search into the folder of a running one is refused (DIR/polydem.lock) and changes nothing.
# usage: fos_cli_test.sh POLYDEM SCENE WORKDIR
set -u
polydem=$1; scene=$2; work=$3
rm -rf "$work"; mkdir -p "$work"; cd "$work" || exit 1
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
field() { /usr/bin/python3 -c "import json,sys; print(json.load(open(sys.argv[1]))[sys.argv[2]])" "$@"; }
within() {  # within VALUE EXPECTED RELATIVE
  /usr/bin/python3 -c "import sys; v, e, r = map(float, sys.argv[1:]); sys.exit(abs(v - e) > r * e)" "$@"
}
analytical=1.4533631938113549

for model in sub-contacts point; do
  "$polydem" fos "$scene" --kernel gjk-epa-ipm --contact-model $model --out $model --quiet \
    > $model.log 2>&1 || fail "$model: exit status $?: $(tail -3 $model.log)"
  [ "$(field $model/fos.json contact_model)" = $model ] || fail "$model: fos.json contact_model"
  [ "$(field $model/fos.json kernel)" = gjk-epa-ipm ] || fail "$model: fos.json kernel"
done
f_sub=$(field sub-contacts/fos.json factor_of_safety)
f_point=$(field point/fos.json factor_of_safety)
within "$f_sub" $analytical 0.02 || fail "sub-contacts: F = $f_sub, analytical $analytical"
within "$f_point" $analytical 0.02 || fail "point: F = $f_point, analytical $analytical"

"$polydem" fos "$scene" --contact-model points --out bad > bad.log 2>&1
status=$?
[ $status = 2 ] || fail "unknown contact model: exit status $status"
grep -q "unknown contact model 'points'" bad.log || fail "unknown contact model: $(cat bad.log)"
[ ! -e bad ] || fail "unknown contact model: bad/ was created"

[ "$(field sub-contacts/fos.json complete)" = True ] || fail "fos.json complete"
/usr/bin/python3 - sub-contacts/fos.json << 'EOF2' || fail "fos.json criterion or trials"
import json, sys
j = json.load(open(sys.argv[1]))
c = j["criterion"]
assert c["local_damping"] == 0.8 and "static solution" in c["description"], c
for t in j["trials"]:
    assert t["outcome"] in ("stable", "failed"), t["outcome"]
    assert t["steps"] > 0 and t["history"], t
EOF2

# refuse NAME EXPECTED_MESSAGE SCENE [OPTIONS]: exit status 1, the message, nothing written.
refuse() {
  local name=$1 message=$2 file=$3
  "$polydem" fos "$file" --out "refused_$name" "${@:4}" > "$name.log" 2>&1
  local status=$?
  [ $status = 1 ] || fail "$name: exit status $status: $(cat "$name.log")"
  grep -q -- "$message" "$name.log" || fail "$name: no '$message' in: $(cat "$name.log")"
  [ ! -e "refused_$name" ] || fail "$name: refused_$name/ was created"
}
without_fos=$(sed '/^\[fos\]/,$d' "$scene")
{ echo "$without_fos"
  printf '[[material]]\nname = "clay"\ndensity = 2000\nkn = 1e9\nks = 5e8\nfriction_angle = 20\n\n'
  printf '[fos]\nf_max = 3\nmax_time = "2 s"\ninteractions = [["clay", "rock"]]\n'; } > unused.toml
line=$(grep -n '^interactions' unused.toml | cut -d: -f1)
refuse unused_interaction "unused.toml:$line: \[fos\] interactions\[0\] = \[\"rock\", \"clay\"\]: no contact" unused.toml
refuse short_trial "a trial needs at least 500 steps" "$scene" --max-time 0.001
{ echo "$without_fos"; printf '[fos]\nmax_time = "2 s"\ncheck_every = 1e9\n'; } > check.toml
line=$(grep -n '^check_every' check.toml | cut -d: -f1)
refuse check_every "check.toml:$line: \[fos\] check_every = 1000000000 steps" check.toml

# A search held at its first trial (test hook) owns busy/; a second one into busy/ is refused.
POLYDEM_TEST_PAUSE=fos-trial:60 "$polydem" fos "$scene" --out busy --quiet > holder.log 2>&1 &
holder=$!
for _ in $(seq 600); do grep -q "test pause: fos-trial" holder.log && break; sleep 0.1; done
grep -q "test pause: fos-trial" holder.log || fail "the holding search did not reach its pause"
before=$(ls -l busy)
"$polydem" fos "$scene" --out busy --quiet > second.log 2>&1
status=$?
[ $status = 1 ] || fail "second search into a busy folder: exit status $status: $(cat second.log)"
grep -q "output folder busy is in use: busy/polydem.lock names process $holder" second.log ||
  fail "second search: no message naming the lock: $(cat second.log)"
[ "$(ls -l busy)" = "$before" ] || fail "the refused search changed busy/"
kill -9 $holder 2> /dev/null; wait $holder 2> /dev/null

[ $failures = 0 ] && echo "all fos CLI checks passed (F = $f_sub sub-contacts, $f_point point)"
exit $((failures > 0))
