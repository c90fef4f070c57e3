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
        "tools/make_tilt_table.py); each slope alone (docs/validation.md, tools/tilt_study.py): "
        "the sliding slopes (s2, s4, s5) start at atan(mu) = 25.99 deg (onsets 25.95-26.16) and "
        "s2 and s4 reach 2 mm as a rigid block does at 0.03 rad/s, at 26.57 deg (s2's onset lies "
        "in its range 25.0-26.3; s4's 23.0-24.9 and s5's 19.5-21.8 lie below atan(mu)); the "
        "staircases s1 and s3 topple at or "
        "beyond Goodman and Bray's limit for their columns (s1 25.17, s3 14.03 deg on the flat "
        "platform), above the experiment's 22.1-24.2 and 9.8-11.6 unless the columns stand on "
        "treads 0.12-0.15 m high or more; the distance potential moves s3 by under 0.8 deg")

KNOWN_FAILURES = [
    ("D-PILLAR", "*", "vs wave speed",
     "the paper's contacts were twice as stiff: its eq. 44 measures kn = F / delta = rho V^2 = "
     "1.99e9 N/m, not the scene's E L = 1e9; with that kn the front block leaves at 1.70e-3 s "
     "on gjk-epa-ipm (+3.6 %, a chain of 6 masses: 1.70e-3) and 1.74e-3 on the distance "
     "potential (+6.0 %), with 1e9 at 2.41e-3 (docs/validation.md, tools/pillar_study.py)"),
    ("A-TILT-TABLE", "*", "s1: failure angle", TILT),
    ("A-TILT-TABLE", "*", "s2: failure angle", TILT),
    ("A-TILT-TABLE", "*", "s3: failure angle", TILT),
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
