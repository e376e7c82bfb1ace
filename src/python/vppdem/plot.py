"""The plots of vppdem's output folders (PNG, matplotlib), as `vppdem plot DIR` draws them.

    damper(run_dir)                           a `vppdem damper` folder
    sweep(study_dir, caption=None, prefix=None)   a `vppdem sweep` folder
    calibration(dir, caption=None)            a `vppdem calibrate` folder
each returns the paths of the files it wrote and raises PlotError (a ValueError) naming the file
and what is wrong when a record is missing or lacks a column. From the shell:

    python3 -m vppdem.plot DIR [--caption TEXT] [--prefix NAME] [--kind KIND]

draws what DIR holds (a calibration folder: calibration() then sweep(); a sweep folder: sweep();
else damper()) and prints the files written, one per line; on an error it prints
`vppdem.plot: MESSAGE` on stderr and exits 1. Needs numpy and matplotlib, not the compiled
module: PYTHONPATH=src/python is enough.

damper(DIR) reads DIR/forces.csv (header `time,displacement,force_total,force_grains,force_foil,
force_zeroed,cycle`; displacement [m] of the upper cap downward from the start of cycling, forces
[N], both positive in compression; cycle 1-based) and writes
  loops_total.png   force_total (grains + foil, not zeroed) vs displacement
  loops_foil.png    force_foil vs displacement
  loops_grains.png  force_grains vs displacement
  loops.png         the three side by side (total, foil, grains)
with one colour per cycle. The title gives the underpressure when DIR/summary.json has the key
"underpressure" [Pa]; when DIR/cycles.csv exists (header `cycle,dissipated_energy,W,...`), the
legend of the total plots gives W [J/m^2] per cycle. When cycles.csv also has the energy columns
`friction_dissipation,damping_dissipation,viscous_dissipation` [J] (a damper run; see
docs/energy.md), it writes
  energy_split.png  per cycle, the dissipated energy split into friction, local damping and
                    viscous damping (stacked bars) against the loop area; next to it, from
                    DIR/energy.csv when present, the cumulative terms over time.

sweep(DIR) reads DIR/summary.csv (header: the swept keys in [grid] order, then
`W,dissipated_energy,peak_force,run_seconds,status,case,...`), DIR/summary_cases.csv when it is
there (one row per case over its seeds: `<keys>,seeds,ok,W_n,W_mean,W_sd,W_ci95,...`) and each
finished run's DIR/<case>/forces.csv, and writes
  sweep_W.png      W [J/m^2] of the last cycle against the first swept key (the seed left out),
                   one line per combination of the other swept keys (e.g. W against radius, one
                   line per underpressure); with seeds, the mean over the seeds with its 95%
                   interval as error bars and each run as a dot. Further panels show W_settled
                   (the mean W of the settled cycles) when any run settled, and the friction share
                   of the dissipation when the runs kept the energy ledger.
  sweep_loops.png  the last cycle's loop (force_total against displacement) of every run, one
                   panel per combination of the other swept keys, one colour per value of the
                   first key (every seed of a case in its colour)
caption: text written under each figure (e.g. the command that made the data); prefix NAME
writes NAME_W.png and NAME_loops.png instead. Runs that did not finish ("status" not ok) are
left out.

calibration(DIR) reads DIR/calibration.json (keys "case", "simulated_force", "cycles_compared",
"grid", "best", "misfit"), DIR/experiment.csv (`time,displacement,force,cycle`: the measured loop
in SI units, compression positive, displacement from its minimum) and DIR/<case>/forces.csv of
the best case, and writes calibration.png: left, the measured and the best simulated loops over
the compared cycles (displacements shifted to start at 0, as in the misfit); right, the misfit of
every grid point against the first grid key (one line per combination of the others), with its
95% interval over the seeds as error bars and the range of grid values whose interval overlaps
the best's shaded.
"""

import argparse
import json
import os
import sys

import matplotlib
import numpy as np
from matplotlib.figure import Figure

from . import records

__all__ = ["PlotError", "damper", "sweep", "calibration", "main"]


class PlotError(ValueError):
    """A folder that cannot be plotted: the message names the file and what is wrong."""


