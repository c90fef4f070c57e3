#!/usr/bin/python3
"""The separation time of the front block of D-PILLAR in one dimension: a chain of 6 blocks of
75 kg joined by compression-only springs of 1 GN/m, struck by a quarter of the 3900 kg projectile
at 50 m/s (it strikes 2 x 2 columns). Integrated with a time step of 1e-8 s; prints the time the
last spring stops pressing, beside the wave-speed estimate t = 6 L / V, V = L sqrt(kn / m).

Run: /usr/bin/python3 benchmark_scenes/tools/pillar_chain.py   (numpy only)
"""
import math

import numpy as np


def separation_time(blocks=6, kn=1e9, mass=75.0, striker=3900.0 / 4, speed=50.0, dt=1e-8,
                    min_force=1e4):
    masses = np.array([striker] + [mass] * blocks)
    u = np.zeros(blocks + 1)       # displacements along the impact, striker first
    v = np.zeros(blocks + 1)
    v[0] = speed
    pressed, t = False, 0.0
    while t < 1e-2:
        squeeze = u[:-1] - u[1:]   # shortening of each spring
        f = kn * np.maximum(squeeze, 0.0)
        force = np.zeros_like(u)
        force[:-1] -= f
        force[1:] += f
        v += force / masses * dt    # symplectic Euler, as the leapfrog of polydem
        u += v * dt
        t += dt
        if f[-1] > min_force:
            pressed = True
        elif pressed:
            return t
    return math.nan


if __name__ == "__main__":
    t = separation_time()
    wave = 6 / math.sqrt(1e9 / 75.0)
    print(f"chain of 6 blocks: the front block leaves at t = {t:.4e} s")
    print(f"wave-speed estimate 6 L / V = {wave:.4e} s ({100 * (t / wave - 1):+.1f} %)")
