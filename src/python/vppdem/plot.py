"""The plots of vppdem's output folders (PNG, matplotlib), as `vppdem plot DIR` draws them.

    damper(run_dir)                           a `vppdem damper` folder
    sweep(study_dir, caption=None, prefix=None)   a `vppdem sweep` folder
    calibration(dir, caption=None)            a `vppdem calibrate` folder

    device(run_dir)                           a `vppdem device` folder
    device_study(study_dir, caption=None, prefix=None)   a `vppdem sweep` folder of a device study
each returns the paths of the files it wrote and raises PlotError (a ValueError) naming the file
and what is wrong when a record is missing or lacks a column. From the shell:

    python3 -m vppdem.plot DIR [--caption TEXT] [--prefix NAME] [--kind KIND]

draws what DIR holds (kind_of: a calibration folder: calibration() then sweep(); a device study's
folder (summary.csv beginning `case,seed,folder`): device_study(); a sweep folder: sweep(); a
device run's folder (tools.csv, no forces.csv): device(); else damper()) and prints the files
written, one per line; on an error it prints `vppdem.plot: MESSAGE` on stderr and exits 1. Needs
numpy and matplotlib, not the compiled module: PYTHONPATH=src/python is enough.

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

device(DIR) reads DIR/tools.csv (`time,stage,` then per tool `NAME_z,NAME_fx,NAME_fy,NAME_fz`:
time [s], the stage number 0-4 (fill, seal, press, vacuum, load), the tool's z displacement [m]
and the particles' force on it [N]; a published folder's tools.csv.gz, the rows from the press on,
when there is no tools.csv), DIR/air.csv when there (`time,stage,enclosed_volume,gas_volume,dp`:
[m^3], [Pa]) and DIR/summary.json when there (its holding force, stiffness and underpressure in
the title), and writes
  device_tools.png  per tool (a row), F_z against its z displacement and F_z against time, one
                    colour per stage, the stages' starts marked on the time axis
  device_air.png    dp and the enclosed volume (and the gas volume) against time, the stages
                    marked (only with air.csv)

device_study(DIR) reads DIR/summary.csv of a device study (`case,seed,folder`, the numbers of each
run's summary.json, `status,message`: docs/devices.md, "Studies") and DIR/summary_cases.csv when
there (`case,seeds,ok`, per number Q `Q_n,Q_mean,Q_sd,Q_ci95`, `folders`), and writes
  PREFIX_numbers.png  (prefix default "sweep") each number of summary.csv that the finished runs
                    have and that is not the same in every run, against the case (file order): the
                    mean over the seeds with its 95% interval (Student t) as error bars, each run
                    as a dot; the numbers the same in every run are named under the figure.
                    Without summary_cases.csv (a study run before it was written) the means of
                    summary.csv's runs, without intervals, and a warning.

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

__all__ = ["PlotError", "damper", "sweep", "calibration", "device", "device_study", "DEVICE_NUMBERS", "main"]


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


# ---- device -------------------------------------------------------------------------------------

DEVICE_STAGES = ("fill", "seal", "press", "vacuum", "load")  # tools.csv's stage numbers (docs/devices.md)
STAGE_COLOURS = ("0.55", "tab:purple", "tab:blue", "tab:orange", "tab:green")
# The numbers of a device study's summary.csv (docs/devices.md, "Studies"): label, unit, scale
# from the record's SI unit to the unit shown. A number summary.csv gains later is shown as it is.
DEVICE_NUMBERS = {
    "holding_force": ("holding force", "N", 1.0),
    "press_force": ("press force", "N", 1.0),
    "underpressure": ("underpressure", "kPa", 1e-3),
    "volume_change": ("volume change, seal to end of vacuum", "%", 100.0),
    "volume_change_vacuum": ("volume change in the vacuum", "%", 100.0),
    "packing_seal": ("packing at the seal", "", 1.0),
    "packing_vacuum": ("packing after the vacuum", "", 1.0),
    "grains": ("grains", "", 1.0),
    "stiffness": ("stiffness", "N/m", 1.0),
    "work_per_cycle": ("work per cycle", "µJ", 1e6),
    "peak_force": ("peak force", "N", 1.0),
    "energy_residual": ("energy ledger's residual", "mJ", 1e3),
    "energy_scale": ("energy ledger's scale", "mJ", 1e3),
    "holding_ratio": ("holding force / (dp x the object's cross-section)", "", 1.0),
    "object_area": ("the object's cross-section", "mm^2", 1e6),
    "suction_force_max": ("suction's largest pull", "N", 1.0),
    "seal_area": ("sealed area", "mm^2", 1e6),
}


def device_number_label(name):
    """(axis label with its unit, scale) of a device study's number."""
    label, unit, scale = DEVICE_NUMBERS.get(name, (name, "", 1.0))
    return (f"{label} [{unit}]" if unit else label), scale


