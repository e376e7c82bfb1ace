"""Velocity convergence cycle by cycle: paired differences of W (and of the energy ledger's
friction and local-damping dissipation, where the runs recorded them) against a reference
velocity, per underpressure and per cycle (docs/studies.md, "Velocity convergence: results").

usage: python3 -m vppdem.report velocity_cycles SWEEP_DIR [--extra DIR ...] [--reference V] [--out PREFIX]
                          [--caption TEXT]

SWEEP_DIR: a `vppdem sweep` over process.velocity x simulation.seed (and process.underpressure);
every run's cycles.csv is read (not only the last cycle, as vppdem.report.paired_velocity does), so
cycle k at one velocity is compared with cycle k at the reference velocity from the same prepared
sample. --extra: further runs branched from the same samples (e.g. one cycle at the paper's
3.33e-4 m/s), each a damper run's folder or a sweep's folder (then each of its cases with a
summary.json, in name order: a study whose cases take their samples from SWEEP_DIR's, samples_from
in docs/studies.md); a run's summary.json gives velocity, underpressure and seed (an older run's
summary.json without inputs.simulation.seed: the seed is read from the --from checkpoint's folder
name ...simulation.seed=S...). --reference: the velocity to compare with (default: the slowest
present for each underpressure and cycle).

For each underpressure dp, cycle k, velocity v and quantity Q (W [J/m^2], friction and damping
dissipation [J]): d_s = Q(v, k, s) - Q(v_ref, k, s) over the seeds s present at both; the mean,
sample sd and the 95% Student-t interval of d; the relative difference mean(d) / mean(Q_ref).
Writes PREFIX.csv:
  underpressure,cycle,velocity,quantity,n,mean,sd,ref_velocity,diff_n,diff_mean,diff_ci95,rel_diff,within
and PREFIX.png (W per cycle against velocity, one panel per underpressure, every seed a thin line,
the mean bold). Runs under /usr/bin/python3 (numpy, matplotlib).
"""
import argparse
import csv
import glob
import json
import os
import re
import sys

from ..records import fail, read_table
from .stats import interval, mean  # interval: (n, mean, sd, ci95 half width; Student t)

QUANTITIES = ["W", "friction_dissipation", "damping_dissipation", "peak_force"]


def key_value(text, key):
    m = re.search(re.escape(key) + r"=([^_/]+)", text)
    return float(m.group(1)) if m else None


def runs_of_sweep(d):
    out = []
    for case in sorted(glob.glob(os.path.join(d, "*", "cycles.csv"))):
        name = os.path.basename(os.path.dirname(case))
        v = key_value(name, "process.velocity")
        dp = key_value(name, "process.underpressure")
        s = key_value(name, "simulation.seed")
        if v is None or dp is None or s is None:
            continue
        out.append((dp, v, int(s), read_table(case)[1]))
    return out


def extra_dirs(paths):
    """--extra: a run's folder (with summary.json) as it is; a sweep's folder: its finished cases
    (the subfolders with a summary.json), in name order."""
    dirs = []
    for p in paths:
        if os.path.isfile(os.path.join(p, "summary.json")):
            dirs.append(p)
        elif os.path.isdir(p):
            dirs += [os.path.dirname(f) for f in sorted(glob.glob(os.path.join(p, "*", "summary.json")))]
        else:
            fail(f"--extra {p}: no such folder")
    return dirs


def run_of_extra(d):
    with open(os.path.join(d, "summary.json")) as f:
        summ = json.load(f)
    inputs = summ.get("inputs", {})
    frm = summ.get("from", "")
    s = inputs.get("simulation.seed")
    if s is None:  # an older vppdem's summary.json: the seed of the --from checkpoint's folder name
        s = key_value(frm, "simulation.seed")
    if s is None:
        fail(f"{d}: cannot tell the seed from its checkpoint path '{frm}'")
    v = inputs.get("process.velocity")
    dp = inputs.get("process.underpressure", summ.get("underpressure"))
    if v is None:
        fail(f"{d}: summary.json has no inputs.process.velocity")
    return (float(dp), float(v), int(s), read_table(os.path.join(d, "cycles.csv"))[1])


