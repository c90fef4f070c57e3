"""scripts/peer_table.py (docs/performance.md "polydem beside its peers"): the one command that
runs the dense pack and the settled and loose piles in polydem, Yade and LAMMPS and writes one
table between the doc's markers. Run here on tiny scenes with stand-ins for Yade and LAMMPS that
answer from the input they are given, then without either peer, then on a doc without markers.

Checked: the rest of the doc is kept and the old table replaced; every figure of the table is the
one in the runs' JSON files; each peer's peak memory is its own process's (the Yade stand-in
touches 64 MB, the LAMMPS stand-in, run after it, does not); LAMMPS's own memory count is read;
rows of missing peers say so; a doc without markers is left alone and the command fails.
usage: peer_table_test.py POLYDEM SOURCE_DIR WORK_DIR
"""
import json
import pathlib
import shutil
import subprocess
import sys

polydem, source, work = sys.argv[1], pathlib.Path(sys.argv[2]), pathlib.Path(sys.argv[3])
shutil.rmtree(work, ignore_errors=True)
work.mkdir(parents=True)
script = source / "scripts" / "peer_table.py"

FAKE_YADE = r'''#!/usr/bin/env python3
import re, sys
script = open(sys.argv[-1]).read()
runs = re.findall(r"^O\.run\((\d+), True\)$", script, re.M)
free = len(re.findall(r"^body\(\[.*\], False\)$", script, re.M))
touched = b"\x01" * (64 << 20)  # a peak of its own, above the LAMMPS stand-in's
print("POLYDEM-YADE %d 11 %s 0.25" % (free, runs[-1]))
'''
FAKE_LMP = r'''#!/usr/bin/env python3
import re, sys
args = sys.argv[1:]
script = open(args[args.index("-in") + 1]).read()
atoms = int(re.search(r"^(\d+) atoms$", open("data.pile").read(), re.M).group(1))
with open(args[args.index("-screen") + 1], "w") as screen:
    for steps in re.findall(r"^run (\d+)$", script, re.M):
        screen.write("Per MPI rank memory allocation (min/avg/max) = 1.5 | 1.5 | 1.5 Mbytes\n")
        screen.write("Loop time of 0.5 on 1 procs for %s steps with %d atoms\n\n" % (steps, atoms))
        screen.write("80.0% CPU use with 1 MPI tasks x 1 OpenMP threads\n")
'''
for name, text in (("fake-yade", FAKE_YADE), ("fake-lmp", FAKE_LMP)):
    (work / name).write_text(text)
    (work / name).chmod(0o755)

DOC = "# Performance\n\nintro kept\n\n<!-- peer-table:begin -->\nold figures\n" \
      "<!-- peer-table:end -->\n\nafter kept\n"
SMALL = ["--polydem", polydem, "--dense", "40", "--dense-steps", "2", "--dense-warmup", "1",
         "--pile", "8", "--layers", "2", "--settle", "3000", "--memory-pile", "12",
         "--memory-settle", "200", "--steps", "3", "--warmup", "1", "--nice", "0"]


def fail(msg):
    print("FAIL:", msg)
    sys.exit(1)


def table_rows(doc_text):
    body = doc_text.split("<!-- peer-table:begin -->\n")[1].split("<!-- peer-table:end -->")[0]
    rows = [line.strip("|").split(" | ") for line in body.splitlines() if line.startswith("| ")]
    rows = [[c.strip() for c in r] for r in rows[1:]]  # without the header
    for i in range(1, len(rows)):  # a scene is named on its first row only
        rows[i][0] = rows[i][0] or rows[i - 1][0]
    return rows


def run_table(name, peers):
    doc = work / f"{name}.md"
    doc.write_text(DOC)
    out = work / name
    r = subprocess.run(["/usr/bin/python3", str(script)] + SMALL + peers +
                       ["--out", str(out), "--doc", str(doc)], capture_output=True, text=True)
    if r.returncode != 0:
        fail(f"{name}: exit status {r.returncode}\n{r.stdout}\n{r.stderr}")
    text = doc.read_text()
    if not text.startswith("# Performance\n\nintro kept\n\n<!-- peer-table:begin -->\n") \
            or not text.endswith("<!-- peer-table:end -->\n\nafter kept\n") or "old figures" in text:
        fail(f"{name}: the doc around the table changed or the old table stayed:\n{text}")
    return table_rows(text), out