def device_tools(path):
    """The tool names of tools.csv's header (`time,stage,` then `NAME_z,NAME_fx,NAME_fy,NAME_fz` per
    tool), in its order; PlotError when the header is not a device's."""
    header, _ = _read_table(path)
    if header[:2] != ["time", "stage"] or (len(header) - 2) % 4 or len(header) < 6:
        raise PlotError(f"{path}: not a device's tools.csv (expected time,stage, then NAME_z,NAME_fx,NAME_fy,NAME_fz "
                        f"per tool; columns: {', '.join(header)})")
    names = []
    for k in range(2, len(header), 4):
        name = header[k][:-2] if header[k].endswith("_z") else None
        if name is None or header[k + 1:k + 4] != [f"{name}_fx", f"{name}_fy", f"{name}_fz"]:
            raise PlotError(f"{path}: columns {', '.join(header[k:k + 4])} are not NAME_z,NAME_fx,NAME_fy,NAME_fz")
        names.append(name)
    return names


def stage_spans(time, stage):
    """[(stage, first time, last time)] of each run of equal stage numbers, in time order."""
    spans = []
    for t, s in zip(time, np.asarray(stage).astype(int)):
        if spans and spans[-1][0] == s:
            spans[-1][2] = t
        else:
            spans.append([s, t, t])
    return [tuple(x) for x in spans]


def _stage_name(s):
    return DEVICE_STAGES[s] if 0 <= s < len(DEVICE_STAGES) else f"stage {s}"


def _stage_colour(s):
    return STAGE_COLOURS[s] if 0 <= s < len(STAGE_COLOURS) else "k"


def _by_stage(ax, x, y, stage, labelled):
    """y against x, one colour per stage (each stage's rows joined to the next stage's first row, so
    the line is unbroken); each stage labelled once per axes."""
    stage = np.asarray(stage).astype(int)
    starts = [0] + [i for i in range(1, len(stage)) if stage[i] != stage[i - 1]] + [len(stage)]
    for a, b in zip(starts[:-1], starts[1:]):
        s = int(stage[a])
        stop = min(b + 1, len(stage))
        ax.plot(x[a:stop], y[a:stop], "-", lw=1.0, color=_stage_colour(s),
                label=_stage_name(s) if s not in labelled else None)
        labelled.add(s)


def _mark_stages(ax, spans):
    """A dotted line at each stage's start and its name at the top of the axes."""
    for s, t0, _ in spans:
        ax.axvline(t0, color=_stage_colour(s), ls=":", lw=0.8)
        ax.text(t0, 1.0, " " + _stage_name(s), transform=ax.get_xaxis_transform(), rotation=90, va="top",
                ha="left", fontsize=7, color=_stage_colour(s))


def _device_title(d):
    try:
        with open(os.path.join(d, "summary.json")) as f:
            s = json.load(f)
    except (OSError, ValueError):
        return "device run"
    parts = []
    if records.finite_number(s.get("underpressure")) is not None:
        parts.append(f"dp {s['underpressure'] * 1e-3:g} kPa")
    if s.get("object") and records.finite_number(s.get("holding_force")) is not None:
        parts.append(f"holding force {s['holding_force']:.4g} N ({s['object']})")
    if s.get("cycle_tool"):  # the cycles' numbers are 0 in a run without result.cycle_tool
        if records.finite_number(s.get("stiffness")) is not None:
            parts.append(f"stiffness {s['stiffness']:.4g} N/m")
        if records.finite_number(s.get("work_per_cycle")) is not None:
            parts.append(f"work per cycle {s['work_per_cycle'] * 1e6:.4g} µJ")
    return "device run" + (": " + ", ".join(parts) if parts else "")


