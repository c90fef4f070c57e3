#!/usr/bin/python3
"""Plots a probability-of-failure study (`polydem fos SCENE --realizations N --out DIR`): the
histogram of the realizations' factors of safety and their empirical CDF, with F = 1 marked and
the study's mean, sd and P(F < 1) in the title, as DIR/realizations.png.

    /usr/bin/python3 python_coupling/plots/plot_realizations.py DIR [--out DIR/realizations.png]
"""
import argparse
import csv
import json
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def plot(run_dir, out=None):
    summary = json.load(open(os.path.join(run_dir, "realizations.json")))
    factors = []
    with open(os.path.join(run_dir, "realizations.csv")) as f:
        for row in csv.DictReader(f):
            if row["factor_of_safety"]:
                factors.append(float(row["factor_of_safety"]))
    factors.sort()
    fig, (hist, cdf) = plt.subplots(1, 2, figsize=(10, 4.2))
    if factors:
        bins = max(5, min(30, len(factors) // 4))
        hist.hist(factors, bins=bins, color="tab:blue", alpha=0.8, edgecolor="white")
        n = len(factors)
        cdf.step(factors, [(i + 1) / n for i in range(n)], where="post", color="tab:blue")
    for ax in (hist, cdf):
        ax.axvline(1.0, color="tab:red", ls="--", lw=1)
        ax.set_xlabel("factor of safety F")
        ax.grid(alpha=0.3)
    hist.set_ylabel("realizations")
    cdf.set_ylabel("P(factor of safety < F)")
    cdf.set_ylim(0, 1)

    def fmt(v):
        return "-" if v is None else format(v, ".3g")

    fig.suptitle(
        f"{os.path.basename(summary['scene_path'])}: {summary['count']} realizations "
        f"({summary['resolved']} with F resolved), "
        f"mean F {fmt(summary['mean_factor_of_safety'])}, sd {fmt(summary['sd_factor_of_safety'])}, "
        f"P(F < 1) = {fmt(summary['probability_of_failure'])} "
        f"+- {fmt(summary['probability_of_failure_se'])}", fontsize=10)
    fig.tight_layout()
    out = out or os.path.join(run_dir, "realizations.png")
    fig.savefig(out, dpi=110)
    plt.close(fig)
    return out


if __name__ == "__main__":
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("dir")
    p.add_argument("--out")
    a = p.parse_args()
    print(plot(a.dir, a.out))
