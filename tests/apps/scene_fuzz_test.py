#!/usr/bin/env python3
"""Fixed-seed fuzz test of the scene reader and the start of a run.

Mutates the scene files given (deleted, duplicated or swapped lines, numbers replaced by extreme
values, strings and units changed, keys misspelt, arrays shortened, tables duplicated, files cut
short or with stray bytes) with a seeded SplitMix64, so that every run tries the same scenes,
and runs `polydem run MUTANT --steps 3` on each. Every mutant must end, within the time limit,
either with exit status 0 or with exit status 1 and one error line that names the mutant file
and, for an error in it, the line ("error: FILE:LINE: ..."). A run still going at the limit is
sent SIGTERM (as a batch system would) and must then stop cleanly with status 0 within the
grace period; anything else (a crash, a hang, another status, an error without the file, a
std:: exception text) is a failure, printed with the mutant's text.

usage: scene_fuzz_test.py POLYDEM WORKDIR COUNT SEED SCENE...
"""
import os
import re
import shutil
import signal
import subprocess
import sys
import time

LIMIT_S = 20.0  # then SIGTERM
GRACE_S = 20.0  # then SIGKILL: a failure
MASK = (1 << 64) - 1

EXTREMES = ["0", "-1", "1e308", "-1e308", "1e-310", "4.9e-324", "nan", "inf", "-inf", "1e400",
            "2147483648", "9223372036854775807", "-9223372036854775808", "1e9", "-0.0", "3.5"]
WORDS = ["", "x", "rock", "cube", "gjk-epa", "fcp", "metis", "max", "report", "1 m", "30 deg",
         "\\u0000", "a,b", "b00", "1e-3 kg/m^3", "5 s", "-2 m/s"]
UNITS = ["m", "s", "kg", "deg", "rad", "N/m", "Pa", "kg/m^3", "m/s^2", "Hz", "mm", "furlong"]


class SplitMix64:
    def __init__(self, seed):
        self.state = seed & MASK

    def next(self):
        self.state = (self.state + 0x9E3779B97F4A7C15) & MASK
        z = self.state
        z = ((z ^ (z >> 30)) * 0xBF58476D1CE4E5B9) & MASK
        z = ((z ^ (z >> 27)) * 0x94D049BB133111EB) & MASK
        return z ^ (z >> 31)

    def below(self, n):
        return self.next() % n

    def pick(self, items):
        return items[self.below(len(items))]


NUMBER = re.compile(r"(?<![\w.])-?\d+(\.\d*)?([eE][-+]?\d+)?(?![\w.])")
STRING = re.compile(r'"[^"\n]*"')
KEY = re.compile(r"^(\s*)([A-Za-z_]+)(\s*=)", re.M)


def mutate(text, rng):
    lines = text.split("\n")
    kind = rng.below(11)
    if kind == 0 and len(lines) > 1:  # delete a line
        del lines[rng.below(len(lines))]
    elif kind == 1:  # duplicate a line
        i = rng.below(len(lines))
        lines.insert(i, lines[i])
    elif kind == 2 and len(lines) > 1:  # swap two lines
        i, j = rng.below(len(lines)), rng.below(len(lines))
        lines[i], lines[j] = lines[j], lines[i]
    elif kind in (3, 4):  # a number replaced by an extreme value
        spots = [(i, m) for i, l in enumerate(lines) for m in NUMBER.finditer(l)]
        if spots:
            i, m = rng.pick(spots)
            lines[i] = lines[i][:m.start()] + rng.pick(EXTREMES) + lines[i][m.end():]
    elif kind == 5:  # a string replaced
        spots = [(i, m) for i, l in enumerate(lines) for m in STRING.finditer(l)]
        if spots:
            i, m = rng.pick(spots)
            lines[i] = lines[i][:m.start()] + '"%s"' % rng.pick(WORDS) + lines[i][m.end():]
    elif kind == 6:  # a unit changed
        spots = [(i, m) for i, l in enumerate(lines) for m in STRING.finditer(l)
                 if re.match(r'"-?[\d.]', m.group())]
        if spots:
            i, m = rng.pick(spots)
            number = m.group()[1:-1].split(" ")[0]
            lines[i] = lines[i][:m.start()] + '"%s %s"' % (number, rng.pick(UNITS)) + \
                lines[i][m.end():]
    elif kind == 7:  # a key misspelt
        spots = [(i, m) for i, l in enumerate(lines) for m in [KEY.match(l)] if m]
        if spots:
            i, m = rng.pick(spots)
            key = m.group(2)
            k = rng.below(len(key))
            key = key[:k] + key[k + 1:] if len(key) > 1 else key + "x"
            lines[i] = m.group(1) + key + lines[i][m.end(2):]
    elif kind == 8:  # an array shortened
        spots = [i for i, l in enumerate(lines) if "[" in l and "," in l and "=" in l]
        if spots:
            i = rng.pick(spots)
            lines[i] = re.sub(r",[^,\]]*\]", "]", lines[i], count=1)
    elif kind == 9:  # a table header duplicated
        spots = [i for i, l in enumerate(lines) if l.startswith("[")]
        if spots:
            i = rng.pick(spots)
            lines.insert(rng.below(len(lines) + 1), lines[i])
    else:  # cut short, or stray bytes
        flat = "\n".join(lines)
        at = rng.below(len(flat) + 1)
        if rng.below(2):
            return flat[:at]
        return flat[:at] + rng.pick(["\x00", "\xff", "{{", "]]", "=", "\"", "\\", "#"]) + flat[at:]
    return "\n".join(lines)