def device(run_dir):
    """The tools' forces and the air of a `vppdem device` folder (device_tools.png, and
    device_air.png when air.csv is there); returns the paths written."""
    d = os.fspath(run_dir)
    path = os.path.join(d, "tools.csv")
    if not os.path.isfile(path) and os.path.isfile(path + ".gz"):
        path += ".gz"
    if not os.path.isfile(path):
        raise PlotError(f"{os.path.join(d, 'tools.csv')} not found (run `vppdem device FILE --out DIR` first)")
    names = device_tools(path)
    data = _read_csv(path, None)
    title = _device_title(d)
    t, stage = data["time"], data["stage"]
    spans = stage_spans(t, stage)
    written = []

    fig, axes = _figure(len(names), 2, figsize=(12, 3.4 * len(names) + 0.6), squeeze=False)
    for row, name in enumerate(names):
        z_mm, fz = 1e3 * data[f"{name}_z"], data[f"{name}_fz"]
        a1, a2 = axes[row]
        if np.all(z_mm == z_mm[0]):  # a fixed tool (the gripper's object, the beam's supports)
            a1.text(0.5, 0.5, f"{name} does not move (z = {z_mm[0]:g} mm):\nits force against time only",
                    transform=a1.transAxes, ha="center", va="center", fontsize=9)
            a1.set_axis_off()
        else:
            _by_stage(a1, z_mm, fz, stage, set())
            a1.set_xlabel(f"{name}: z displacement [mm]")
            a1.set_ylabel(f"{name}: F_z [N]")
            a1.set_title(f"{name}: force against displacement", fontsize=10)
            a1.grid(True, alpha=0.3)
            _legend(a1, fontsize=7, title="stage", title_fontsize=7)
        _by_stage(a2, t, fz, stage, set())
        _mark_stages(a2, spans)
        a2.set_xlabel("time [s]")
        a2.set_ylabel(f"{name}: F_z [N]")
        a2.set_title(f"{name}: force against time", fontsize=10)
        a2.grid(True, alpha=0.3)
        if np.all(z_mm == z_mm[0]):
            _legend(a2, fontsize=7, title="stage", title_fontsize=7)
    fig.suptitle(title + " (F_z: the particles' force on the tool, + up)", fontsize=11)
    fig.tight_layout()
    written.append(_save(fig, os.path.join(d, "device_tools.png"), 100))

    apath = os.path.join(d, "air.csv")
    if os.path.isfile(apath):
        air = _read_csv(apath, ("time", "stage", "enclosed_volume", "gas_volume", "dp"))
        aspans = stage_spans(air["time"], air["stage"])
        fig, (a1, a2) = _figure(1, 2, figsize=(12, 4.4))
        _by_stage(a1, air["time"], air["dp"] * 1e-3, air["stage"], set())
        _mark_stages(a1, aspans)
        a1.set_xlabel("time [s]")
        a1.set_ylabel("dp (outside - inside) [kPa]")
        a1.set_title("underpressure", fontsize=10)
        a1.grid(True, alpha=0.3)
        _by_stage(a2, air["time"], air["enclosed_volume"] * 1e6, air["stage"], set())
        a2.plot(air["time"], air["gas_volume"] * 1e6, "k--", lw=0.8, label="gas (enclosed - grains)")
        _mark_stages(a2, aspans)
        a2.set_xlabel("time [s]")
        a2.set_ylabel("volume [cm$^3$]")
        a2.set_title("enclosed volume (through the membrane particles' centres)", fontsize=10)
        a2.grid(True, alpha=0.3)
        _legend(a2, fontsize=7)
        fig.suptitle(title, fontsize=11)
        fig.tight_layout()
        written.append(_save(fig, apath[:-len("air.csv")] + "device_air.png", 100))
    return written


def _read_device_summary(d):
    """(numbers, finished runs) of a device study's summary.csv: its number columns (between
    `case,seed,folder` and `status`) and its rows of status ok."""
    path = os.path.join(d, "summary.csv")
    if not os.path.exists(path):
        raise PlotError(f"{path} not found (not a study folder)")
    header, rows = _read_table(path)
    if header[:3] != ["case", "seed", "folder"] or "status" not in header:
        raise PlotError(f"{path}: not a device study's table (expected case,seed,folder, its numbers, status; "
                        f"columns: {', '.join(header)})")
    numbers = header[3:header.index("status")]
    runs = [r for r in rows if r.get("status") == "ok"]
    if not runs:
        raise PlotError(f"{path}: no finished run (status ok)")
    return numbers, runs


