#!/bin/bash
# `polydem bench checkpoint --dir DIR` deletes only what it wrote: files that
# were in DIR before (even ones named like the benchmark's own), the working directory with
# `--dir .`, and a DIR it did not create all survive; a DIR it created is removed again.
# usage: bench_checkpoint_dir_test.sh POLYDEM MPIEXEC WORKDIR
set -u
polydem=$1; mpiexec="$2 --oversubscribe"; work=$3
[ "$(id -u)" = 0 ] && mpiexec="$mpiexec --allow-run-as-root"
rm -rf "$work"; mkdir -p "$work"; cd "$work" || exit 1
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
launcher=""  # empty: one process; "$mpiexec -n 2": two ranks
bench() {
  timeout 120 $launcher "$polydem" bench checkpoint --particles 300 --histories-per-particle 2 \
    --repeat 1 "$@"
}
# A directory holding a user's files, two of them named as the benchmark names its own.
fill() {
  mkdir -p "$1/sub"
  echo precious > "$1/notes.txt"; echo mine > "$1/checkpoint.h5"; echo mine > "$1/raw.h5"
  echo deep > "$1/sub/data.txt"
}
same() {  # dir: the files fill() made are all there, unchanged, and nothing else
  [ "$(cat "$1/notes.txt" "$1/checkpoint.h5" "$1/raw.h5" "$1/sub/data.txt" 2> /dev/null)" = \
    "$(printf 'precious\nmine\nmine\ndeep')" ] || return 1
  [ "$(find "$1" | wc -l)" = 6 ]
}

fill user
bench --dir user > user.log 2>&1 || fail "--dir user: exit status $?: $(cat user.log)"
same user || fail "--dir user: the directory's files changed: $(find user)"

mkdir here && fill here
(cd here && bench --dir . > ../here.log 2>&1) || fail "--dir .: exit status"
same here || fail "--dir .: the working directory changed: $(find here)"

mkdir cwd && fill cwd
(cd cwd && launcher="$mpiexec -n 2" bench > ../cwd.log 2>&1) || fail "no --dir, 2 ranks: exit"
same cwd || fail "no --dir: the working directory changed: $(find cwd)"

bench --dir made/deeper > made.log 2>&1 || fail "--dir made/deeper: exit status"
[ ! -e made/deeper ] || fail "--dir made/deeper: the directory it made is left: $(find made)"

mkdir kept && fill kept
bench --dir kept --keep > kept.log 2>&1 || fail "--keep: exit status"
file=$(sed -n 's/^kept: //p' kept.log)
[ -f "$file" ] || fail "--keep: no kept checkpoint reported: $(cat kept.log)"
case "$file" in kept/polydem_bench_checkpoint.*/checkpoint.h5) ;; *) fail "--keep: kept $file" ;; esac
rm -rf "$(dirname "$file")"
same kept || fail "--keep: the directory's own files changed"

[ $failures = 0 ] && echo "bench checkpoint --dir: all checks passed"
exit $((failures > 0))
