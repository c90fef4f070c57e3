#!/usr/bin/python3
"""Builds the README's validation table from the summary.json files of scripts/validation-table.

One table per contact model, one row per scene, one column per kernel (the potential kernels,
which have no contact model, only in the first table). A cell is PASS or FAIL (every check of the scene must
pass) with the scene's headline figure; a run that did not finish shows why (the last line of its
log). The check list of every cell follows the table, so that each figure can be traced.
"""
import argparse
import json
import pathlib

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


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("out")
    ap.add_argument("--kernels", nargs="+", required=True)
    ap.add_argument("--scenes", nargs="+", required=True)
    ap.add_argument("--models", nargs="+", default=["sub-contacts"])
    ap.add_argument("--potential", nargs="*", default=[])
    ap.add_argument("--flat", action="store_true",
                    help="runs in OUT/SCENE/KERNEL, with the scenes' own contact model")
    a = ap.parse_args()
    if a.flat:
        a.models = [""]
    out = pathlib.Path(a.out)
    details = []
    for m, model in enumerate(a.models):
        kernels = [k for k in a.kernels if m == 0 or k not in a.potential]
        print(f"contact_model = {model or 'as in the scene files'}:\n")
        print("| scene | " + " | ".join(kernels) + " |")
        print("|---" * (len(kernels) + 1) + "|")
        for scene in a.scenes:
            row = []
            for k in kernels:
                base = out / model if model else out
                text, s = cell(base / scene / k, base / scene / f"{k}.log")
                row.append(text)
                if s:
                    details.append((model, scene, k, s))
            print(f"| {scene} | " + " | ".join(row) + " |")
        print()
    for model, scene, k, s in details:
        print(f"- {scene} / {k} / {model or s.get('contact_model')}: {s['steps']} steps, {s['wall_seconds']:.1f} s wall, "
              f"hash {s['state_hash']}")
        for c in s.get("checks", []):
            print(f"  - {c['name']}: {fmt(c['value'])}{unit(c)} (expected {fmt(c['expected'])}, "
                  f"{c['compare']} {fmt(c['tolerance'])}) {'pass' if c['pass'] else 'FAIL'}")


if __name__ == "__main__":
    main()