def device_study_cases(study_dir):
    """What device_study() draws: (cases in order, {number: {case: (mean, ci95 or None, [the runs'
    values])}}, intervals) for the numbers of summary.csv that a finished run has. Means and
    intervals from summary_cases.csv (intervals True); without it the means of summary.csv's
    finished runs (intervals False)."""
    d = os.fspath(study_dir)
    numbers, runs = _read_device_summary(d)
    cases = list(dict.fromkeys(r["case"] for r in runs))
    values = {q: {c: [v for r in runs if r["case"] == c for v in [records.finite_number(r.get(q))] if v is not None]
                  for c in cases} for q in numbers}
    path = os.path.join(d, "summary_cases.csv")
    table = {}
    if os.path.exists(path):
        header, rows = _read_table(path)
        need = ["case"] + [f"{q}_{x}" for q in numbers for x in ("mean", "ci95")]
        missing = [c for c in need if c not in header]
        if missing:
            raise PlotError(f"{path}: missing column(s) {', '.join(missing)}")
        table = {r["case"]: r for r in rows}
    out = {}
    for q in numbers:
        per = {}
        for c in cases:
            if not values[q][c]:
                continue
            if table:
                row = table.get(c, {})
                m = records.finite_number(row.get(f"{q}_mean"))
                per[c] = (m if m is not None else float(np.mean(values[q][c])),
                          records.finite_number(row.get(f"{q}_ci95")), values[q][c])
            else:
                per[c] = (float(np.mean(values[q][c])), None, values[q][c])
        if per:
            out[q] = per
    return cases, out, bool(table)


