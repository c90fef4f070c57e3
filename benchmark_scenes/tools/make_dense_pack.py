#!/usr/bin/env python3
"""A dense pack of aligned unit cubes in a box (the scene of `polydem bench scaling --shapes cubes
--gap -0.001`: lattice pitch 0.999 m, every face in contact from the first step), written as a
scene file. With --shuffled the cubes are listed, and so numbered and created, in random order:
storage order and uid order are then unrelated to space, as in a pile whose generator scatters
them. Used by docs/broadphase.md's storage-order measurements.

    make_dense_pack.py --side 20 --layers 5 [--shuffled] [--steps 10] > pack.toml
"""
import argparse
import random


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--side", type=int, default=20, help="cubes along x and y")
    ap.add_argument("--layers", type=int, default=5, help="cubes along z")
    ap.add_argument("--shuffled", action="store_true", help="list the cubes in random order")
    ap.add_argument("--steps", type=int, default=10)
    ap.add_argument("--seed", type=int, default=1)
    a = ap.parse_args()
    pitch = 0.999
    width = a.side * pitch
    height = a.layers * pitch + 2.0
    t = 1.0
    cells = [(ix, iy, iz) for iz in range(a.layers) for iy in range(a.side) for ix in range(a.side)]
    if a.shuffled:
        random.Random(a.seed).shuffle(cells)
    out = [
        "[scene]",
        f'id = "DENSE-PACK-{len(cells)}{"-SHUFFLED" if a.shuffled else ""}"',
        'title = "dense pack of aligned unit cubes in a box"',
        "",
        "[simulation]",
        'kernel = "gjk-epa-ipm"',
        'dt = "1e-4 s"',
        f"steps = {a.steps}",
        "",
        "[domain]",
        f"min = [{-t - 0.5}, {-t - 0.5}, {-t - 0.5}]",
        f"max = [{width + t + 0.5}, {width + t + 0.5}, {height + 0.5}]",
        "",
        "[[material]]",
        'name = "rock"',
        'density = "2650 kg/m^3"',
        'kn = "1e8 N/m"',
        'ks = "5e7 N/m"',
        "friction_angle = 30",
        "local_damping = 0.1",
        "",
        '[[shape]]\nname = "cube"\ntype = "box"\nsize = [1, 1, 1]',
        f'[[shape]]\nname = "floor"\ntype = "box"\nmin = [{-t}, {-t}, {-t}]\n'
        f"max = [{width + t}, {width + t}, 0]",
        f'[[shape]]\nname = "wall_x"\ntype = "box"\nmin = [{-t}, {-t}, 0]\nmax = [0, {width + t}, {height}]',
        f'[[shape]]\nname = "wall_y"\ntype = "box"\nmin = [0, {-t}, 0]\nmax = [{width}, 0, {height}]',
    ]
    for shape, shift in (("floor", (0, 0)), ("wall_x", (0, 0)), ("wall_x", (width + t, 0)),
                         ("wall_y", (0, 0)), ("wall_y", (0, width + t))):
        out.append(f'[[particle]]\nshape = "{shape}"\nmaterial = "rock"\nfixed = true\n'
                   f"position = [{shift[0]}, {shift[1]}, 0]")
    for ix, iy, iz in cells:
        x, y, z = ((ix + 0.5) * pitch, (iy + 0.5) * pitch, (iz + 0.5) * pitch + 0.01)
        out.append(f'[[particle]]\nshape = "cube"\nmaterial = "rock"\nposition = [{x!r}, {y!r}, {z!r}]')
    print("\n".join(out))


if __name__ == "__main__":
    main()
