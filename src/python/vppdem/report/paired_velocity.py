"""Velocity convergence of a `vppdem sweep` with seeds: paired differences against the slowest
velocity (docs/studies.md, "Velocity convergence").

usage: python3 -m vppdem.report paired_velocity DIR [--key process.velocity] [--quantities W,peak_force,W_settled]
                              [--out PREFIX] [--caption TEXT]

Reads DIR/summary.csv of a sweep over `--key` (default process.velocity) x simulation.seed (and
any other keys, e.g. process.underpressure: one group per combination of them). In each group the
runs of one seed share their prepared sample, so the differences between velocities at the same
seed are free of the packing's scatter: for each velocity v and quantity Q,
    d_s = Q(v, seed s) - Q(v_slowest, seed s)
over the seeds finished at both, with the mean, the sample standard deviation and the 95%
interval mean(d) +- t_{0.975, n-1} sd(d) / sqrt(n) (Student t, n - 1 degrees of freedom). v is
"within" when that interval contains 0 (its Q cannot be told from the slowest's at this number of
seeds); the group's converged velocity is the fastest v such that v and every velocity between it
and the slowest are within.

Writes PREFIX.csv (default DIR/paired_velocity.csv), one row per group, velocity and quantity:
  <group keys>,velocity,quantity,n,mean,sd,ci95,diff_n,diff_mean,diff_sd,diff_ci95,within,converged
(mean, sd, ci95: Q over the seeds, unpaired; diff_*: the paired differences; within 1/0, empty
with fewer than 2 pairs; converged 1 on the group's converged velocity) and PREFIX.png (per
quantity: Q against velocity with its interval, and the paired difference with its interval),
and prints the converged velocity of each group. The intervals are vppdem.report.stats'. Runs under
/usr/bin/python3 (matplotlib, numpy).
"""
import argparse
import math
import os
import sys

from ..records import fail, read_table
from ..records import finite_number as number
from .stats import interval

SEED = "simulation.seed"


def fmt(v):
    return "" if v is None or (isinstance(v, float) and not math.isfinite(v)) else f"{v:.10g}"


def analyse(rows, keys, vkey, quantities):
    """Per group of the other keys: {velocity: {quantity: stats}}, the converged velocities."""
    others = [k for k in keys if k not in (vkey, SEED)]
    groups = {}
    for r in rows:
        groups.setdefault(tuple(r[k] for k in others), []).append(r)
    results = []
    for g, members in groups.items():
        vels = sorted({number(r[vkey]) for r in members if number(r[vkey]) is not None})
        if not vels:
            continue
        slow = vels[0]
        by = {(number(r[vkey]), r[SEED]): r for r in members}
        seeds = sorted({r[SEED] for r in members}, key=lambda s: (number(s) is None, number(s) or 0, s))
        table = {}
        for v in vels:
            for q in quantities:
                vals = [number(by[(v, s)].get(q)) for s in seeds if (v, s) in by]
                diffs = []
                for s in seeds:
                    a, b = by.get((v, s)), by.get((slow, s))
                    if a is None or b is None:
                        continue
                    x, y = number(a.get(q)), number(b.get(q))
                    if x is not None and y is not None:
                        diffs.append(x - y)
                st, dt = interval(vals), interval(diffs)
                within = None
                if dt[0] >= 2:
                    within = abs(dt[1]) <= dt[3]
                elif v == slow and dt[0] >= 1:
                    within = True  # the reference against itself
                table[(v, q)] = (st, dt, within)
        converged = {}
        for q in quantities:
            best = None
            for v in vels:  # slowest first: stop at the first velocity that is not within
                if table[(v, q)][2]:
                    best = v
                else:
                    break
            converged[q] = best
        results.append((g, others, vels, table, converged))
    return results