def device_numbers_figure(title, cases, stats, intervals=True, notes=""):
    """The figure of device_study() (and of vppdem.report's device study report): a panel per
    number of `stats` ({number: {case: (mean, 95% half width or None, [the runs' values])}}, in SI
    units), the cases on the x axis in the order of `cases`: the mean (with its interval as an error
    bar when `intervals`), each run as a dot. `notes`: text under the panels."""
    qs = list(stats)
    if not qs:
        raise PlotError(f"{title}: no number to draw")
    cols = min(len(qs), 3)
    rows = (len(qs) + cols - 1) // cols
    fig, axes = _figure(rows, cols, figsize=(max(4.8, 0.55 * len(cases) + 2.5) * cols, 3.9 * rows + 0.4), squeeze=False)
    for k, q in enumerate(qs):
        ax = axes[k // cols][k % cols]
        label, scale = device_number_label(q)
        per = stats[q]
        xs = [i for i, c in enumerate(cases) if c in per]
        ms = [per[cases[i]][0] * scale for i in xs]
        err = [(per[cases[i]][1] or 0.0) * scale for i in xs]
        ax.errorbar(xs, ms, yerr=err if intervals else None, fmt="s", color="C0", capsize=4, ms=5, zorder=3,
                    label="mean, 95% interval" if intervals else "mean")
        for i in xs:
            vs = per[cases[i]][2]
            ax.plot([i] * len(vs), [v * scale for v in vs], ".", color="0.45", alpha=0.6, ms=6, zorder=2)
        ax.set_xticks(range(len(cases)), cases, rotation=30 if len(cases) > 4 else 0,
                      ha="right" if len(cases) > 4 else "center", fontsize=8)
        ax.set_xlim(-0.5, len(cases) - 0.5)
        ax.set_ylabel(label)
        ax.set_title(q, fontsize=9)
        ax.grid(True, alpha=0.3)
    for k in range(len(qs), rows * cols):
        axes[k // cols][k % cols].axis("off")
    what = ("mean over the seeds, 95% interval (Student t); dots: runs" if intervals
            else "mean over the runs, no intervals; dots: runs")
    fig.suptitle(f"{title}: {what}", fontsize=10)
    fig.tight_layout(rect=(0, 0.04 if notes else 0, 1, 0.97))
    _caption(fig, notes)
    return fig


def split_constant(stats):
    """(the numbers whose runs differ, [(number, value)] of those the same in every run) of
    device_numbers_figure's `stats`; with no number that differs (one run), all of them differ."""
    varying, constant = [], []
    for q, per in stats.items():
        vals = {v for _, _, vs in per.values() for v in vs}
        if len(vals) == 1:
            constant.append((q, next(iter(vals))))
        else:
            varying.append(q)
    return (varying, constant) if varying else (list(stats), [])


def constant_text(constant):
    """'the same in every run: grains = 570, ...' (in the units shown), or ''."""
    if not constant:
        return ""
    parts = []
    for q, v in constant:
        label, unit, scale = DEVICE_NUMBERS.get(q, (q, "", 1.0))
        parts.append(f"{label} {v * scale:g}" + (f" {unit}" if unit else ""))
    return "the same in every run: " + ", ".join(parts)


def device_study(study_dir, caption=None, prefix=None):
    """Each number of a device study's summary.csv against the case (PREFIX_numbers.png; prefix
    default "sweep"): the mean over the seeds with its 95% interval, each run as a dot; the numbers
    the same in every run named under the figure. Returns the paths written."""
    d = os.fspath(study_dir)
    prefix = prefix or "sweep"
    cases, stats, intervals = device_study_cases(d)
    if not stats:
        raise PlotError(f"{os.path.join(d, 'summary.csv')}: no finished run has a number")
    if not intervals:
        _warn(f"{os.path.join(d, 'summary_cases.csv')} not found: the means without their intervals "
              "(`vppdem sweep STUDY --out DIR --report-only` writes it)")
    varying, constant = split_constant(stats)
    notes = "; ".join(t for t in (constant_text(constant), caption) if t)
    fig = device_numbers_figure(os.path.basename(os.path.abspath(d)), cases, {q: stats[q] for q in varying},
                                intervals, notes)
    return [_save(fig, os.path.join(d, f"{prefix}_numbers.png"), 110)]


# ---- command ------------------------------------------------------------------------------------

KINDS = ("damper", "sweep", "calibration", "device", "device_study")


def _is_device_study(d):
    path = os.path.join(d, "summary.csv")
    try:
        with open(path, newline="") as f:
            return f.readline().startswith("case,seed,folder,")
    except OSError:
        return False


def kind_of(d):
    """What a folder holds: "calibration" (calibration.json), "device_study" (a summary.csv beginning
    `case,seed,folder`), "sweep" (another summary.csv), "device" (tools.csv or tools.csv.gz and no
    forces.csv) or "damper"."""
    if os.path.exists(os.path.join(d, "calibration.json")):
        return "calibration"
    if _is_device_study(d):
        return "device_study"
    if os.path.exists(os.path.join(d, "summary.csv")):
        return "sweep"
    if not os.path.exists(os.path.join(d, "forces.csv")) and any(
            os.path.isfile(os.path.join(d, f)) for f in ("tools.csv", "tools.csv.gz")):
        return "device"
    return "damper"


def main(argv=None):
    ap = argparse.ArgumentParser(
        prog="python3 -m vppdem.plot",
        description="Draws the plots of a vppdem output folder (PNG): a calibration folder (calibration.json) "
                    "calibration.png and the sweep plots, a device study's folder (summary.csv of case,seed,folder) "
                    "its numbers against the case, a sweep folder (summary.csv) the sweep plots, a device run's "
                    "folder (tools.csv) its tools' forces and its air, else the damper loops. Prints the files "
                    "written, one per line.")
    ap.add_argument("dir", help="damper, device, sweep or calibration output folder")
    ap.add_argument("--caption", default="", metavar="TEXT",
                    help="text under the sweep and calibration figures (e.g. the command that made the data)")
    ap.add_argument("--prefix", default="sweep", metavar="NAME",
                    help="the sweep plots' names: NAME_W.png, NAME_loops.png; a device study's NAME_numbers.png")
    ap.add_argument("--kind", choices=KINDS, help="draw only this kind's plots (default: what DIR holds)")
    a = ap.parse_args(argv)
    kind = a.kind or kind_of(a.dir)
    try:
        if kind == "damper":
            written = damper(a.dir)
        elif kind == "sweep":
            written = sweep(a.dir, a.caption, a.prefix)
        elif kind == "device":
            written = device(a.dir)
        elif kind == "device_study":
            written = device_study(a.dir, a.caption, a.prefix)
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