# ---- shared -------------------------------------------------------------------------------------
# Figures are made without pyplot and drawn by Agg (savefig of a PNG): no display is needed, and
# the backend of a session that imports this module (a notebook's) is left alone.


def _figure(nrows=1, ncols=1, figsize=None, squeeze=True):
    fig = Figure(figsize=figsize)
    return fig, fig.subplots(nrows, ncols, squeeze=squeeze)


def _legend(ax, **kw):
    """A legend of what the axes draw with a label; none when nothing is labelled (matplotlib
    would draw an empty box and warn)."""
    if ax.get_legend_handles_labels()[1]:
        ax.legend(**kw)


def _save(fig, path, dpi):
    try:
        fig.savefig(path, dpi=dpi)
    except OSError as e:
        raise PlotError(f"cannot write {path}: {e.strerror or e}") from None
    return path


def _read_csv(path, columns):
    try:
        return records.read_csv(path, columns)
    except records.RecordError as e:
        raise PlotError(str(e)) from None


def _read_table(path):
    try:
        return records.read_table(path)
    except records.RecordError as e:
        raise PlotError(str(e)) from None


def _warn(msg):
    print(f"vppdem.plot: {msg}", file=sys.stderr)


# ---- damper -------------------------------------------------------------------------------------

COLUMNS = ("displacement", "force_total", "force_grains", "force_foil", "cycle")  # the ones plotted
PANELS = (  # (column, file stem, panel title)
    ("force_total", "total", "total force (grains + foil, not zeroed)"),
    ("force_foil", "foil", "foil force (top ring)"),
    ("force_grains", "grains", "grain force (upper cap)"),
)
ENERGY_TERMS = (  # (cycles.csv / energy.csv column, label, colour)
    ("friction_dissipation", "friction (Coulomb slip)", "tab:blue"),
    ("damping_dissipation", "local damping", "tab:orange"),
    ("viscous_dissipation", "viscous (restitution)", "tab:green"),
)


def _find_key(obj, key):
    """The value of `key` at the top level of a JSON object, else in nested objects."""
    if isinstance(obj, dict):
        if key in obj:
            return obj[key]
        for v in obj.values():
            r = _find_key(v, key)
            if r is not None:
                return r
    return None


def _underpressure_text(d):
    path = os.path.join(d, "summary.json")
    try:
        with open(path) as f:
            dp = float(_find_key(json.load(f), "underpressure"))
    except (OSError, ValueError, TypeError):
        return ""
    return f"underpressure {dp / 1e6:.3g} MPa"


def _read_w(d):
    """{cycle: W} from DIR/cycles.csv, empty when absent or unreadable."""
    path = os.path.join(d, "cycles.csv")
    if not os.path.exists(path):
        return {}
    try:
        c = records.read_csv(path, ("cycle", "W"))
    except records.RecordError as e:
        _warn(f"ignoring {path}: {e}")
        return {}
    return {int(round(k)): w for k, w in zip(c["cycle"], c["W"])}


