#!/usr/bin/env python3
"""Plots a `vppdem calibrate` output folder.

usage: plot_calibration.py DIR [--caption TEXT]

Reads DIR/calibration.json (keys "case", "simulated_force", "cycles_compared", "grid", "best",
"misfit"), DIR/experiment.csv (`time,displacement,force,cycle`: the measured loop in SI units,
compression positive, displacement from its minimum) and DIR/<case>/forces.csv of the best case,
and writes DIR/calibration.png: left, the measured and the best simulated loops over the
compared cycles (displacements shifted to start at 0, as in the misfit); right, the misfit of
every grid point against the first grid key (one line per combination of the others), with its
95% interval over the seeds as error bars and the range of grid values whose interval overlaps the
best's shaded.
Runs under Debian's /usr/bin/python3 (matplotlib, numpy).
"""
import csv
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def fail(msg):
    print(f"plot_calibration.py: {msg}", file=sys.stderr)
    sys.exit(1)


def read_csv(path):
    with open(path, newline="") as f:
        rows = [r for r in csv.reader(f) if r and not r[0].startswith("#")]
    if len(rows) < 2:
        fail(f"{path} holds no data")
    header = rows[0]
    data = np.array([[float(x) for x in r] for r in rows[1:]])
    return {h: data[:, k] for k, h in enumerate(header)}


def main():
    import argparse
    ap = argparse.ArgumentParser(description="plot of a vppdem calibrate folder")
    ap.add_argument("dir")
    ap.add_argument("--caption", default="", help="text under the figure (e.g. the command that made it)")
    args = ap.parse_args()
    d = args.dir
    try:
        with open(os.path.join(d, "calibration.json")) as f:
            cal = json.load(f)
    except (OSError, ValueError) as e:
        fail(f"cannot read {os.path.join(d, 'calibration.json')}: {e}")
    if not cal.get("best"):
        fail("calibration.json has no best grid point")
    exp = read_csv(os.path.join(d, "experiment.csv"))
    sim = read_csv(os.path.join(d, cal["case"], "forces.csv"))
    col = cal.get("simulated_force", "force_zeroed")
    sd = sim["displacement"] - sim["displacement"].min()
    cycles = cal.get("cycles_compared") or [1]

    fig, (a1, a2) = plt.subplots(1, 2, figsize=(12, 4.8))
    ecyc = sorted(c for c in set(exp["cycle"].astype(int)) if c > 0)
    scyc = sorted(c for c in set(sim["cycle"].astype(int)) if c > 0)
    for n in cycles:
        if n - 1 < len(ecyc):
            m = exp["cycle"] == ecyc[n - 1]
            a1.plot(1e3 * exp["displacement"][m], exp["force"][m], color="0.55", lw=0.8,
                    label="measured" if n == cycles[0] else None)
        if n - 1 < len(scyc):
            m = sim["cycle"] == scyc[n - 1]
            a1.plot(1e3 * sd[m], sim[col][m], color="C3", lw=1.4,
                    label="simulated (best)" if n == cycles[0] else None)
    best = ", ".join(f"{k} = {v}" for k, v in cal["best"].items())
    a1.set_title(f"best: {best}\nmisfit {cal['misfit']:.4g}, cycles {', '.join(map(str, cycles))}", fontsize=9)
    a1.set_xlabel("displacement [mm] (compression +)")
    a1.set_ylabel(f"force [N] ({col}, compression +)")
    a1.grid(True, alpha=0.3)
    a1.legend()

    grid = [g for g in cal.get("grid", []) if g.get("misfit") is not None]
    keys = list(cal["best"].keys())
    xkey, others = keys[0], keys[1:]
    groups = []
    for g in grid:
        t = tuple(g[k] for k in others)
        if t not in groups:
            groups.append(t)
    for t in groups:
        # With seeds: the mean misfit and its 95% interval (misfit_ci95; None with one seed).
        pts = sorted((g[xkey], g["misfit"], g.get("misfit_ci95") or 0.0)
                     for g in grid if tuple(g[k] for k in others) == t)
        label = ", ".join(f"{k} = {v}" for k, v in zip(others, t)) or None
        xs = [p[0] for p in pts]
        xv = xs if all(isinstance(x, (int, float)) for x in xs) else list(range(len(xs)))
        a2.errorbar(xv, [p[1] for p in pts], yerr=[p[2] for p in pts], fmt="o-", capsize=3, label=label)
        if xv is not xs:
            a2.set_xticks(range(len(xs)), [str(x) for x in xs])
    unc = cal.get("uncertainty", {}).get(xkey)
    if unc and all(isinstance(v, (int, float)) for v in unc) and len(unc) > 1:
        a2.axvspan(min(unc), max(unc), color="C3", alpha=0.08, label="interval overlaps the best's")
    a2.axvline(cal["best"][xkey], color="C3", ls="--", lw=0.8) if isinstance(cal["best"][xkey], (int, float)) else None
    a2.set_xlabel(xkey)
    a2.set_ylabel("misfit")
    a2.grid(True, alpha=0.3)
    if others or unc:
        a2.legend(fontsize=8)
    fig.tight_layout(rect=(0, 0.04 if args.caption else 0, 1, 1))
    if args.caption:
        fig.text(0.01, 0.005, args.caption, fontsize=5, color="0.35", wrap=True)
    out = os.path.join(d, "calibration.png")
    fig.savefig(out, dpi=120)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
