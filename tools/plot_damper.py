#!/usr/bin/env python3
"""Plots the hysteresis loops of a `vppdem damper` run.

usage: plot_damper.py DIR

Reads DIR/forces.csv (header `time,displacement,force_total,force_grains,force_foil,
force_zeroed,cycle`; displacement [m] of the upper cap downward from the start of cycling,
forces [N], both positive in compression; cycle 1-based) and writes
  DIR/loops_total.png   force_total (grains + foil, not zeroed) vs displacement
  DIR/loops_foil.png    force_foil vs displacement
  DIR/loops_grains.png  force_grains vs displacement
  DIR/loops.png         the three side by side (total, foil, grains)
with one colour per cycle. The title gives the underpressure when DIR/summary.json has the key
"underpressure" [Pa]; when DIR/cycles.csv exists (header `cycle,dissipated_energy,W,...`), the
legend of the total plots gives W [J/m^2] per cycle. When cycles.csv also has the energy
columns `friction_dissipation,damping_dissipation,viscous_dissipation` [J] (a damper run; see
docs/energy.md), it writes
  DIR/energy_split.png  per cycle, the dissipated energy split into friction, local damping and
                        viscous damping (stacked bars) against the loop area; next to it, from
                        DIR/energy.csv when present, the cumulative terms over time.
Exits nonzero with a message when forces.csv is missing, empty or lacks a plotted column.
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

COLUMNS = ("displacement", "force_total", "force_grains", "force_foil", "cycle")  # the ones plotted
PANELS = (  # (column, file stem, panel title)
    ("force_total", "total", "total force (grains + foil, not zeroed)"),
    ("force_foil", "foil", "foil force (top ring)"),
    ("force_grains", "grains", "grain force (upper cap)"),
)


def fail(msg):
    print(f"plot_damper.py: {msg}", file=sys.stderr)
    sys.exit(1)


def read_csv(path, required):
    """Returns {column: float array} for the named columns of a CSV file with a header."""
    with open(path, newline="") as f:
        rows = [r for r in csv.reader(f) if r and any(c.strip() for c in r) and not r[0].startswith("#")]
    if not rows:
        raise ValueError(f"{path} is empty")
    header = [c.strip() for c in rows[0]]
    missing = [c for c in required if c not in header]
    if missing:
        raise ValueError(f"{path}: missing column(s) {', '.join(missing)} (columns: {', '.join(header)})")
    if len(rows) < 2:
        raise ValueError(f"{path} has a header but no data rows")
    out = {}
    for name in required:
        k = header.index(name)
        try:
            out[name] = np.array([float(r[k]) for r in rows[1:]])
        except (ValueError, IndexError) as e:
            raise ValueError(f"{path}: bad value in column {name}: {e}") from None
    return out


def find_key(obj, key):
    """The value of `key` at the top level of a JSON object, else in nested objects."""
    if isinstance(obj, dict):
        if key in obj:
            return obj[key]
        for v in obj.values():
            r = find_key(v, key)
            if r is not None:
                return r
    return None


def underpressure_text(d):
    path = os.path.join(d, "summary.json")
    try:
        with open(path) as f:
            dp = float(find_key(json.load(f), "underpressure"))
    except (OSError, ValueError, TypeError):
        return ""
    return f"underpressure {dp / 1e6:.3g} MPa"


def read_w(d):
    """{cycle: W} from DIR/cycles.csv, empty when absent or unreadable."""
    path = os.path.join(d, "cycles.csv")
    if not os.path.exists(path):
        return {}
    try:
        c = read_csv(path, ("cycle", "W"))
    except (OSError, ValueError) as e:
        print(f"plot_damper.py: ignoring {path}: {e}", file=sys.stderr)
        return {}
    return {int(round(k)): w for k, w in zip(c["cycle"], c["W"])}


ENERGY_TERMS = (  # (cycles.csv / energy.csv column, label, colour)
    ("friction_dissipation", "friction (Coulomb slip)", "tab:blue"),
    ("damping_dissipation", "local damping", "tab:orange"),
    ("viscous_dissipation", "viscous (restitution)", "tab:green"),
)


def plot_energy_split(d, dp):
    """DIR/energy_split.png from the energy columns of cycles.csv (and energy.csv); None if absent."""
    path = os.path.join(d, "cycles.csv")
    if not os.path.exists(path):
        return None
    try:
        c = read_csv(path, ("cycle", "dissipated_energy") + tuple(t[0] for t in ENERGY_TERMS))
    except (OSError, ValueError):
        return None  # a cycles.csv without the energy budget (e.g. from `vppdem analyze`)
    e = None
    epath = os.path.join(d, "energy.csv")
    if os.path.exists(epath):
        try:
            e = read_csv(epath, ("time", "boundary_work", "pressure_work", "residual") + tuple(t[0] for t in ENERGY_TERMS))
        except (OSError, ValueError) as err:
            print(f"plot_damper.py: ignoring {epath}: {err}", file=sys.stderr)
    fig, axes = plt.subplots(1, 2 if e is not None else 1, figsize=(13 if e is not None else 6.4, 4.8), squeeze=False)
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
    ax.legend(fontsize=8, loc="lower right")
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
        ax.legend(fontsize=8, loc="upper left")
    fig.suptitle(f"VPP damper energy budget{', ' + dp if dp else ''}", fontsize=11)
    fig.tight_layout()
    out = os.path.join(d, "energy_split.png")
    fig.savefig(out, dpi=100)
    plt.close(fig)
    return out


def cycle_colours(cycles):
    cmap = plt.get_cmap("tab10") if len(cycles) <= 10 else plt.get_cmap("viridis")
    n = max(len(cycles) - 1, 1)
    return {c: (cmap(i) if len(cycles) <= 10 else cmap(i / n)) for i, c in enumerate(cycles)}


def draw(ax, data, column, title, colours, w_by_cycle):
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
    ax.legend(fontsize=8, loc="best")


def main():
    if len(sys.argv) != 2 or sys.argv[1] in ("-h", "--help"):
        print(__doc__.strip(), file=sys.stderr)
        sys.exit(0 if len(sys.argv) == 2 else 2)
    d = sys.argv[1]
    path = os.path.join(d, "forces.csv")
    if not os.path.isfile(path):
        fail(f"{path} not found (run `vppdem damper` with this output directory first)")
    if os.path.getsize(path) == 0:
        fail(f"{path} is empty")
    try:
        data = read_csv(path, COLUMNS)
    except (OSError, ValueError) as e:
        fail(str(e))
    finite = np.isfinite(data["displacement"]) & np.isfinite(data["cycle"])
    data = {k: v[finite] for k, v in data.items()}
    if not len(data["cycle"]):
        fail(f"{path} has no finite rows")

    cycles = sorted(set(np.rint(data["cycle"]).astype(int).tolist()))
    colours = cycle_colours(cycles)
    w_by_cycle = read_w(d)
    dp = underpressure_text(d)
    written = []

    for column, stem, title in PANELS:
        fig, ax = plt.subplots(figsize=(6.4, 4.8))
        draw(ax, data, column, title, colours, w_by_cycle if stem == "total" else {})
        fig.suptitle(f"VPP damper loops{', ' + dp if dp else ''}", fontsize=11)
        fig.tight_layout()
        out = os.path.join(d, f"loops_{stem}.png")
        fig.savefig(out, dpi=110)
        plt.close(fig)
        written.append(out)

    fig, axes = plt.subplots(1, 3, figsize=(16, 4.8))
    for ax, (column, stem, title) in zip(axes, PANELS):
        draw(ax, data, column, title, colours, w_by_cycle if stem == "total" else {})
    fig.suptitle(f"VPP damper loops{', ' + dp if dp else ''}", fontsize=12)
    fig.tight_layout()
    out = os.path.join(d, "loops.png")
    fig.savefig(out, dpi=100)
    plt.close(fig)
    written.append(out)
    out = plot_energy_split(d, dp)
    if out:
        written.append(out)
    print("\n".join(written))


if __name__ == "__main__":
    main()
