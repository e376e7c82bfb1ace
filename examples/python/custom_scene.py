# A scene built from Python with the generic DEM core: grains poured into a cylinder made of
# facets onto a floor plane, then a lid pressed down on them; the lid's force is printed.
#   PYTHONPATH=build/python /usr/bin/python3 examples/python/custom_scene.py
# VPPDEM_SCENE_STEPS shortens the run (the smoke test).
import math
import os

import numpy as np

import vppdem

steps = int(os.environ.get("VPPDEM_SCENE_STEPS", "20000"))
R, H, r = 0.02, 0.06, 0.002  # [m] cylinder radius, height, grain radius

w = vppdem.World()
glass = w.add_material("glass", density=2500.0, young=5e7, friction=0.4, restitution=0.5)  # [kg/m^3], [Pa]
w.add_plane([0, 0, 0], [0, 0, 1], material=glass)  # floor (wall 0)

# The cylinder's side: 48 quads of two triangles each, from vertex arrays.
n = 48
tris = []
for k in range(n):
    a, b = 2 * math.pi * k / n, 2 * math.pi * (k + 1) / n
    p0, p1 = [R * math.cos(a), R * math.sin(a)], [R * math.cos(b), R * math.sin(b)]
    tris.append([[*p0, 0], [*p1, 0], [*p1, H]])
    tris.append([[*p0, 0], [*p1, H], [*p0, H]])
w.add_facets(np.array(tris), material=glass)

# Grains on a loose lattice inside the cylinder, slightly jittered (a fixed seed: reproducible).
rng = np.random.default_rng(1)
s = 2.2 * r
for z in np.arange(r * 1.5, H - r, s):
    for x in np.arange(-R + 2 * r, R - 2 * r, s):
        for y in np.arange(-R + 2 * r, R - 2 * r, s):
            if math.hypot(x, y) < R - 1.5 * r:
                w.add_sphere([x, y, z] + rng.uniform(-0.05, 0.05, 3) * r, r, material=glass)
w.dt = 0.2 * w.critical_dt()  # [s]
w.local_damping = 0.3
print(f"{len(w)} grains, dt = {w.dt:.3g} s")

w.step(steps)  # pour
top = w.positions[:, 2].max() + r
lid = w.add_plane([0, 0, top + 1e-3], [0, 0, -1], material=glass)  # wall `lid`
w.set_plane_motion(lid, velocity=[0, 0, -0.05])                  # [m/s] down
w.step(steps // 4)
print(f"t = {w.time:.4f} s: grains top {top:.4f} m, lid force {w.wall_force(lid)[2]:.4g} N, "
      f"floor force {w.wall_force(0)[2]:.4g} N, mean speed {np.linalg.norm(w.velocities, axis=1).mean():.3g} m/s")