def main(argv=None):
    ap = argparse.ArgumentParser()
    ap.add_argument("sweep")
    ap.add_argument("--extra", nargs="*", default=[])
    ap.add_argument("--reference", type=float)
    ap.add_argument("--out")
    ap.add_argument("--caption", default="")
    a = ap.parse_args(argv)
    runs = runs_of_sweep(a.sweep) + [run_of_extra(d) for d in extra_dirs(a.extra)]
    if not runs:
        fail(f"no finished runs in {a.sweep}")
    prefix = a.out or os.path.join(a.sweep, "velocity_cycles")
    # table[(dp, cycle, v, q)][seed] = value
    table = {}
    for dp, v, s, cycles in runs:
        for row in cycles:
            k = int(row["cycle"])
            for q in QUANTITIES:
                if q in row and row[q] not in ("", "nan"):
                    table.setdefault((dp, k, v, q), {})[s] = float(row[q])
    rows = []
    for dp in sorted({t[0] for t in table}):
        for k in sorted({t[1] for t in table if t[0] == dp}):
            for q in QUANTITIES:
                vs = sorted({t[2] for t in table if t[0] == dp and t[1] == k and t[3] == q})
                if not vs:
                    continue
                ref = a.reference if a.reference in vs else vs[0]
                base = table[(dp, k, ref, q)]
                for v in vs:
                    cur = table[(dp, k, v, q)]
                    _, m, sd, _ = interval(list(cur.values()))
                    common = sorted(set(cur) & set(base))
                    d = [cur[s] - base[s] for s in common]
                    _, dm, dsd, dci = interval(d) if d else (0,) + (float("nan"),) * 3
                    bm = mean([base[s] for s in common])
                    within = "" if len(d) < 2 else int(abs(dm) <= dci)
                    rows.append([dp, k, v, q, len(cur), m, sd, ref, len(d), dm, dci,
                                 dm / bm if bm else float("nan"), within])
    with open(prefix + ".csv.part", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["underpressure", "cycle", "velocity", "quantity", "n", "mean", "sd", "ref_velocity",
                    "diff_n", "diff_mean", "diff_ci95", "rel_diff", "within"])
        for r in rows:
            w.writerow([f"{x:.6g}" if isinstance(x, float) else x for x in r])
    os.replace(prefix + ".csv.part", prefix + ".csv")
    for r in rows:
        if r[3] == "W":
            print(f"dp {r[0]:g} Pa cycle {r[1]} v {r[2]:g} m/s: W {r[5]:.1f} (n {r[4]}), "
                  f"paired to {r[7]:g}: {r[9]:+.1f} +- {r[10]:.1f} ({100 * r[11]:+.1f}%)")
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("vppdem.report velocity_cycles: no matplotlib (run under /usr/bin/python3): no figure", file=sys.stderr)
        return
    dps = sorted({t[0] for t in table})
    fig, axes = plt.subplots(1, len(dps), figsize=(5.5 * len(dps), 4.2), squeeze=False)
    for ax, dp in zip(axes[0], dps):
        for k in sorted({t[1] for t in table if t[0] == dp}):
            vs = sorted({t[2] for t in table if t[0] == dp and t[1] == k and t[3] == "W"})
            seeds = sorted({s for v in vs for s in table[(dp, k, v, "W")]})
            for s in seeds:
                pts = [(v, table[(dp, k, v, "W")][s]) for v in vs if s in table[(dp, k, v, "W")]]
                ax.plot([p[0] for p in pts], [p[1] for p in pts], lw=0.6, alpha=0.5, color=f"C{k - 1}")
            # The mean line joins the velocities every seed ran; a velocity fewer seeds ran (one
            # run at the paper's velocity) is an open marker, so a mean of other seeds is not read
            # as a trend.
            full = max(len(table[(dp, k, v, "W")]) for v in vs)
            on = [v for v in vs if len(table[(dp, k, v, "W")]) == full]
            means = [mean(table[(dp, k, v, "W")].values()) for v in on]
            ax.plot(on, means, "o-", lw=2, color=f"C{k - 1}", label=f"cycle {k}")
            for v in vs:
                if v not in on:
                    runs_v = table[(dp, k, v, "W")]
                    ax.plot([v], [mean(runs_v.values())], "o", mfc="none", ms=9, color=f"C{k - 1}",
                            label=f"cycle {k}, {len(runs_v)} of {full} seeds")
        ax.set_xscale("log")
        ax.set_xlabel("loading velocity v_z [m/s]")
        ax.set_ylabel("W [J/m^2]")
        ax.set_title(f"dp = {dp / 1e6:g} MPa (thin: one seed each)")
        ax.legend(fontsize=8)
    if a.caption:
        fig.text(0.01, 0.005, a.caption, fontsize=6, family="monospace", va="bottom", wrap=True)
    fig.tight_layout(rect=(0, 0.06 if a.caption else 0, 1, 1))
    fig.savefig(prefix + ".png.part.png", dpi=110)
    os.replace(prefix + ".png.part.png", prefix + ".png")


if __name__ == "__main__":
    main(sys.argv[1:])
