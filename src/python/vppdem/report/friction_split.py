"""Where the dissipated energy goes, against grain friction: stacked bars of the friction,
local-damping and viscous dissipation of one cycle, read from damper runs' cycles.csv.

usage: python3 -m vppdem.report friction_split OUT.png DIR [DIR ...] [--cycle N]
Each DIR is a `vppdem damper` output folder; its grain friction is read from summary.json.
Runs under Debian's /usr/bin/python3 (matplotlib, numpy).
"""
import argparse
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from ..records import fail, read_table


def main(argv=None):
    ap = argparse.ArgumentParser()
    ap.add_argument("out")
    ap.add_argument("dirs", nargs="+")
    ap.add_argument("--cycle", type=int, default=-1, help="cycle to show (default: the last)")
    a = ap.parse_args(argv)
    rows = []
    for d in a.dirs:
        with open(os.path.join(d, "summary.json")) as f:
            s = json.load(f)
        mu = s["inputs"]["grains.friction"]
        lam = s["inputs"]["simulation.local_damping"]
        _, cyc = read_table(os.path.join(d, "cycles.csv"))
        if not cyc or "friction_dissipation" not in cyc[0]:
            fail(f"{d}/cycles.csv has no dissipation columns (run with output.energy = true)")
        c = cyc[a.cycle] if a.cycle < 0 else cyc[a.cycle - 1]
        rows.append((mu, lam, float(c["dissipated_energy"]), float(c["friction_dissipation"]),
                     float(c["damping_dissipation"]), float(c["viscous_dissipation"]), int(c["cycle"])))
    rows.sort()
    labels = [f"{r[0]:g}" for r in rows]
    fr = [r[3] for r in rows]
    dm = [r[4] for r in rows]
    vi = [r[5] for r in rows]
    loop = [r[2] for r in rows]
    fig, ax = plt.subplots(figsize=(7, 4.5))
    x = range(len(rows))
    ax.bar(x, fr, label="Coulomb friction (slip + released springs)", color="tab:orange")
    ax.bar(x, dm, bottom=fr, label=f"local damping (lambda = {rows[0][1]:g})", color="tab:blue")
    ax.bar(x, vi, bottom=[f + d for f, d in zip(fr, dm)], label="viscous", color="tab:gray")
    ax.plot(list(x), loop, "k_", markersize=30, mew=2, label="loop area (boundary work)")
    for i, r in enumerate(rows):
        tot = r[3] + r[4] + r[5]
        if tot > 0:
            # Many bars: the share alone (the legend says what it is), so labels do not overlap.
            label = f"{100 * r[3] / tot:.0f}%" if len(rows) > 6 else f"{100 * r[3] / tot:.0f}% friction"
            ax.text(i, tot * 1.02, label, ha="center", fontsize=8)
    ax.set_ylim(0, 1.15 * max(max(f + d + v for f, d, v in zip(fr, dm, vi)), max(loop)))
    ax.set_xticks(list(x))
    ax.set_xticklabels(labels)
    ax.set_xlabel("grain friction coefficient mu")
    ax.set_ylabel(f"energy dissipated in cycle {rows[0][6]} [J]")
    ax.set_title("Where the energy goes (paper's damper, dp = 0.06 MPa)")
    ax.legend(fontsize=8, loc="upper left")
    ax.grid(axis="y", alpha=0.3)
    fig.tight_layout()
    fig.savefig(a.out, dpi=110)
    print(a.out)


if __name__ == "__main__":
    main(sys.argv[1:])
