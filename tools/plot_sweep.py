#!/usr/bin/env python3
"""Plots a `vppdem sweep` output folder.

usage: plot_sweep.py DIR [--caption TEXT] [--prefix NAME]

Reads DIR/summary.csv (header: the swept keys in [grid] order, then
`W,dissipated_energy,peak_force,run_seconds,status,case,...`), DIR/summary_cases.csv when it is
there (one row per case over its seeds: `<keys>,seeds,ok,W_n,W_mean,W_sd,W_ci95,...`) and each
finished run's DIR/<case>/forces.csv, and writes
  DIR/sweep_W.png      W [J/m^2] of the last cycle against the first swept key (the seed left
                       out), one line per combination of the other swept keys (e.g. W against
                       radius, one line per underpressure); with seeds, the mean over the seeds
                       with its 95% interval as error bars and each run as a dot. Further panels
                       show W_settled (the mean W of the settled cycles) when any run settled, and
                       the friction share of the dissipation when the runs kept the energy ledger.
  DIR/sweep_loops.png  the last cycle's loop (force_total against displacement) of every run,
                       one panel per combination of the other swept keys, one colour per value of
                       the first key (every seed of a case in its colour)
--caption TEXT is written under each figure (e.g. the command that made the data); --prefix NAME
writes NAME_W.png and NAME_loops.png instead. Runs that did not finish ("status" not ok) are left
out. Exits nonzero with a message when summary.csv is missing or holds no finished run. Runs under
Debian's /usr/bin/python3 (matplotlib, numpy).
"""
import argparse
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

SEED = "simulation.seed"
LENGTHS = ("damper.radius", "damper.height", "grains.radius", "process.amplitude")


def fail(msg):
    print(f"plot_sweep.py: {msg}", file=sys.stderr)
    sys.exit(1)


def as_number(s):
    try:
        v = float(s)
    except (TypeError, ValueError):
        return None
    return v if math.isfinite(v) else None


def pretty(key, value):
    """Axis-friendly value: MPa for underpressures, mm for lengths."""
    v = as_number(value)
    if v is None:
        return value
    if key == "process.underpressure":
        return f"{v * 1e-6:g} MPa"
    if key in LENGTHS:
        return f"{v * 1e3:g} mm"
    return f"{v:g}"