def main(argv=None):
    ap = argparse.ArgumentParser(description="paired velocity convergence of a vppdem sweep with seeds")
    ap.add_argument("dir")
    ap.add_argument("--key", default="process.velocity")
    ap.add_argument("--quantities", default="W,peak_force,W_settled")
    ap.add_argument("--out", default="")
    ap.add_argument("--caption", default="")
    a = ap.parse_args(argv)
    path = os.path.join(a.dir, "summary.csv")
    if not os.path.exists(path):
        fail(f"{path} not found (not a sweep folder)")
    header, rows = read_table(path)
    if not rows:
        fail(f"{path} holds no run")
    if "W" not in header:
        fail(f"{path}: no column W")
    keys = header[: header.index("W")]
    for k in (a.key, SEED):
        if k not in keys:
            fail(f"{path}: the sweep has no grid key {k} (keys: {', '.join(keys)}); run it with seeds (seeds = N)")
    rows = [r for r in rows if r.get("status") == "ok"]
    quantities = [q for q in a.quantities.split(",") if q in header]
    quantities = [q for q in quantities if any(number(r.get(q)) is not None for r in rows)]
    if not quantities:
        fail(f"{path}: none of the quantities {a.quantities} has a value")
    results = analyse(rows, keys, a.key, quantities)
    prefix = a.out or os.path.join(a.dir, "paired_velocity")

    others = results[0][1] if results else []
    lines = [",".join(others + ["velocity", "quantity", "n", "mean", "sd", "ci95", "diff_n", "diff_mean", "diff_sd",
                                "diff_ci95", "within", "converged"])]
    for g, _, vels, table, converged in results:
        for q in quantities:
            for v in vels:
                st, dt, within = table[(v, q)]
                lines.append(",".join(list(g) + [fmt(v), q, str(st[0]), fmt(st[1]), fmt(st[2]), fmt(st[3]), str(dt[0]),
                                                 fmt(dt[1]), fmt(dt[2]), fmt(dt[3]),
                                                 "" if within is None else str(int(within)),
                                                 str(int(converged[q] == v))]))
        label = ", ".join(f"{k} = {v}" for k, v in zip(others, g)) or "all runs"
        for q in quantities:
            c = converged[q]
            msg = (f"{q}: fastest velocity within the paired 95% interval of {vels[0]:g} m/s (and every slower one): "
                   f"{c:g} m/s" if c is not None else f"{q}: no velocity to compare (fewer than 2 paired seeds)")
            print(f"{label}: {msg}")
    tmp = prefix + ".csv.part"
    with open(tmp, "w") as f:
        f.write("\n".join(lines) + "\n")
    os.replace(tmp, prefix + ".csv")

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(len(quantities), 2, figsize=(11, 3.6 * len(quantities)), squeeze=False)
    for qi, q in enumerate(quantities):
        a1, a2 = axes[qi]
        for gi, (g, _, vels, table, converged) in enumerate(results):
            label = ", ".join(f"{k} = {v}" for k, v in zip(others, g)) or None
            colour = f"C{gi % 10}"
            st = [table[(v, q)][0] for v in vels]
            dt = [table[(v, q)][1] for v in vels]
            a1.errorbar(vels, [s[1] for s in st], yerr=[0 if math.isnan(s[3]) else s[3] for s in st], fmt="o-",
                        capsize=3, color=colour, label=label)
            a2.errorbar(vels, [d[1] for d in dt], yerr=[0 if math.isnan(d[3]) else d[3] for d in dt], fmt="o-",
                        capsize=3, color=colour, label=label)
            if converged[q] is not None:
                a2.axvline(converged[q], color=colour, ls=":", lw=1)
        a2.axhline(0, color="0.3", lw=0.8)
        for ax in (a1, a2):
            ax.set_xscale("log")
            ax.set_xlabel(f"{a.key} [m/s]")
            ax.grid(True, alpha=0.3)
        a1.set_ylabel(f"{q} (mean over seeds, 95% interval)")
        a2.set_ylabel(f"{q} - {q} at the slowest, same seed")
        if others:
            a1.legend(fontsize=8)
    fig.suptitle("velocity convergence: paired differences against the slowest velocity (dotted: converged)")
    fig.tight_layout(rect=(0, 0.03 if a.caption else 0, 1, 1))
    if a.caption:
        fig.text(0.01, 0.005, a.caption, fontsize=6, color="0.35")
    fig.savefig(prefix + ".png", dpi=120)
    print(f"wrote {prefix}.csv and {prefix}.png")


if __name__ == "__main__":
    main(sys.argv[1:])
