#!/usr/bin/python3
"""Builds the validation tables of docs/validation.md from the summary.json files that
scripts/validation-table's runs wrote.

One table per contact model, one row per scene, one column per kernel (the potential kernels,
which have no contact model, only in the first table). A cell is PASS or FAIL (every check of the
scene must pass) with the scene's headline figure; a run that did not finish shows why (the last
line of its log). The check list of every cell follows the tables on stdout, so that each figure
can be traced; --doc FILE also writes the tables into FILE between the validation-table markers.
"""
import argparse
import json
import os
import pathlib
import sys

# The figure shown in a passing cell: the first check whose name contains one of these words.
# A failing cell shows its worst check instead (largest value / bound).
HEADLINE = ("rotation", "drift", "displacement", "velocity", "energy", "steps")


def worst(checks):
    def excess(c):
        v, e = c.get("value"), c.get("expected")
        if v is None or e is None:
            return float("inf")
        return abs(v) / abs(e) if e else abs(v)
    failing = [c for c in checks if not c["pass"]]
    return max(failing, key=excess) if failing else None


def headline(checks):
    bad = worst(checks)
    if bad:
        return bad
    for word in HEADLINE:
        for c in checks:
            if word in c["name"]:
                return c
    return checks[0] if checks else None


def fmt(v):
    if v is None:
        return "-"
    if isinstance(v, float):
        return f"{v:.3g}"
    return str(v)


# Kinds whose dimensionless value is a count, not a ratio.
COUNTS = {"equilibrium_steps": " steps", "contact_count": " contacts"}


def unit(check):
    """The unit a figure is in (summary.json "unit"; "1" is a ratio or, for COUNTS, a count)."""
    u = check.get("unit")
    if not u:
        return ""
    if u == "1":
        return COUNTS.get(check.get("kind"), " (ratio)")
    return " " + u


def cell(run_dir, log):
    summary = run_dir / "summary.json"
    if not summary.exists():
        last = log.read_text(errors="replace").strip().splitlines()[-1:] if log.exists() else []
        return "not run" if not last else "error: " + last[0][:80].replace("|", "/"), None
    s = json.loads(summary.read_text())
    checks = [c for c in s.get("checks", []) if c.get("kind") != "report" and
              c.get("compare") != "report"]
    ok = all(c["pass"] for c in checks)
    h = headline(checks)
    text = ("PASS" if ok else "FAIL") + (f" {h['name']} {fmt(h['value'])}{unit(h)}" if h else "")
    eq = s.get("equilibrium")
    if eq:
        text += f"; equilibrium {'in ' + str(eq['steps']) + ' steps' if eq['reached'] else 'not reached in ' + str(eq['steps'])}"
    return text, s


def tables(out, kernels, scenes, models, potential):
    """The tables (one per contact model) and the check list of every cell, as two strings."""
    lines, details = [], []
    for m, model in enumerate(models):
        columns = [k for k in kernels if m == 0 or k not in potential]
        lines.append(f"contact_model = {model or 'as in the scene files'}:\n")
        lines.append("| scene | " + " | ".join(columns) + " |")
        lines.append("|---" * (len(columns) + 1) + "|")
        for scene in scenes:
            row = []
            for k in columns:
                base = out / model if model else out
                text, s = cell(base / scene / k, base / scene / f"{k}.log")
                row.append(text)
                if s:
                    details.append((model, scene, k, s))
            lines.append(f"| {scene} | " + " | ".join(row) + " |")
        lines.append("")
    checks = []
    for model, scene, k, s in details:
        checks.append(f"- {scene} / {k} / {model or s.get('contact_model')}: {s['steps']} steps, "
                      f"{s['wall_seconds']:.1f} s wall, hash {s['state_hash']}")
        for c in s.get("checks", []):
            checks.append(f"  - {c['name']}: {fmt(c['value'])}{unit(c)} (expected "
                          f"{fmt(c['expected'])}, {c['compare']} {fmt(c['tolerance'])}) "
                          f"{'pass' if c['pass'] else 'FAIL'}")
    return "\n".join(lines) + "\n", "\n".join(checks) + ("\n" if checks else "")


# The part of a document (docs/validation.md) that the tables replace: everything between these
# two lines, which stay.
BEGIN = "<!-- validation-table:begin -->"
END = "<!-- validation-table:end -->"


def write_section(doc, text):
    """Replaces the lines between BEGIN and END in the file doc by text, keeping the rest of the
    file byte for byte. The file is written to a temporary name beside it and renamed, so a failed
    write leaves it as it was; a file without exactly one BEGIN followed by one END is refused
    (SystemExit naming the file and the line) and left untouched."""
    doc = pathlib.Path(doc)
    old = doc.read_text()
    lines = old.splitlines(keepends=True)
    begins = [i for i, line in enumerate(lines) if line.strip() == BEGIN]
    ends = [i for i, line in enumerate(lines) if line.strip() == END]
    if len(begins) != 1 or len(ends) != 1 or ends[0] < begins[0]:
        where = ", ".join(f"line {i + 1}" for i in begins + ends) or "nowhere"
        raise SystemExit(f"{doc}: needs one '{BEGIN}' line followed by one '{END}' line "
                         f"(found at {where}); not changed")
    b, e = begins[0], ends[0]
    body = text if text.endswith("\n") else text + "\n"
    new = "".join(lines[:b + 1]) + body + "".join(lines[e:])
    tmp = doc.with_name(f".{doc.name}.tmp.{os.getpid()}")
    try:
        tmp.write_text(new)
        os.replace(tmp, doc)
    finally:
        if tmp.exists():
            tmp.unlink()


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("out")
    ap.add_argument("--kernels", nargs="+", required=True)
    ap.add_argument("--scenes", nargs="+", required=True)
    ap.add_argument("--models", nargs="+", default=["sub-contacts"])
    ap.add_argument("--potential", nargs="*", default=[])
    ap.add_argument("--flat", action="store_true",
                    help="runs in OUT/SCENE/KERNEL, with the scenes' own contact model")
    ap.add_argument("--doc", help="also write the tables between the validation-table markers "
                    "of this file (docs/validation.md), replacing what was there")
    a = ap.parse_args()
    if a.flat:
        a.models = [""]
    text, checks = tables(pathlib.Path(a.out), a.kernels, a.scenes, a.models, a.potential)
    if a.doc:
        write_section(a.doc, text)
    sys.stdout.write(text + checks)


if __name__ == "__main__":
    main()