def _energy_split(d, dp):
    """DIR/energy_split.png from the energy columns of cycles.csv (and energy.csv); None if absent."""
    path = os.path.join(d, "cycles.csv")
    if not os.path.exists(path):
        return None
    try:
        c = records.read_csv(path, ("cycle", "dissipated_energy") + tuple(t[0] for t in ENERGY_TERMS))
    except records.RecordError:
        return None  # a cycles.csv without the energy budget (e.g. from `vppdem analyze`)
    e = None
    epath = os.path.join(d, "energy.csv")
    if os.path.exists(epath):
        try:
            e = records.read_csv(epath, ("time", "boundary_work", "pressure_work", "residual") +
                                 tuple(t[0] for t in ENERGY_TERMS))
        except records.RecordError as err:
            _warn(f"ignoring {epath}: {err}")
    fig, axes = _figure(1, 2 if e is not None else 1, figsize=(13 if e is not None else 6.4, 4.8), squeeze=False)
    ax = axes[0][0]
    cyc = np.rint(c["cycle"]).astype(int)
    bottom = np.zeros(len(cyc))
    for col, label, colour in ENERGY_TERMS:
        ax.bar(cyc, c[col] * 1e3, bottom=bottom * 1e3, color=colour, label=label, width=0.6)
        bottom += c[col]
    total = np.where(bottom > 0, bottom, np.nan)
    ax.plot(cyc, c["dissipated_energy"] * 1e3, "k_", markersize=28, mew=2, label="loop area (cycles.csv)")
    for x, b, f in zip(cyc, total, c["friction_dissipation"]):
        if np.isfinite(b):
            ax.annotate(f"{100 * f / b:.0f}% friction", (x, b * 1e3), ha="center", va="bottom", fontsize=8)
    top = np.nanmax(np.concatenate([bottom, c["dissipated_energy"]])) * 1e3
    if np.isfinite(top) and top > 0:
        ax.set_ylim(0, 1.12 * top)  # room for the labels above the bars
    ax.set_xlabel("cycle")
    ax.set_ylabel("energy dissipated per cycle [mJ]")
    ax.set_xticks(cyc)
    ax.set_title("where the loop energy goes", fontsize=10)
    ax.grid(True, axis="y", alpha=0.3)
    _legend(ax, fontsize=8, loc="lower right")
    if e is not None:
        ax = axes[0][1]
        t = e["time"]
        ax.plot(t, e["boundary_work"] * 1e3, "k-", lw=1.5, label="boundary work (cap + ring)")
        ax.plot(t, e["pressure_work"] * 1e3, "k:", lw=1.2, label="pressure work")
        for col, label, colour in ENERGY_TERMS:
            ax.plot(t, e[col] * 1e3, "-", color=colour, lw=1.2, label=label)
        ax.plot(t, e["residual"] * 1e3, "r--", lw=1.0, label="residual (balance error)")
        ax.set_xlabel("time since the start of cycling [s]")
        ax.set_ylabel("cumulative energy [mJ]")
        ax.set_title("energy ledger (energy.csv)", fontsize=10)
        ax.grid(True, alpha=0.3)
        _legend(ax, fontsize=8, loc="upper left")
    fig.suptitle(f"VPP damper energy budget{', ' + dp if dp else ''}", fontsize=11)
    fig.tight_layout()
    return _save(fig, os.path.join(d, "energy_split.png"), 100)


def _cycle_colours(cycles):
    cmap = matplotlib.colormaps["tab10" if len(cycles) <= 10 else "viridis"]
    n = max(len(cycles) - 1, 1)
    return {c: (cmap(i) if len(cycles) <= 10 else cmap(i / n)) for i, c in enumerate(cycles)}


def _draw_loops(ax, data, column, title, colours, w_by_cycle):
    disp_mm = data["displacement"] * 1e3
    cyc = np.rint(data["cycle"]).astype(int)
    for c in colours:
        sel = cyc == c
        label = f"cycle {c}" if c > 0 else "before cycling"
        if c in w_by_cycle:
            label += f": W = {w_by_cycle[c]:.4g} J/m²"
        ax.plot(disp_mm[sel], data[column][sel], "-", lw=1.2, color=colours[c], label=label)
    ax.set_xlabel("displacement (compression) [mm]")
    ax.set_ylabel(f"{column} (compression +) [N]")
    ax.set_title(title, fontsize=10)
    ax.grid(True, alpha=0.3)
    _legend(ax, fontsize=8, loc="best")


