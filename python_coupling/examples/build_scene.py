"""A whole scene built in Python, without a scene file: a block sliding down a plane (Coulomb
friction) beside a few cubes dropped onto it, run, checkpointed, restarted and compared.

    /usr/bin/python3 python_coupling/examples/build_scene.py --out build_scene_run
    mpirun -n 2 /usr/bin/python3 python_coupling/examples/build_scene.py --out build_scene_run

It writes OUT/scene.toml (the scene as a scene file: `polydem run OUT/scene.toml` makes the same
run) and OUT/half.h5 (a checkpoint half-way), and prints the block's acceleration beside the
rigid-block law and the state hashes of the uninterrupted and the restarted run, which are equal.
"""
import argparse
import math
import os

import polydem

G = 9.81


def build(tilt_deg=30.0, friction_deg=20.0, steps=4000):
    """The plane is a fixed slab, horizontal; gravity is tilted by `tilt_deg` instead."""
    t = math.radians(tilt_deg)
    s = polydem.Scene("build-scene-example", title="Block on an inclined plane, cubes falling",
                      dt=2e-5, steps=steps, gravity=(G * math.sin(t), 0, -G * math.cos(t)))
    s.add_material("rock", density=2650, kn=2e9, ks=1e9, friction_angle=friction_deg,
                   normal_damping=0.3)
    s.add_shape("slab", type="box", min=(-3, -3, -1), max=(8, 3, 0))
    s.add_shape("block", box=(1, 1, 0.5))
    s.add_shape("cube", type="cube", edge=0.4)
    s.add_particle("slab", "rock", fixed=True, label="slab")
    sink = 2650 * 0.5 * G * math.cos(t) / 2e9  # static overlap of the contact springs
    block = s.add_particle("block", "rock", position=(0, 0, 0.25 - sink), label="block")
    s.add_particle_grid("cube", "rock", count=(3, 1, 1), spacing=1.0, origin=(3, 1.5, 0.21),
                        label_prefix="cube")
    s.set_output(monitor=["block"])
    return s, block


def velocity_of(sim, uid):
    p = sim.particles(gather=True)
    return p["velocity"][list(p["uid"]).index(uid)]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", default="build_scene_run")
    parser.add_argument("--steps", type=int, default=4000)
    args = parser.parse_args()
    polydem.set_log_level("warning")
    root = polydem.mpi_rank() == 0
    if root:
        os.makedirs(args.out, exist_ok=True)

    tilt, friction = 30.0, 20.0
    scene, block = build(tilt, friction, args.steps)
    if root:
        scene.save(os.path.join(args.out, "scene.toml"))

    # The uninterrupted run, with the block's acceleration measured over the second half.
    sim = polydem.Simulation(scene)
    half = args.steps // 2
    sim.step(half)
    v1, t1 = velocity_of(sim, block), sim.time
    checkpoint = os.path.join(args.out, "half.h5")
    sim.write_checkpoint(checkpoint)
    sim.run()
    v2, t2 = velocity_of(sim, block), sim.time
    whole = sim.state_hash()
    a = (v2[0] - v1[0]) / (t2 - t1)
    t, f = math.radians(tilt), math.radians(friction)
    law = G * (math.sin(t) - math.tan(f) * math.cos(t))

    # The same run continued from the checkpoint (any rank count would do).
    restarted = polydem.Simulation.restart(checkpoint)
    restarted.run()
    again = restarted.state_hash()
    contacts = restarted.contacts()
    if root:
        print("block acceleration %.4f m/s^2; rigid block with Coulomb friction %.4f m/s^2"
              % (a, law))
        print("contacts on rank 0 at the end: %d" % len(contacts["uids"]))
        print("state hash, uninterrupted: %s" % whole)
        print("state hash, restarted:     %s" % again)
        print("same bits" if whole == again else "DIFFERENT")
    raise SystemExit(0 if whole == again else 1)


if __name__ == "__main__":
    main()
