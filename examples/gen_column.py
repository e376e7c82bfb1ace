#!/usr/bin/env python3
"""Writes a loose column of equal grains (x,y,z,r CSV, no header) for the example scenes.

Grains sit on a square lattice of spacing 2.2 r inside a circle, layer after layer, each
centre moved by a small seeded jitter so the pour is not perfectly regular.
usage: gen_column.py N RADIUS CIRCLE_RADIUS Z0 OUT.csv [SEED]
"""
import math
import random
import sys


def main():
    n, r, rc, z0, out = int(sys.argv[1]), float(sys.argv[2]), float(sys.argv[3]), float(sys.argv[4]), sys.argv[5]
    rng = random.Random(int(sys.argv[6]) if len(sys.argv) > 6 else 1)
    h = 2.2 * r
    sites = []
    k = int(rc / h) + 1
    for i in range(-k, k + 1):
        for j in range(-k, k + 1):
            x, y = i * h, j * h
            if math.hypot(x, y) + r <= rc:
                sites.append((x, y))
    rows = []
    layer = 0
    while len(rows) < n:
        z = z0 + layer * h
        for x, y in sites:
            if len(rows) == n:
                break
            jx, jy, jz = (rng.uniform(-0.05, 0.05) * r for _ in range(3))
            rows.append((x + jx, y + jy, z + jz, r))
        layer += 1
    with open(out, "w") as f:
        for row in rows:
            f.write(",".join(f"{v:.9g}" for v in row) + "\n")


if __name__ == "__main__":
    main()