# With both stand-ins.
rows, out = run_table("with", ["--yade", str(work / "fake-yade"), "--lmp", str(work / "fake-lmp")])
dense = [r for r in rows if r[0].startswith("dense pack")]
for model in ("sub-contacts", "point"):
    rate = json.load(open(out / f"dense_{model}.json"))[0]
    mem = json.load(open(out / f"dense_memory_{model}.json"))
    row = [r for r in dense if r[2] == f"gjk-epa-ipm, {model}"]
    cpu_rate = rate["particles"] * rate["steps"] / rate["cpu_seconds"]
    if len(row) != 1 or row[0][3] != f"{cpu_rate:,.0f}" \
            or row[0][9] != f"{mem['peak_bytes'] / mem['particles']:,.0f}" or float(row[0][7]) <= 0:
        fail(f"dense pack, {model}: row {row} against {rate} and {mem['peak_bytes']}")
base = {r["code"]: r["peak_kb"] for r in json.load(open(out / "pile_baseline.json"))["rows"]}
if sorted(base) != ["lammps", "polydem", "yade"] or not all(v > 0 for v in base.values()):
    fail(f"baseline peaks {base}")
for pile in ("settled", "loose"):
    data = json.load(open(out / f"pile_{pile}.json"))
    mine = [r for r in rows if r[0].startswith(f"{pile} pile")]
    if len(mine) != len(data["rows"]):
        fail(f"{pile} pile: {len(mine)} rows for {len(data['rows'])} records")
    yade = [r for r in mine if r[1] == "Yade (Polyhedra)"]
    lmp = [r for r in mine if r[1] == "LAMMPS (BODY)"]
    n = data["pile"]["particles"]
    # The stand-ins' answers: Yade 3 steps in 0.25 s of CPU, LAMMPS 3 steps in 0.5 s at 80 % CPU
    # (0.4 s of CPU), 1.5 MB counted.
    if len(yade) != 1 or yade[0][3] != f"{n * 3 / 0.25:,.0f}" or yade[0][4] != "1.0" \
            or yade[0][5] != "1.6" or yade[0][6] != "11":
        fail(f"{pile} pile: Yade row {yade}")
    if len(lmp) != 1 or lmp[0][3] != f"{n * 3 / 0.4:,.0f}" or lmp[0][5] != "1.0" \
            or lmp[0][9] != "-":
        fail(f"{pile} pile: LAMMPS row {lmp}")
    if not float(yade[0][7]) >= 64 or not 0 < float(lmp[0][7]) < 64:
        fail(f"{pile} pile: peak MB Yade {yade[0][7]}, LAMMPS {lmp[0][7]}: each its own expected")
    # Above the baseline: each code's peak less its own run of 8 cubes, per block.
    for row, rec in zip(mine, data["rows"]):
        if row[8] != f"{(rec['peak_kb'] - base[rec['code']]) * 1024 / n:,.0f}":
            fail(f"{pile} pile: {row} above the baseline {base} expected")
    for r, rec in zip([r for r in mine if r[1] == "polydem"],
                      [r for r in data["rows"] if r["code"] == "polydem"]):
        if r[3] != f"{rec['particle_steps_per_second']:,.0f}" or float(r[4].replace(",", "")) <= 0 \
                or r[9] != f"{rec['counted_bytes'] / rec['particles']:,.0f}":
            fail(f"{pile} pile: polydem row {r} against {rec}")

# Without either peer: their rows say so, polydem's are there.
rows, _ = run_table("without", ["--yade", str(work / "no-yade"), "--lmp", str(work / "no-lmp")])
for code in ("Yade (Polyhedra)", "LAMMPS (BODY)"):
    mine = [r for r in rows if r[1] == code]
    if len(mine) != 2 or any(not r[2].startswith("not installed") for r in mine):
        fail(f"without peers: {code} rows {mine}")
if not any(r[1] == "polydem" and r[0].startswith("settled pile") and r[4] == "-" for r in rows):
    fail(f"without peers: no polydem row without ratios: {rows}")

# A doc without markers: nothing runs, nothing is written, the exit status says so.
bare = work / "bare.md"
bare.write_text("# no markers\n")
r = subprocess.run(["/usr/bin/python3", str(script)] + SMALL + ["--doc", str(bare), "--out",
                   str(work / "bare")], capture_output=True, text=True)
if r.returncode == 0 or bare.read_text() != "# no markers\n" or "peer-table:begin" not in r.stderr:
    fail(f"doc without markers: status {r.returncode}, {r.stderr}")
print("peer_table: one table from the runs' files, with and without peers: OK")
