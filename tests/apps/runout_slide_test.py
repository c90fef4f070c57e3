"""polydem runout on A-RUNOUT-SLIDE-TO-REST (a block launched down an incline, sliding to rest on
it): the runout of its front and its travel against the exact answer the scene's header derives,
computed here from the scene's own inputs, within 1 % of the block's size; and a run-on stopped by
SIGTERM between two checks of rest and continued from its checkpoint ends on the same step with
the same bits.

    runout_slide_test.py POLYDEM SCENE WORKDIR
"""
import json
import math
import os
import shutil
import signal
import subprocess
import sys
import tomllib

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from scene_test_util import FAILURES, expect, run  # noqa: E402


def expected_travel(scene):
    """The block's travel down the slope, its front's horizontal runout and its size."""
    shapes = {s["name"]: s for s in scene["shape"]}
    materials = {m["name"]: m for m in scene["material"]}
    block = next(p for p in scene["particle"] if p.get("label") == "block")
    slab = next(p for p in scene["particle"] if p.get("fixed"))
    b = shapes[block["shape"]]["size"][0]
    theta = math.radians(shapes[slab["shape"]]["rotation"]["angle"])
    # A pair takes the lower of its two materials' friction angles.
    phi = min(float(materials[p["material"]]["friction_angle"]) for p in (block, slab))
    mu = math.tan(math.radians(phi))
    g = 9.81
    v0 = math.hypot(*block["velocity"])
    travel = v0 ** 2 / (2 * g * (mu * math.cos(theta) - math.sin(theta)))
    return travel, travel * math.cos(theta), b


def main():
    polydem, scene_path, workdir = sys.argv[1:4]
    shutil.rmtree(workdir, ignore_errors=True)
    os.makedirs(workdir)
    with open(scene_path, "rb") as f:
        scene = tomllib.load(f)
    travel, runout, b = expected_travel(scene)
    run([polydem, "runout", scene_path, "--out", "out", "--quiet"], workdir)
    with open(os.path.join(workdir, "out", "runout.json")) as f:
        r = json.load(f)
    expect(r["at_rest"], f"not at rest: {r['stopped_by']}")
    got = r["runout_distance"]
    print(f"runout {got:.5f} m, expected {runout:.5f} m ({(got - runout) / b:+.2%} of b)")
    expect(abs(got - runout) <= 0.01 * b, f"runout {got} m, expected {runout} m within 1 % of b = {b} m")
    moved = r["largest_block_travel"]
    print(f"travel {moved:.5f} m, expected {travel:.5f} m ({(moved - travel) / b:+.2%} of b)")
    expect(abs(moved - travel) <= 0.01 * b, f"travel {moved} m, expected {travel} m within 1 % of b")
    expect(abs(r["direction"][0] - 1) < 1e-6, f"direction {r['direction']}, expected +x")
    # Stopped by SIGTERM after its first step (held before it by the test hook), between two
    # checks of rest, and continued: the same steps and bits as the run that never stopped.
    env = dict(os.environ, POLYDEM_TEST_PAUSE="runout-start:3")
    proc = subprocess.Popen([polydem, "runout", scene_path, "--out", "stopped", "--quiet"],
                            cwd=workdir, env=env, stderr=subprocess.PIPE, text=True)
    for line in proc.stderr:
        if "test pause: runout-start" in line:
            proc.send_signal(signal.SIGTERM)
            break
    proc.communicate()
    with open(os.path.join(workdir, "stopped", "runout.json")) as f:
        s = json.load(f)
    expect(s["stopped_by"] == "SIGTERM" and s["steps"] == 1,
           f"the stop: {s['stopped_by']} at step {s['steps']}, expected SIGTERM at step 1")
    run([polydem, "runout", "--resume", "stopped", "--quiet"], workdir)
    with open(os.path.join(workdir, "stopped", "runout.json")) as f:
        c = json.load(f)
    expect(c["steps"] == r["steps"] and c["state_hash"] == r["state_hash"],
           f"continued: step {c['steps']} hash {c['state_hash']}; whole run: step {r['steps']} "
           f"hash {r['state_hash']}")
    if FAILURES:
        sys.exit(f"{len(FAILURES)} check(s) failed")
    print("runout slide to rest: all checks pass")


if __name__ == "__main__":
    main()
