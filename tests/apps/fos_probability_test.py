"""F-PROBABILITY (BENCHMARKS.md section F): `polydem fos --realizations N` on a block on an
incline whose friction angle is normal (mean, sd), on 2 ranks. Every figure is computed from the
scene file's own inputs:
  - P(F < 1) of the study within 3 binomial standard deviations of Phi((theta - mean) / sd);
  - the mean F within 3 sd(F) / sqrt(N) of E[tan(phi)] / tan(theta) (quadrature over the normal);
  - each realization's F, from the fos search of its scene, within the search's resolution and
    1 % of tan(phi_i) / tan(theta) of its own drawn friction angle (where an undecided trial left
    a search unresolved, its bracket of decided trials around it);
  - realizations.png written.
usage: fos_probability_test.py POLYDEM MPIEXEC SCENE WORKDIR N"""

import csv
import json
import math
import os
import shutil
import subprocess
import sys
import tomllib

import numpy as np

sys.path.insert(0, os.path.dirname(__file__))
from scene_test_util import FAILURES, expect  # noqa: E402


def phi_cdf(x):
    return 0.5 * math.erfc(-x / math.sqrt(2.0))


def main():
    polydem, mpiexec, scene_path, work, n = sys.argv[1:6]
    n = int(n)
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    scene = tomllib.load(open(scene_path, "rb"))
    theta = next(s for s in scene["shape"] if s["name"] == "incline")["rotation"]["angle"]
    (entry,) = scene["random"]
    expect(entry["parameter"] == "material.rock.friction_angle"
           and entry["distribution"] == "normal", f"the scene's random input: {entry}")
    mean, sd = entry["mean"], entry["sd"]
    resolution = scene["fos"]["resolution"]

    mpi = [mpiexec, "-n", "2", "--oversubscribe"] + (["--allow-run-as-root"]
                                                     if os.geteuid() == 0 else [])
    out = subprocess.run(mpi + [polydem, "fos", scene_path, "--realizations", str(n), "--out",
                                "pof"], cwd=work, capture_output=True, text=True)
    print(out.stdout[-2000:], out.stderr[-2000:])
    if out.returncode != 0:
        sys.exit(f"polydem fos --realizations failed with exit status {out.returncode}")
    summary = json.load(open(os.path.join(work, "pof", "realizations.json")))
    rows = list(csv.DictReader(open(os.path.join(work, "pof", "realizations.csv"))))
    expect(summary["complete"] and summary["count"] == n and len(rows) == n,
           f"{n} realizations: {summary['count']} in the summary, {len(rows)} rows")
    # Each realization: its F (or, where an undecided trial left the search unresolved, its
    # bracket of decided trials) agrees with tan(phi) / tan(theta) of its own draw.
    tan_t = math.tan(math.radians(theta))
    for r in rows:
        phi = float(r[entry["parameter"]])
        exact = math.tan(math.radians(phi)) / tan_t
        what = f"realization {r['realization']}: phi {phi:.4f} deg, tan(phi)/tan(theta) {exact:.4f}"
        if r["factor_of_safety"]:
            f = float(r["factor_of_safety"])
            expect(abs(f - exact) <= 0.5 * resolution + 0.01 * exact, f"{what}, F {f:.4f}")
        else:
            print(f"{what}: {r['outcome']}, bracket [{r['stable']}, {r['failed']}]")
            expect(r["stable"] and r["failed"], f"{what}: {r['outcome']} without a bracket")
            expect(float(r["stable"]) <= 1.01 * exact <= 1.02 * float(r["failed"]),
                   f"{what}: bracket [{r['stable']}, {r['failed']}]")
    resolved = summary["resolved"]
    expect(resolved >= 0.9 * n, f"F resolved in {resolved} of {n} realizations only")

    # P(F < 1) over the realizations whose F < 1 or not is known (resolved, or bracketed on
    # one side of 1).
    known = summary["known"]
    expect(known == n, f"F < 1 or not known for {known} of {n} realizations")
    p = phi_cdf((theta - mean) / sd)
    band = 3.0 * math.sqrt(p * (1.0 - p) / known)
    pof = summary["probability_of_failure"]
    print(f"P(F < 1) = {pof:.4f} over {known}; Phi((theta - mean) / sd) = {p:.4f}, "
          f"3 sd = {band:.4f}")
    expect(abs(pof - p) <= band, f"P(F < 1) {pof:.4f} not within {band:.4f} of {p:.4f}")

    x = np.linspace(mean - 8 * sd, mean + 8 * sd, 20001)
    w = np.exp(-0.5 * ((x - mean) / sd) ** 2)
    expected_mean = float(np.sum(w * np.tan(np.radians(x))) / np.sum(w)) / tan_t
    m, s = summary["mean_factor_of_safety"], summary["sd_factor_of_safety"]
    print(f"mean F = {m:.4f} (sd {s:.4f}); E[tan phi] / tan theta = {expected_mean:.4f}")
    expect(abs(m - expected_mean) <= 3.0 * s / math.sqrt(resolved),
           f"mean F {m:.4f} not within 3 sd/sqrt(N) of {expected_mean:.4f}")
    expect(os.path.getsize(os.path.join(work, "pof", "realizations.png")) > 0,
           "realizations.png written")
    sys.exit(1 if FAILURES else 0)


if __name__ == "__main__":
    main()