def damper(run_dir):
    """The loops of a `vppdem damper` folder (and its energy split when cycles.csv has the
    ledger's columns); returns the paths written."""
    d = os.fspath(run_dir)
    path = os.path.join(d, "forces.csv")
    if not os.path.isfile(path):
        raise PlotError(f"{path} not found (run `vppdem damper` with this output directory first)")
    if os.path.getsize(path) == 0:
        raise PlotError(f"{path} is empty")
    data = _read_csv(path, COLUMNS)
    finite = np.isfinite(data["displacement"]) & np.isfinite(data["cycle"])
    data = {k: v[finite] for k, v in data.items()}
    if not len(data["cycle"]):
        raise PlotError(f"{path} has no finite rows")

    cycles = sorted(set(np.rint(data["cycle"]).astype(int).tolist()))
    colours = _cycle_colours(cycles)
    w_by_cycle = _read_w(d)
    dp = _underpressure_text(d)
    written = []

    for column, stem, title in PANELS:
        fig, ax = _figure(figsize=(6.4, 4.8))
        _draw_loops(ax, data, column, title, colours, w_by_cycle if stem == "total" else {})
        fig.suptitle(f"VPP damper loops{', ' + dp if dp else ''}", fontsize=11)
        fig.tight_layout()
        written.append(_save(fig, os.path.join(d, f"loops_{stem}.png"), 110))

    fig, axes = _figure(1, 3, figsize=(16, 4.8))
    for ax, (column, stem, title) in zip(axes, PANELS):
        _draw_loops(ax, data, column, title, colours, w_by_cycle if stem == "total" else {})
    fig.suptitle(f"VPP damper loops{', ' + dp if dp else ''}", fontsize=12)
    fig.tight_layout()
    written.append(_save(fig, os.path.join(d, "loops.png"), 100))
    out = _energy_split(d, dp)
    if out:
        written.append(out)
    return written


# ---- sweep --------------------------------------------------------------------------------------

SEED = "simulation.seed"
LENGTHS = ("damper.radius", "damper.height", "grains.radius", "process.amplitude")


def _pretty(key, value):
    """Axis-friendly value: MPa for underpressures, mm for lengths."""
    v = records.finite_number(value)
    if v is None:
        return value
    if key == "process.underpressure":
        return f"{v * 1e-6:g} MPa"
    if key in LENGTHS:
        return f"{v * 1e3:g} mm"
    return f"{v:g}"


def _read_summary(d):
    path = os.path.join(d, "summary.csv")
    if not os.path.exists(path):
        raise PlotError(f"{path} not found (not a sweep folder)")
    header, rows = _read_table(path)
    if not header:
        raise PlotError(f"{path} is empty")
    if "W" not in header:
        raise PlotError(f"{path}: no column W (columns: {', '.join(header)})")
    keys = header[: header.index("W")]
    runs = [r for r in rows if r.get("status") == "ok"]
    if not runs:
        raise PlotError(f"{path}: no finished case (status ok)")
    return keys, runs


def _read_cases(d, keys, runs):
    """Rows of summary_cases.csv; without it (an older sweep), one row per run."""
    path = os.path.join(d, "summary_cases.csv")
    if os.path.exists(path):
        header, rows = _read_table(path)
        if not header:
            raise PlotError(f"{path} is empty")
        return rows
    rows = []
    for r in runs:
        c = {k: r[k] for k in keys if k != SEED}
        for q in ("W", "W_settled"):
            v = records.finite_number(r.get(q))
            c[q + "_n"], c[q + "_mean"], c[q + "_ci95"] = ("1", r[q], "") if v is not None else ("0", "", "")
        rows.append(c)
    return rows


def _caption(fig, text):
    if text:
        fig.text(0.01, 0.005, text, fontsize=6, color="0.35", ha="left", va="bottom", wrap=True)


