"""Side views of a device run: the particles of VTK frames in a slab about the plane y = 0.

    python3 -m vppdem.report device_slices OUT.png FRAME.vtk [FRAME.vtk ...]
        [--titles "a,b,..."] [--sphere R] [--cylinder R,H,Z] [--grain-radius r] [--grain-material M]

Grains (radius above --grain-radius, or with --grain-material M the particles of material M: a
bag whose grains and membrane particles have one radius, orange) within 1.1 of their radius of
the plane, the membrane (blue) within 1.1 of its; --sphere R draws the gripper's object, a sphere
of radius R [mm] about the origin, --cylinder R,H,Z a cylinder of radius R and height H standing
on z = Z [mm]. docs/devices_gripper.png is

    python3 -m vppdem.report device_slices docs/devices_gripper.png out/gripper/vtk/stage_{0_fill,2_press,3_vacuum,4_load}.vtk \\
        --sphere 6 --titles "after the fill,after the press (2 N),after the vacuum (50 kPa),the object let go"

and docs/devices_gripper_jamming.png (the frames of `vppdem device examples/devices/gripper_jamming.toml
--out out/gripper_jamming`)

    python3 -m vppdem.report device_slices docs/devices_gripper_jamming.png \
        out/gripper_jamming/vtk/stage_{1_seal,2_press,3_vacuum,4_load}.vtk --cylinder 6,12,-6 --grain-material 1 \
        --titles "at the seal,after the press (16 N),after the vacuum (50 kPa),the object let go"
"""
import argparse

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.patches import Circle, Rectangle


def load(path):
    """Points [m] and radii [m] of a vppdem particles frame (legacy ASCII VTK)."""
    lines = open(path).read().split("\n")
    start = next(k for k, l in enumerate(lines) if l.startswith("POINTS"))
    n = int(lines[start].split()[1])
    pts = np.array([[float(v) for v in lines[start + 1 + k].split()] for k in range(n)])
    at = next(k for k, l in enumerate(lines) if l.startswith("SCALARS radius")) + 2  # after LOOKUP_TABLE
    radius = np.array([float(lines[at + k]) for k in range(n)])
    return pts, radius


def materials(path):
    """The material of each particle of a frame (its SCALARS material), or None without them."""
    lines = open(path).read().split("\n")
    n = int(next(l for l in lines if l.startswith("POINTS")).split()[1])
    at = next((k for k, l in enumerate(lines) if l.startswith("SCALARS material")), None)
    if at is None:
        return None
    return np.array([int(lines[at + 2 + k]) for k in range(n)])


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("out")
    ap.add_argument("frames", nargs="+")
    ap.add_argument("--titles", default="")
    ap.add_argument("--sphere", type=float, default=0.0, help="[mm] the object's radius (0: none)")
    ap.add_argument("--cylinder", default="", help="R,H,Z [mm]: the object, a cylinder of radius R, height H, base at z = Z")
    ap.add_argument("--grain-radius", type=float, default=0.6, help="[mm] particles larger than this are grains")
    ap.add_argument("--grain-material", type=int, default=None, help="the grains' material (instead of --grain-radius)")
    a = ap.parse_args(argv)
    titles = a.titles.split(",") if a.titles else [f.split("/")[-1] for f in a.frames]
    frames = [load(f) for f in a.frames]
    grain = []
    for f, (_, r) in zip(a.frames, frames):
        if a.grain_material is None:
            grain.append(r * 1e3 > a.grain_radius)
        else:
            m = materials(f)
            if m is None:
                ap.error(f"{f}: no SCALARS material for --grain-material")
            grain.append(m == a.grain_material)
    cyl = [float(v) for v in a.cylinder.split(",")] if a.cylinder else None
    lo = np.min([p.min(axis=0) for p, _ in frames], axis=0) * 1e3  # one scale for every panel
    hi = np.max([p.max(axis=0) for p, _ in frames], axis=0) * 1e3
    fig, axs = plt.subplots(1, len(a.frames), figsize=(4 * len(a.frames), 4.5))
    for ax, (p, r), g, title in zip(np.atleast_1d(axs), frames, grain, titles):
        p, r = p * 1e3, r * 1e3
        near = np.abs(p[:, 1]) < 1.1 * r
        for q, rr, gg in zip(p[near], r[near], g[near]):
            ax.add_patch(Circle((q[0], q[2]), rr, color="tab:orange" if gg else "tab:blue", alpha=0.7))
        if a.sphere > 0:
            ax.add_patch(Circle((0, 0), a.sphere, fill=False, color="k"))
        if cyl:
            ax.add_patch(Rectangle((-cyl[0], cyl[2]), 2 * cyl[0], cyl[1], fill=False, color="k"))
        ax.set_xlim(min(lo[0], -a.sphere) - 2, max(hi[0], a.sphere) + 2)
        ax.set_ylim(min(lo[2], -a.sphere) - 2, hi[2] + 2)
        ax.set_aspect("equal")
        ax.set_title(title, fontsize=10)
        ax.set_xlabel("x [mm]")
        ax.set_ylabel("z [mm]")
    plt.tight_layout()
    plt.savefig(a.out, dpi=70)


if __name__ == "__main__":
    main()
