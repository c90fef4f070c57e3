"""Goodman and Bray's (1976) limit-equilibrium recursion for block toppling on a stepped base
(Hoek and Bray, Rock Slope Engineering, ch. 10; Wyllie and Mah, 2004, section 9.4), with one
friction angle on the bases and between the columns. Blocks are listed from the toe (0) up."""
import math


def toe_force(phi, psi, dx, heights, bases):
    """P_0: the force the toe needs to hold the set at friction angle phi (deg), and each block's
    mode ('toppling', 'sliding', 'stable'). psi: dip of the bases (deg); dx: block width;
    heights[i]: height of block i; bases[i]: its base's level along the bases' normal. Weights
    are per unit weight and width (the sign of P_0 does not depend on them)."""
    t = math.tan(math.radians(phi))
    s, c = math.sin(math.radians(psi)), math.cos(math.radians(psi))
    n = len(heights)
    p, modes = 0.0, [""] * n
    for k in range(n - 1, -1, -1):
        y, w = heights[k], dx * heights[k]
        # Heights above block k's base of the tops of its contacts with the blocks above and below.
        m = min(y, bases[k + 1] + heights[k + 1] - bases[k]) if k + 1 < n else 0.0
        l = min(y, bases[k - 1] + heights[k - 1] - bases[k]) if k > 0 else y
        topple = (p * (m - dx * t) + 0.5 * w * (y * s - dx * c)) / l
        slide = p - w * (t * c - s) / (1.0 - t * t)
        if topple <= 0.0 and slide <= 0.0:
            modes[k], p = "stable", 0.0 if k > 0 else max(topple, slide)
        elif topple >= slide:
            modes[k], p = "toppling", topple
        else:
            modes[k], p = "sliding", slide
    return p, modes


def limit_friction(psi, dx, heights, bases):
    """The friction angle (deg) at which P_0 = 0, by bisection between psi (below it the bases
    slide whatever the toe does) and 45 deg (where 1 - tan^2 phi vanishes); and the modes just
    below it."""
    lo, hi = psi, 44.999
    if toe_force(hi, psi, dx, heights, bases)[0] > 0.0:
        raise ValueError("the set needs a toe force at 45 deg: no limit below it")
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        if toe_force(mid, psi, dx, heights, bases)[0] > 0.0:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi), toe_force(lo, psi, dx, heights, bases)[1]
