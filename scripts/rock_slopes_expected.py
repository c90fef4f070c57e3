#!/usr/bin/python3
"""The verdicts scripts/validation-rock-slopes expects from the full-length runs of the rock-slope
scenes: every check passes except the known failures listed here, each with its reason (docs/validation.md
says the same). A verdict that differs either way is reported and gives exit status 1, so that a
fix shows up and this list and docs/validation.md get updated.

    scripts/rock_slopes_expected.py results/rock-slopes --kernels K... --scenes S...
"""
import argparse
import json
import pathlib
import sys

# (scene, kernel, part of the check's name, reason). Checks with compare = "report" never fail.
TILT = ("the slopes are reconstructed from the paper's captions (its drawings did not survive: "
        "tools/make_tilt_table.py); with sub-contacts they stand longer than the experiment's: "
        "s1 fails at 25.5 deg (22.1-24.2), s4 at 25.2 (23.0-24.9), s5 at 25.9 (19.5-21.8), and the "
        "staircase of 0.1 m cubes (s3) at 16.0 instead of 9.8-11.6; only the brick pyramid (s2) "
        "slides at the friction angle as measured (26.6, 25.0-26.3 +- 0.65). The s3 study "
        "(docs/validation.md, tools/tilt_study.py) shows the cause: on the flat platform the "
        "staircase slips 2 mm and jams, and topples 1.3-2.6 deg after Goodman and Bray's 14.0; on "
        "a stepped base it topples at their limit (onset 12.6 / 12.2 deg against 12.7, both "
        "kernels); on treads lower than a cube these columns have no limit below 11.7: the "
        "experiment's 9.8-11.6 is that of free columns 5-6 cubes high. s3 is read as sliding because its "
        "first block to move 5 cm is the top cube sliding off a toppling column")

KNOWN_FAILURES = [
    ("D-PILLAR", "*", "vs wave speed",
     "the paper's contacts were twice as stiff: its eq. 44 measures kn = F / delta = rho V^2 = "
     "1.99e9 N/m, not the scene's E L = 1e9; with that kn the front block leaves at 1.70e-3 s "
     "on gjk-epa-ipm (+3.6 %, a chain of 6 masses: 1.70e-3) and 1.74e-3 on the distance "
     "potential (+6.0 %), with 1e9 at 2.41e-3 (docs/validation.md, tools/pillar_study.py)"),
    ("A-TILT-TABLE", "*", "s1: failure angle", TILT),
    ("A-TILT-TABLE", "*", "s2: failure angle", TILT),
    ("A-TILT-TABLE", "*", "s3: failure angle", TILT),
    ("A-TILT-TABLE", "*", "s3: toppling", TILT),
    ("A-TILT-TABLE", "*", "s4: failure angle", TILT),
    ("A-TILT-TABLE", "*", "s5: failure angle", TILT),
]


def known(scene, kernel, name):
    for s, k, part, reason in KNOWN_FAILURES:
        if s == scene and k in ("*", kernel) and part in name:
            return reason
    return None


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("out")
    ap.add_argument("--kernels", nargs="+", required=True)
    ap.add_argument("--scenes", nargs="+", required=True)
    a = ap.parse_args()
    bad = 0
    for scene in a.scenes:
        for kernel in a.kernels:
            summary = pathlib.Path(a.out) / scene / kernel / "summary.json"
            if not summary.exists():
                print(f"UNEXPECTED {scene} / {kernel}: no summary.json (the run failed)")
                bad += 1
                continue
            for c in json.loads(summary.read_text())["checks"]:
                if c["compare"] == "report":
                    continue
                reason = known(scene, kernel, c["name"])
                if c["pass"] == (reason is None):
                    continue
                bad += 1
                what = "passes, listed as a known failure" if c["pass"] else "fails"
                print(f"UNEXPECTED {scene} / {kernel}: '{c['name']}' {what}: value {c['value']}"
                      f" ({c['compare']} {c['expected']}){' [' + reason + ']' if reason else ''}")
    print(f"{bad} unexpected verdict(s)")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
