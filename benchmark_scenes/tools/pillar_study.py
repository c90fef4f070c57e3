#!/usr/bin/python3
"""D-PILLAR with the contact stiffness of Zhao's own numbers, on the default kernel and on the
distance potential; writes the table of docs/validation.md ("D-PILLAR: the contact stiffness the
paper's numbers imply").

Zhao's eq. 44 measures E as F / delta of a contact (N/m) and eq. 43 then takes V = sqrt(E / rho):
its V = 1819.5 m/s means F / delta = rho V^2 = 600 x 1819.5^2 = 1.986e9 N/m between the 0.5 m
cubes. Each case is D-PILLAR with only its stiffness changed:

  gjk-epa-ipm        kn = ks = the stiffness (N/m).
  distance-potential penalty = kn / (S (1/r_A + 1/r_B)) (docs/kernels/distance-potential.md: the
                     slab's stiffness), S = 0.25 m^2 the cubes' face, r = 0.25 m their inradius:
                     penalty (Pa) = kn / 2 m.

The front block's separation time is D-PILLAR's `pair_separation` check; beside it, the same
chain of six masses on compression-only springs of that kn (pillar_chain.py).

Run from the repository root (1 rank each, one after another, nice -n 10):
  /usr/bin/python3 benchmark_scenes/tools/pillar_study.py --out results/pillar-study
"""
import argparse
import json
import math
import os
import re
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import pillar_chain  # noqa: E402

SCENE = "benchmark_scenes/D-PILLAR.toml"
RHO, V_PAPER, EDGE = 600.0, 1819.5, 0.5
KN_PAPER = RHO * V_PAPER**2        # N/m: F / delta by Zhao's eqs. 43-44
SLAB = 0.25 * (2 / 0.25)           # m: S (1/r_A + 1/r_B) of two 0.5 m cubes
CASES = {  # name: (kernel, kn N/m)
    "gjk-kn-1e9": ("gjk-epa-ipm", 1e9),
    "gjk-kn-paper": ("gjk-epa-ipm", KN_PAPER),
    "dp-kn-paper": ("distance-potential", KN_PAPER),
    "dp-penalty-2GPa": ("distance-potential", 2e9 * SLAB),
}


def scene_text(kn):
    """D-PILLAR with kn = ks = kn and the distance potential's penalty giving the same kn."""
    with open(SCENE) as f:
        text = f.read()
    text, n1 = re.subn(r'^kn = "1 GN/m"', f'kn = "{kn:.6g} N/m"', text, flags=re.M)
    text, n2 = re.subn(r'^ks = "1 GN/m"', f'ks = "{kn:.6g} N/m"', text, flags=re.M)
    text, n3 = re.subn(r'^penalty = ".*$', f'penalty = "{kn / SLAB:.6g} Pa"', text,
                       flags=re.M)
    assert n1 == n2 == n3 == 2, "D-PILLAR's materials changed: update pillar_study.py"
    return text


def run_case(name, root):
    kernel, kn = CASES[name]
    os.makedirs(root, exist_ok=True)
    scene_file = os.path.join(root, f"{name}.toml")
    with open(scene_file, "w") as f:
        f.write(scene_text(kn))
    out = os.path.join(root, name)
    cmd = ["nice", "-n", "10", "build/bin/polydem", "run", scene_file, "--out", out,
           "--no-snapshots", "--quiet", "--kernel", kernel]
    t0 = time.time()
    subprocess.run(cmd, check=False)
    wall = time.time() - t0
    with open(os.path.join(out, "summary.json")) as f:
        checks = json.load(f)["checks"]
    t = next(c["value"] for c in checks if c["name"] == "front block separation vs wave speed")
    r = {"name": name, "kernel": kernel, "kn": kn, "penalty": kn / SLAB,
         "t": math.nan if t is None else t, "chain": pillar_chain.separation_time(kn=kn),
         "wall": wall, "command": " ".join(cmd)}
    with open(os.path.join(root, f"{name}.json"), "w") as f:
        json.dump(r, f, indent=1)
    return r


def table(root):
    lines = ["| case | kernel | kn (N/m) | penalty (Pa) | front block leaves at (s) "
             "| chain of 6 masses, same kn (s) | against 1.64e-3 s | wall (s) | command |",
             "|---|---|---|---|---|---|---|---|---|"]
    for name in CASES:
        path = os.path.join(root, f"{name}.json")
        if not os.path.exists(path):
            continue
        with open(path) as f:
            r = json.load(f)
        pen = f"{r['penalty']:.4g}" if r["kernel"] == "distance-potential" else "-"
        lines.append(f"| {name} | {r['kernel']} | {r['kn']:.4g} | {pen} | {r['t']:.4g} "
                     f"| {r['chain']:.4g} | {100 * (r['t'] / 1.64e-3 - 1):+.1f} % "
                     f"| {r['wall']:.0f} | `{r['command']}` |")
    text = "\n".join(lines) + "\n"
    with open(os.path.join(root, "table.md"), "w") as f:
        f.write(text)
    return text


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--cases", nargs="*", default=list(CASES), help=f"some of {list(CASES)}")
    ap.add_argument("--out", default="results/pillar-study")
    ap.add_argument("--table", help="only write the table of the runs under this folder")
    args = ap.parse_args()
    if args.table:
        print(table(args.table), end="")
        return
    for name in args.cases:
        if name not in CASES:
            sys.exit(f"pillar_study.py: unknown case '{name}' (known: {', '.join(CASES)})")
    for name in args.cases:
        r = run_case(name, args.out)
        print(f"{name}: {r['t']:.4g} s (chain {r['chain']:.4g} s), {r['wall']:.0f} s wall",
              flush=True)
    print(table(args.out), end="")


if __name__ == "__main__":
    main()
