#!/usr/bin/env python3
"""Plots a `vppdem sweep` output folder.

usage: plot_sweep.py DIR

Reads DIR/summary.csv (header: the swept keys in [grid] order, then
`W,dissipated_energy,peak_force,run_seconds,status,case`) and each finished case's
DIR/<case>/forces.csv (`time,displacement,force_total,...,cycle`), and writes
  DIR/sweep_W.png      W [J/m^2] of the last cycle against the first swept key, one line per
                       combination of the other swept keys (e.g. W against radius, one line per
                       underpressure)
  DIR/sweep_loops.png  the last cycle's loop (force_total against displacement) of every case,
                       one panel per combination of the other swept keys, one colour per value of
                       the first key
Cases whose status is not "ok" are left out. Exits nonzero with a message when summary.csv is
missing or holds no finished case. Runs under Debian's /usr/bin/python3 (matplotlib, numpy).
"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

TAIL = ["W", "dissipated_energy", "peak_force", "run_seconds", "status", "case"]


def fail(msg):
    print(f"plot_sweep.py: {msg}", file=sys.stderr)
    sys.exit(1)


def as_number(s):
    try:
        return float(s)
    except ValueError:
        return None


def pretty(key, value):
    """Axis-friendly value: MPa for underpressures, mm for lengths."""
    v = as_number(value)
    if v is None:
        return value
    if key == "process.underpressure":
        return f"{v * 1e-6:g} MPa"
    if key in ("damper.radius", "damper.height", "grains.radius", "process.amplitude"):
        return f"{v * 1e3:g} mm"
    return f"{v:g}"


def read_summary(d):
    path = os.path.join(d, "summary.csv")
    if not os.path.exists(path):
        fail(f"{path} not found (not a sweep folder)")
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    if not rows:
        fail(f"{path} is empty")
    header = rows[0]
    if "W" not in header:
        fail(f"{path}: no column W (columns: {', '.join(header)})")
    keys = header[: header.index("W")]
    cases = []
    for r in rows[1:]:
        rec = dict(zip(header, r))
        if rec.get("status") != "ok":
            continue
        cases.append(rec)
    if not cases:
        fail(f"{path}: no finished case (status ok)")
    return keys, cases


def read_forces(path):
    with open(path, newline="") as f:
        rows = [r for r in csv.reader(f) if r and not r[0].startswith("#")]
    header = rows[0]
    data = np.array([[float(x) for x in r] for r in rows[1:]])
    return {h: data[:, k] for k, h in enumerate(header)}


def main():
    if len(sys.argv) != 2:
        fail("usage: plot_sweep.py DIR")
    d = sys.argv[1]
    keys, cases = read_summary(d)
    xkey = keys[0] if keys else None
    others = keys[1:]

    def group_of(c):
        return tuple(c[k] for k in others)

    groups = []
    for c in cases:
        if group_of(c) not in groups:
            groups.append(group_of(c))

    def group_label(g):
        return ", ".join(f"{k} = {pretty(k, v)}" for k, v in zip(others, g)) or "all cases"

    # W against the first key.
    fig, ax = plt.subplots(figsize=(6.4, 4.6))
    for g in groups:
        members = [c for c in cases if group_of(c) == g]
        xs = [c[xkey] for c in members] if xkey else ["base"]
        num = [as_number(x) for x in xs]
        ys = [float(c["W"]) for c in members]
        if all(v is not None for v in num):
            order = np.argsort(num)
            xv = np.array(num)[order]
            if xkey in ("damper.radius", "damper.height", "process.amplitude"):
                xv = xv * 1e3
            ax.plot(xv, np.array(ys)[order], "o-", label=group_label(g))
        else:
            ax.plot(range(len(xs)), ys, "o-", label=group_label(g))
            ax.set_xticks(range(len(xs)), xs)
    xlabel = xkey or "case"
    if xkey in ("damper.radius", "damper.height", "process.amplitude"):
        xlabel += " [mm]"
    if xkey == "grains.young" and all(as_number(c[xkey]) for c in cases):
        ax.set_xscale("log")
        xlabel += " [Pa]"
    ax.set_xlabel(xlabel)
    ax.set_ylabel("W of the last cycle [J/m$^2$]")
    ax.grid(True, alpha=0.3)
    if others:
        ax.legend(fontsize=8)
    ax.set_title(os.path.basename(os.path.abspath(d)))
    fig.tight_layout()
    fig.savefig(os.path.join(d, "sweep_W.png"), dpi=130)
    plt.close(fig)

    # Loops of the last cycle, one panel per group.
    n = len(groups)
    cols = min(n, 4)
    rows = (n + cols - 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(4.6 * cols, 3.8 * rows), squeeze=False)
    for gi, g in enumerate(groups):
        ax = axes[gi // cols][gi % cols]
        members = [c for c in cases if group_of(c) == g]
        cmap = plt.get_cmap("viridis")
        for k, c in enumerate(members):
            path = os.path.join(d, c["case"], "forces.csv")
            if not os.path.exists(path):
                continue
            f = read_forces(path)
            last = f["cycle"] == f["cycle"].max()
            colour = cmap(k / max(1, len(members) - 1))
            label = pretty(xkey, c[xkey]) if xkey else c["case"]
            ax.plot(1e3 * f["displacement"][last], f["force_total"][last], color=colour, lw=1.2, label=label)
        ax.set_xlabel("displacement [mm] (compression +)")
        ax.set_ylabel("force [N] (compression +)")
        ax.set_title(group_label(g), fontsize=9)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7, title=xkey, title_fontsize=7)
    for gi in range(n, rows * cols):
        axes[gi // cols][gi % cols].axis("off")
    fig.suptitle("last cycle of each case")
    fig.tight_layout()
    fig.savefig(os.path.join(d, "sweep_loops.png"), dpi=110)
    plt.close(fig)
    print(f"wrote {os.path.join(d, 'sweep_W.png')} and sweep_loops.png")


if __name__ == "__main__":
    main()