def run_one(polydem, path, out):
    start = time.monotonic()
    proc = subprocess.Popen([polydem, "run", path, "--out", out, "--steps", "3", "--no-snapshots",
                             "--quiet"], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True, errors="replace")
    signalled = False
    try:
        stdout, stderr = proc.communicate(timeout=LIMIT_S)
    except subprocess.TimeoutExpired:
        signalled = True
        proc.send_signal(signal.SIGTERM)
        try:
            stdout, stderr = proc.communicate(timeout=GRACE_S)
        except subprocess.TimeoutExpired:
            proc.kill()
            stdout, stderr = proc.communicate()
            return "hang: no exit %g s after SIGTERM" % GRACE_S, stderr, time.monotonic() - start
    seconds = time.monotonic() - start
    status = proc.returncode
    if status == 0:
        return None, stderr, seconds
    errors = [l for l in stderr.splitlines() if l.startswith("error: ")]
    if status < 0:
        return "killed by signal %d%s" % (-status, " after SIGTERM" if signalled else ""), \
            stderr, seconds
    if status != 1:
        return "exit status %d" % status, stderr, seconds
    if len(errors) != 1:
        return "%d error lines" % len(errors), stderr, seconds
    if not re.match(r"error: %s(:\d+)?: " % re.escape(path), errors[0]):
        return "the error does not name the file (and line)", stderr, seconds
    if "std::" in errors[0] or "bad_alloc" in errors[0]:
        return "a C++ library exception", stderr, seconds
    return None, stderr, seconds


def main(polydem, work, count, seed, scenes):
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    rng = SplitMix64(seed)
    texts = [open(s).read() for s in scenes]
    failures, outcomes, slowest = 0, {"exit 0": 0, "file:line error": 0, "file error": 0}, 0.0
    for n in range(count):
        k = rng.below(len(texts))
        text = texts[k]
        for _ in range(1 + rng.below(3)):
            text = mutate(text, rng)
        path = os.path.join(work, "m%04d.toml" % n)
        with open(path, "w", errors="replace") as f:
            f.write(text)
        problem, stderr, seconds = run_one(polydem, path, os.path.join(work, "out%04d" % n))
        slowest = max(slowest, seconds)
        if problem:
            failures += 1
            print("FAIL %s (from %s): %s\n--- stderr:\n%s--- scene:\n%s\n---" %
                  (path, os.path.basename(scenes[k]), problem, stderr[-2000:], text[:3000]))
        else:
            err = [l for l in stderr.splitlines() if l.startswith("error: ")]
            key = "exit 0" if not err else \
                ("file:line error" if re.match(r"error: [^:]+:\d+: ", err[0]) else "file error")
            outcomes[key] += 1
            shutil.rmtree(os.path.join(work, "out%04d" % n), ignore_errors=True)
            os.remove(path)
    print("scene fuzz: %d mutants of %d scenes (seed %d): %s; slowest %.1f s; %d failures" %
          (count, len(scenes), seed, outcomes, slowest, failures))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1], sys.argv[2], int(sys.argv[3]), int(sys.argv[4]), sys.argv[5:]))
