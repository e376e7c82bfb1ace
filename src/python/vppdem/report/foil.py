"""Renders a foil VTK frame (legacy PolyData written by vppdem: points + bond lines) to PNG.

Two panels: a perspective view of the membrane (bonds as lines, coloured by distance from the
axis) and a top view, so folds and the collapse of the cross-section are both visible.
usage: python3 -m vppdem.report foil FRAME.vtk OUT.png [--title TEXT]
Runs under Debian's /usr/bin/python3 (matplotlib, numpy).
"""
import argparse
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib import cm  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Line3DCollection  # noqa: E402


def read_vtk(path):
    with open(path) as f:
        tok = f.read().split("\n")
    i = 0
    pts, lines = None, []
    while i < len(tok):
        line = tok[i].strip()
        if line.startswith("POINTS"):
            n = int(line.split()[1])
            pts = np.array([[float(v) for v in tok[i + 1 + k].split()] for k in range(n)])
            i += n
        elif line.startswith("LINES"):
            n = int(line.split()[1])
            lines = [tuple(int(v) for v in tok[i + 1 + k].split()[1:3]) for k in range(n)]
            i += n
        i += 1
    return pts, np.array(lines, dtype=int).reshape(-1, 2)


def main(argv=None):
    ap = argparse.ArgumentParser()
    ap.add_argument("frame")
    ap.add_argument("out")
    ap.add_argument("--title", default="")
    a = ap.parse_args(argv)
    pts, lines = read_vtk(a.frame)
    r = np.hypot(pts[:, 0], pts[:, 1])
    fig = plt.figure(figsize=(11, 5.2))
    ax = fig.add_subplot(1, 2, 1, projection="3d")
    segs = pts[lines] * 1e3 if len(lines) else np.zeros((0, 2, 3))
    colour = cm.viridis((r[lines].mean(axis=1) - r.min()) / max(np.ptp(r), 1e-12)) if len(lines) else None
    ax.add_collection3d(Line3DCollection(segs, colors=colour, linewidths=0.5))
    lim = np.abs(pts[:, :2]).max() * 1e3
    ax.set_xlim(-lim, lim)
    ax.set_ylim(-lim, lim)
    ax.set_zlim(pts[:, 2].min() * 1e3, pts[:, 2].max() * 1e3)
    ax.set_box_aspect((1, 1, np.ptp(pts[:, 2]) * 1e3 / (2 * lim)))
    ax.view_init(elev=18, azim=35)
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("y [mm]")
    ax.set_zlabel("z [mm]")
    ax.set_title("foil (bonds)")
    ax2 = fig.add_subplot(1, 2, 2)
    sc = ax2.scatter(pts[:, 0] * 1e3, pts[:, 1] * 1e3, c=pts[:, 2] * 1e3, s=2, cmap="plasma")
    ax2.set_aspect("equal")
    ax2.set_xlabel("x [mm]")
    ax2.set_ylabel("y [mm]")
    ax2.set_title("top view, colour = z [mm]")
    fig.colorbar(sc, ax=ax2, shrink=0.8)
    if a.title:
        fig.suptitle(a.title)
    fig.tight_layout()
    fig.savefig(a.out, dpi=110)


if __name__ == "__main__":
    main(sys.argv[1:])