def sweep(study_dir, caption=None, prefix=None):
    """W against the first swept key and the last cycle's loops of a `vppdem sweep` folder
    (PREFIX_W.png, PREFIX_loops.png; prefix default "sweep"); returns the paths written."""
    d = os.fspath(study_dir)
    caption = caption or ""
    prefix = prefix or "sweep"
    keys, runs = _read_summary(d)
    ckeys = [k for k in keys if k != SEED]
    cases = _read_cases(d, keys, runs)
    xkey = ckeys[0] if ckeys else None
    others = ckeys[1:]

    def group_of(c):
        return tuple(c[k] for k in others)

    groups = []
    for c in cases:
        if group_of(c) not in groups:
            groups.append(group_of(c))

    def group_label(g):
        return ", ".join(f"{k} = {_pretty(k, v)}" for k, v in zip(others, g)) or "all cases"

    def xvalue(v):
        x = records.finite_number(v)
        return x * 1e3 if (x is not None and xkey in LENGTHS) else x

    numeric = xkey is not None and all(records.finite_number(c[xkey]) is not None for c in cases)
    xcats = [] if numeric else list(dict.fromkeys(c[xkey] if xkey else "base" for c in cases))

    def xpos(v):
        return xvalue(v) if numeric else xcats.index(v if xkey else "base")

    quantities = ["W"]
    for q in ("W_settled", "friction_share"):
        if any(records.finite_number(c.get(q + "_mean")) is not None for c in cases):
            quantities.append(q)
    ens = any((records.finite_number(c.get("W_n")) or 0) > 1 for c in cases)
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
    fig, axes = _figure(1, len(quantities), figsize=(6.4 * len(quantities), 4.8), squeeze=False)
    for ax, q in zip(axes[0], quantities):
        for gi, g in enumerate(groups):
            colour = f"C{gi % 10}"
            members = [c for c in cases if group_of(c) == g and records.finite_number(c.get(q + "_mean")) is not None]
            members.sort(key=lambda c: xpos(c[xkey]) if xkey else 0)
            xs = [dodge(xpos(c[xkey]) if xkey else 0, gi) for c in members]
            ys = [float(c[q + "_mean"]) for c in members]
            err = [records.finite_number(c.get(q + "_ci95")) or 0.0 for c in members]
            ax.errorbar(xs, ys, yerr=err if ens else None, fmt="o-", color=colour, capsize=3, label=group_label(g))
            # Every run of the ensemble as a dot, so the scatter shows beside its interval.
            if ens:
                for r in runs:
                    v = records.finite_number(r.get(q))
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
            _legend(ax, fontsize=8)
    fig.suptitle(os.path.basename(os.path.abspath(d)))
    fig.tight_layout(rect=(0, 0.03 if caption else 0, 1, 1))
    _caption(fig, caption)
    written = [_save(fig, os.path.join(d, f"{prefix}_W.png"), 130)]

    # Loops of the last cycle, one panel per group of the other keys.
    n = len(groups)
    cols = min(n, 4)
    rows = (n + cols - 1) // cols
    fig, axes = _figure(rows, cols, figsize=(4.6 * cols, 3.8 * rows), squeeze=False)
    xvals = list(dict.fromkeys(r[xkey] for r in runs)) if xkey else ["base"]
    cmap = matplotlib.colormaps["viridis"]
    for gi, g in enumerate(groups):
        ax = axes[gi // cols][gi % cols]
        labelled = set()
        for r in runs:
            if tuple(r[k] for k in others) != g:
                continue
            path = os.path.join(d, r["case"], "forces.csv")
            if not os.path.exists(path):
                continue
            f = _read_csv(path, ("displacement", "force_total", "cycle"))
            last = f["cycle"] == f["cycle"].max()
            xv = r[xkey] if xkey else "base"
            colour = cmap(xvals.index(xv) / max(1, len(xvals) - 1))
            label = (_pretty(xkey, xv) if xkey else r["case"]) if xv not in labelled else None
            labelled.add(xv)
            ax.plot(1e3 * f["displacement"][last], f["force_total"][last], color=colour, lw=1.0, label=label)
        ax.set_xlabel("displacement [mm] (compression +)")
        ax.set_ylabel("force [N] (compression +)")
        ax.set_title(group_label(g), fontsize=9)
        ax.grid(True, alpha=0.3)
        _legend(ax, fontsize=7, title=xkey, title_fontsize=7)
    for gi in range(n, rows * cols):
        axes[gi // cols][gi % cols].axis("off")
    fig.suptitle("last cycle of each run" + (" (every seed)" if SEED in keys else ""))
    fig.tight_layout(rect=(0, 0.03 if caption else 0, 1, 1))
    _caption(fig, caption)
    written.append(_save(fig, os.path.join(d, f"{prefix}_loops.png"), 110))
    return written


# ---- calibration --------------------------------------------------------------------------------


def calibration(dir, caption=None):
    """The measured and best simulated loops and the misfit over the grid of a `vppdem calibrate`
    folder (calibration.png); returns the paths written."""
    d = os.fspath(dir)
    caption = caption or ""
    path = os.path.join(d, "calibration.json")
    try:
        with open(path) as f:
            cal = json.load(f)
    except (OSError, ValueError) as e:
        raise PlotError(f"cannot read {path}: {e}") from None
    if not cal.get("best"):
        raise PlotError(f"{path} has no best grid point")
    col = cal.get("simulated_force", "force_zeroed")
    exp = _read_csv(os.path.join(d, "experiment.csv"), ("displacement", "force", "cycle"))
    sim = _read_csv(os.path.join(d, cal["case"], "forces.csv"), ("displacement", "cycle", col))
    sd = sim["displacement"] - sim["displacement"].min()
    cycles = cal.get("cycles_compared") or [1]

    fig, (a1, a2) = _figure(1, 2, figsize=(12, 4.8))
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
    _legend(a1)

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
        seeds = any(g.get("misfit_ci95") is not None for g in grid)
        what = "mean misfit over the seeds, 95% interval" if seeds else "misfit"
        label = ", ".join(f"{k} = {v}" for k, v in zip(others, t)) or what
        xs = [p[0] for p in pts]
        xv = xs if all(isinstance(x, (int, float)) for x in xs) else list(range(len(xs)))
        a2.errorbar(xv, [p[1] for p in pts], yerr=[p[2] for p in pts], fmt="o-", capsize=3, label=label)
        if xv is not xs:
            a2.set_xticks(range(len(xs)), [str(x) for x in xs])
    unc = cal.get("uncertainty", {}).get(xkey)
    if unc and all(isinstance(v, (int, float)) for v in unc) and len(unc) > 1:
        a2.axvspan(min(unc), max(unc), color="C3", alpha=0.08, label="interval overlaps the best's")
    if isinstance(cal["best"][xkey], (int, float)):
        a2.axvline(cal["best"][xkey], color="C3", ls="--", lw=0.8, label=f"best: {xkey} = {cal['best'][xkey]}")
    a2.set_xlabel(xkey)
    a2.set_ylabel("misfit")
    a2.grid(True, alpha=0.3)
    _legend(a2, fontsize=8)
    fig.tight_layout(rect=(0, 0.04 if caption else 0, 1, 1))
    if caption:
        fig.text(0.01, 0.005, caption, fontsize=5, color="0.35", wrap=True)
    return [_save(fig, os.path.join(d, "calibration.png"), 120)]


# ---- command ------------------------------------------------------------------------------------

KINDS = ("damper", "sweep", "calibration")


def kind_of(d):
    """What a folder holds: "calibration" (calibration.json), "sweep" (summary.csv) or "damper"."""
    if os.path.exists(os.path.join(d, "calibration.json")):
        return "calibration"
    if os.path.exists(os.path.join(d, "summary.csv")):
        return "sweep"
    return "damper"


def main(argv=None):
    ap = argparse.ArgumentParser(
        prog="python3 -m vppdem.plot",
        description="Draws the plots of a vppdem output folder (PNG): a calibration folder (calibration.json) "
                    "calibration.png and the sweep plots, a sweep folder (summary.csv) the sweep plots, else the "
                    "damper loops. Prints the files written, one per line.")
    ap.add_argument("dir", help="damper, sweep or calibration output folder")
    ap.add_argument("--caption", default="", metavar="TEXT",
                    help="text under the sweep and calibration figures (e.g. the command that made the data)")
    ap.add_argument("--prefix", default="sweep", metavar="NAME", help="the sweep plots' names: NAME_W.png, NAME_loops.png")
    ap.add_argument("--kind", choices=KINDS, help="draw only this kind's plots (default: what DIR holds)")
    a = ap.parse_args(argv)
    kind = a.kind or kind_of(a.dir)
    try:
        if kind == "damper":
            written = damper(a.dir)
        elif kind == "sweep":
            written = sweep(a.dir, a.caption, a.prefix)
        else:
            written = calibration(a.dir, a.caption)
            if not a.kind:
                written += sweep(a.dir, a.caption, a.prefix)
    except PlotError as e:
        print(f"vppdem.plot: {e}", file=sys.stderr)
        sys.exit(1)
    print("\n".join(written))


if __name__ == "__main__":
    main()