def read_rows(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    if not rows:
        fail(f"{path} is empty")
    return rows[0], [dict(zip(rows[0], r)) for r in rows[1:]]


def read_summary(d):
    path = os.path.join(d, "summary.csv")
    if not os.path.exists(path):
        fail(f"{path} not found (not a sweep folder)")
    header, rows = read_rows(path)
    if "W" not in header:
        fail(f"{path}: no column W (columns: {', '.join(header)})")
    keys = header[: header.index("W")]
    runs = [r for r in rows if r.get("status") == "ok"]
    if not runs:
        fail(f"{path}: no finished case (status ok)")
    return keys, runs


def read_cases(d, keys, runs):
    """Rows of summary_cases.csv; without it (an older sweep), one row per run."""
    path = os.path.join(d, "summary_cases.csv")
    if os.path.exists(path):
        _, rows = read_rows(path)
        return rows
    rows = []
    for r in runs:
        c = {k: r[k] for k in keys if k != SEED}
        for q in ("W", "W_settled"):
            v = as_number(r.get(q))
            c[q + "_n"], c[q + "_mean"], c[q + "_ci95"] = ("1", r[q], "") if v is not None else ("0", "", "")
        rows.append(c)
    return rows


def read_forces(path):
    with open(path, newline="") as f:
        rows = [r for r in csv.reader(f) if r and not r[0].startswith("#")]
    header = rows[0]
    data = np.array([[float(x) for x in r] for r in rows[1:]])
    return {h: data[:, k] for k, h in enumerate(header)}


def caption(fig, text):
    if text:
        fig.text(0.01, 0.005, text, fontsize=6, color="0.35", ha="left", va="bottom", wrap=True)


def main():
    ap = argparse.ArgumentParser(description="plots of a vppdem sweep folder")
    ap.add_argument("dir")
    ap.add_argument("--caption", default="")
    ap.add_argument("--prefix", default="sweep")
    a = ap.parse_args()
    d = a.dir
    keys, runs = read_summary(d)
    ckeys = [k for k in keys if k != SEED]
    cases = read_cases(d, keys, runs)
    xkey = ckeys[0] if ckeys else None
    others = ckeys[1:]

    def group_of(c):
        return tuple(c[k] for k in others)

    groups = []
    for c in cases:
        if group_of(c) not in groups:
            groups.append(group_of(c))

    def group_label(g):
        return ", ".join(f"{k} = {pretty(k, v)}" for k, v in zip(others, g)) or "all cases"

    def xvalue(v):
        x = as_number(v)
        return x * 1e3 if (x is not None and xkey in LENGTHS) else x

    numeric = xkey is not None and all(as_number(c[xkey]) is not None for c in cases)
    xcats = [] if numeric else list(dict.fromkeys(c[xkey] if xkey else "base" for c in cases))

    def xpos(v):
        return xvalue(v) if numeric else xcats.index(v if xkey else "base")

    quantities = ["W"]
    for q in ("W_settled", "friction_share"):
        if any(as_number(c.get(q + "_mean")) is not None for c in cases):
            quantities.append(q)
    ens = any((as_number(c.get("W_n")) or 0) > 1 for c in cases)
    logx = numeric and xkey in ("grains.young", "process.velocity")
    xs_all = [xpos(c[xkey]) for c in cases] if xkey else [0]
    span = (max(xs_all) - min(xs_all)) if numeric and not logx else 0.0

    def dodge(x, gi):
        """Groups side by side at one x, so their error bars do not hide each other."""
        if not ens or len(groups) < 2:
            return x
        k = gi - 0.5 * (len(groups) - 1)
        if logx:
            return x * 10 ** (0.012 * k)
        return x + 0.012 * k * (span if span > 0 else 1.0)
    fig, axes = plt.subplots(1, len(quantities), figsize=(6.4 * len(quantities), 4.8), squeeze=False)
    for ax, q in zip(axes[0], quantities):
        for gi, g in enumerate(groups):
            colour = f"C{gi % 10}"
            members = [c for c in cases if group_of(c) == g and as_number(c.get(q + "_mean")) is not None]
            members.sort(key=lambda c: xpos(c[xkey]) if xkey else 0)
            xs = [dodge(xpos(c[xkey]) if xkey else 0, gi) for c in members]
            ys = [float(c[q + "_mean"]) for c in members]
            err = [as_number(c.get(q + "_ci95")) or 0.0 for c in members]
            ax.errorbar(xs, ys, yerr=err if ens else None, fmt="o-", color=colour, capsize=3, label=group_label(g))
            # Every run of the ensemble as a dot, so the scatter shows beside its interval.
            if ens:
                for r in runs:
                    v = as_number(r.get(q))
                    if v is None or tuple(r[k] for k in others) != g:
                        continue
                    ax.plot(dodge(xpos(r[xkey]) if xkey else 0, gi), v, ".", color=colour, alpha=0.35, ms=5)
        xlabel = xkey or "case"
        if xkey in LENGTHS:
            xlabel += " [mm]"
        if logx:
            ax.set_xscale("log")
            xlabel += " [Pa]" if xkey == "grains.young" else " [m/s]"
        if not numeric:
            ax.set_xticks(range(len(xcats)), xcats)
        ax.set_xlabel(xlabel)
        ax.set_ylabel({"W": "W of the last cycle [J/m$^2$]",
                       "W_settled": "W_settled, mean of the settled cycles [J/m$^2$]",
                       "friction_share": "friction share of the last cycle's dissipation [-]"}[q])
        if ens:
            ax.set_title("mean over seeds, 95% interval (Student t); dots: runs", fontsize=9)
        ax.grid(True, alpha=0.3)
        if others:
            ax.legend(fontsize=8)
    fig.suptitle(os.path.basename(os.path.abspath(d)))
    fig.tight_layout(rect=(0, 0.03 if a.caption else 0, 1, 1))
    caption(fig, a.caption)
    fig.savefig(os.path.join(d, f"{a.prefix}_W.png"), dpi=130)
    plt.close(fig)

    # Loops of the last cycle, one panel per group of the other keys.
    n = len(groups)
    cols = min(n, 4)
    rows = (n + cols - 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(4.6 * cols, 3.8 * rows), squeeze=False)
    xvals = list(dict.fromkeys(r[xkey] for r in runs)) if xkey else ["base"]
    cmap = plt.get_cmap("viridis")
    for gi, g in enumerate(groups):
        ax = axes[gi // cols][gi % cols]
        labelled = set()
        for r in runs:
            if tuple(r[k] for k in others) != g:
                continue
            path = os.path.join(d, r["case"], "forces.csv")
            if not os.path.exists(path):
                continue
            f = read_forces(path)
            last = f["cycle"] == f["cycle"].max()
            xv = r[xkey] if xkey else "base"
            colour = cmap(xvals.index(xv) / max(1, len(xvals) - 1))
            label = (pretty(xkey, xv) if xkey else r["case"]) if xv not in labelled else None
            labelled.add(xv)
            ax.plot(1e3 * f["displacement"][last], f["force_total"][last], color=colour, lw=1.0, label=label)
        ax.set_xlabel("displacement [mm] (compression +)")
        ax.set_ylabel("force [N] (compression +)")
        ax.set_title(group_label(g), fontsize=9)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7, title=xkey, title_fontsize=7)
    for gi in range(n, rows * cols):
        axes[gi // cols][gi % cols].axis("off")
    fig.suptitle("last cycle of each run" + (" (every seed)" if SEED in keys else ""))
    fig.tight_layout(rect=(0, 0.03 if a.caption else 0, 1, 1))
    caption(fig, a.caption)
    fig.savefig(os.path.join(d, f"{a.prefix}_loops.png"), dpi=110)
    plt.close(fig)
    print(f"wrote {os.path.join(d, a.prefix + '_W.png')} and {a.prefix}_loops.png")


if __name__ == "__main__":
    main()
