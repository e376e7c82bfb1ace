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

       python3 -m vppdem.report velocity_cycles --page STUDIES.md QUICK.csv SMALL.csv
writes docs/studies.md's "Velocity convergence: results" tables and verdicts (the blocks
<!-- velocity_cycles:quick|small|rules begin/end -->) from the published tables of the two dampers,
every "resolved", "within" and verdict by vppdem.report.rules (paired differences, the equivalence
rule, label() for one run), with the page's "Decision rules".
"""
import argparse
import csv
import glob
import json
import os
import re
import sys

from ..records import fail, read_table
from . import rules
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
    argv = sys.argv[1:] if argv is None else list(argv)
    if "--page" in argv:
        return page_main(argv)
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



# ---------------------------------------------------------------------------------------------
# The page: docs/studies.md's "Velocity convergence: results", its tables and what the rules decide,
# from the published tables (docs/data/velocity_quick.csv, velocity_small.csv) (issue 60, items 1
# and 5). Every "resolved", "within" and verdict there is vppdem.report.rules'.

PAGE_USAGE = ("usage: python3 -m vppdem.report velocity_cycles --page STUDIES.md QUICK.csv SMALL.csv\n"
              "  writes the blocks <!-- velocity_cycles:NAME begin/end --> (quick, small, rules) of STUDIES.md from\n"
              "  the published tables of scripts/velocity_convergence.sh (docs/data/velocity_quick.csv, "
              "velocity_small.csv)")
QUICK_STUDY = "studies/velocity/quick.toml"
# The velocities the repository runs at, named on the page with their verdict as a shortcut.
NAMED_VELOCITIES = [(0.01, "the studies' velocity (scripts/trust_studies.sh)"), (0.02, "the README's main job")]
SMALL_STUDY = "studies/velocity/small.toml"


def read_published(path):
    """{(dp, cycle, v, quantity): (n, mean, ref_velocity, rules difference against ref_velocity)} of a
    table this report wrote (PREFIX.csv); the difference's reference is the reference velocity's mean
    over the pairs (diff_mean / rel_diff), or its row's mean."""
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))

    def num(x):
        try:
            return float(x)
        except (TypeError, ValueError):
            return float("nan")
    means = {(num(r["underpressure"]), int(r["cycle"]), num(r["velocity"]), r["quantity"]): num(r["mean"]) for r in rows}
    out = {}
    for r in rows:
        dp, k, v, q = num(r["underpressure"]), int(r["cycle"]), num(r["velocity"]), r["quantity"]
        ref_v = num(r["ref_velocity"])
        n, dm, h, rel = int(r["diff_n"]), num(r["diff_mean"]), num(r["diff_ci95"]), num(r["rel_diff"])
        ref = dm / rel if rel and rel == rel and dm else means.get((dp, k, ref_v, q))
        d = rules.from_interval("paired", n, dm, h if n >= 2 else None, n - 1, ref)
        out[(dp, k, v, q)] = (int(r["n"]), num(r["mean"]), ref_v, d)
    return out


def bold_if(text, d):
    return f"**{text}**" if rules.resolved(d) == "resolved" else text


def fastest(tab, dp, k, q="W"):
    """(the fastest velocity with no change from the reference resolved at it or any slower one, the
    fastest whose interval and every slower one's lie within the margin) of one dp and cycle: by
    rules.resolved and rules.band; None where none."""
    vs = sorted(v for (d_, k_, v, q_), x in tab.items() if d_ == dp and k_ == k and q_ == q and v != x[2]
                and x[3].ok)
    free = within = None
    for v in vs:
        if rules.resolved(tab[(dp, k, v, q)][3]) != "unresolved":
            break
        free = v
    for v in vs:
        if rules.band(tab[(dp, k, v, q)][3]) != "within":
            break
        within = v
    return free, within


def shortcut(tabs, v):
    """The spec's criterion for a velocity v as a shortcut, W within the scatter of slower runs, as a
    claim of no effect: the equivalence rule on every dp and cycle of the tables (tabs [(name, tab)]).
    (verdict, the bands, the reach's range)."""
    diffs = [x[3] for _, tab in tabs for (dp, k, vv, q), x in tab.items()
             if q == "W" and vv == v and vv != x[2] and x[3].ok]
    bands = [rules.band(d) for d in diffs]
    reach = [rules.reach(d) for d in diffs if rules.reach(d) is not None]
    return rules.verdict_equivalence(bands) if bands else None, bands, (min(reach), max(reach)) if reach else None


def quick_block(tab):
    dps = sorted({k[0] for k in tab})
    vs = sorted({k[2] for k in tab if tab[k][0] >= 2 and k[2] != tab[k][2]})
    L = ["| dp, cycle (slowest: W there) | " + " | ".join(f"{v:g} m/s" for v in vs)
         + " | no change resolved up to / within +-10% up to |", "|---|" + "---|" * (len(vs) + 1)]
    first = True
    for dp in dps:
        for k in sorted({kk[1] for kk in tab if kk[0] == dp}):
            ref_v = next(x[2] for kk, x in tab.items() if kk[0] == dp and kk[1] == k)
            ref_mean = tab.get((dp, k, ref_v, "W"), (0, float("nan")))[1]
            cells = []
            for v in vs:
                x = tab.get((dp, k, v, "W"))
                if x is None or not x[3].ok:
                    cells.append("-")
                    continue
                d = x[3]
                cells.append(f"{d.d:+.0f} (+-{d.h:.0f}), " + bold_if(f"{100 * d.rel:+.1f}%", d))
            free, within = fastest(tab, dp, k)
            L.append(f"| {dp / 1e6:g} MPa, cycle {k} ({ref_v:g} m/s: {ref_mean:.0f}{' J/m2' if first else ''}) | "
                     + " | ".join(cells) + f" | {f'{free:g} m/s' if free else 'none'} / "
                     f"{f'{within:g} m/s' if within else 'none'} |")
            first = False
    beyond = [f"{dp / 1e6:g} MPa cycle {k} at {v:g} m/s" for (dp, k, v, q), x in sorted(tab.items())
              if q == "W" and rules.band(x[3]) == "beyond"]
    one = [(dp, k, v, x) for (dp, k, v, q), x in sorted(tab.items()) if q == "W" and x[0] < 2 and v != x[2]]
    L += ["", "Bold: resolved (0 outside the paired 95% interval; vppdem.report.rules). The equivalence rule "
          f"(+-{100 * rules.MARGIN:.0f}% of W at the slowest velocity): "
          + ("no interval lies within the margin" if not any(rules.band(x[3]) == "within" for (_, _, _, q), x in tab.items()
                                                            if q == "W") else "see the last column")
          + (f"; wholly beyond it: {', '.join(beyond)}" if beyond else "") + "."]
    for dp, k, v, x in one:
        rel = f", {100 * x[3].d / x[3].ref:+.1f}% from {x[2]:g} m/s (the same seed)" if x[3].ref else ""
        L.append(f"At {v:g} m/s ({dp / 1e6:g} MPa, cycle {k}) {x[0]} run: W {x[1]:.0f} J/m2{rel}: "
                 f"**{rules.label('one run')}**.")
    return L


def small_block(tab):
    ref_dp = 60000.0
    vs = sorted(v for (dp, k, v, q), x in tab.items() if dp == ref_dp and k == 1 and q == "W" and v != x[2])
    ref_v = tab[(ref_dp, 1, vs[0], "W")][2]
    L = [f"Cycle 1 against the paper's velocity at {ref_dp / 1e6:g} MPa (W {tab[(ref_dp, 1, ref_v, 'W')][1]:.0f} J/m2 "
         "there), and the energy ledger's terms (bold: resolved; the last column: the equivalence rule, "
         f"+-{100 * rules.MARGIN:.0f}% of W at the paper's velocity):", "",
         "| v [m/s] | W | friction dissipation | local damping dissipation | W by the rules |", "|---|---|---|---|---|"]
    for v in vs:
        d = tab[(ref_dp, 1, v, "W")][3]
        cells = [f"{d.d:+.0f} (+-{d.h:.0f}), " + bold_if(f"{100 * d.rel:+.1f}%", d)]
        for q in ("friction_dissipation", "damping_dissipation"):
            x = tab.get((ref_dp, 1, v, q))
            cells.append(bold_if(f"{100 * x[3].rel:+.0f}%", x[3]) if x and x[3].ok else "-")
        L.append(f"| {v:g} | " + " | ".join(cells) + f" | {rules.statement_equivalence(d)} |")
    other = sorted({dp for (dp, k, v, q) in tab if dp != ref_dp})
    for dp in other:
        ws = sorted(v for (d_, k, v, q), x in tab.items() if d_ == dp and k == 1 and q == "W" and v != x[2])
        rv = tab[(dp, 1, ws[0], "W")][2]
        parts = []
        for v in ws:
            d = tab[(dp, 1, v, "W")][3]
            parts.append(bold_if(f"{100 * d.rel:+.1f}%", d) + f" +-{100 * d.h / d.ref:.0f}% ({v:g} m/s)")
        free, within = fastest(tab, dp, 1)
        L += ["", f"At {dp / 1e6:g} MPa, against the paper's velocity (W {tab[(dp, 1, rv, 'W')][1]:.0f} J/m2 there): "
              + ", ".join(parts) + (f"; no change resolved up to {free:g} m/s" if free else "; a change resolved at "
                                    "every velocity")
              + (f", within +-{100 * rules.MARGIN:.0f}% up to {within:g} m/s." if within else
                 f", none within +-{100 * rules.MARGIN:.0f}%.")]
    return L


def verdict_block(quick, small):
    L = ["What the rules decide (the spec's criterion for a faster velocity as a shortcut, \"W within the "
         "scatter of slower runs\", read as a claim of no effect: the equivalence rule on the paired difference "
         "from the slowest velocity of each dp and cycle (the paper's damper: 0.005 m/s; the small damper: the "
         "paper's velocity in cycle 1, 0.002 m/s in cycles 2-3), every dp and cycle of the tables; reproduced only "
         f"where every interval lies within +-{100 * rules.MARGIN:.0f}%):", "",
         "| velocity | the paper's damper (cycles 1-2, 0.02 and 0.06 MPa, 2 seeds) | the small damper (cycles 1-3, "
         "0.02 and 0.06 MPa, 3 seeds) |", "|---|---|---|"]
    vs = sorted({k[2] for k in quick if quick[k][0] >= 2} | {k[2] for k in small if small[k][0] >= 2})
    for v in vs:
        cells = []
        for tab in (quick, small):
            verdict, bands, reach = shortcut([("", tab)], v)
            if verdict is None:
                cells.append("-")
                continue
            cnt = {b: bands.count(b) for b in ("within", "resolved", "beyond", "unresolved") if b in bands}
            cells.append(f"**{verdict}** (" + ", ".join(f"{n} {b}" for b, n in cnt.items())
                         + ((f"; changes up to {100 * reach[0]:.0f}-{100 * reach[1]:.0f}% not excluded"
                             if round(100 * reach[0]) != round(100 * reach[1]) else
                             f"; changes up to {100 * reach[1]:.0f}% not excluded") if reach else "")
                         + ")")
        if any(c != "-" for c in cells):
            L.append(f"| {v:g} m/s | " + " | ".join(cells) + " |")
    named = []
    for v, who in NAMED_VELOCITIES:
        vq, vs_ = shortcut([("", quick)], v)[0], shortcut([("", small)], v)[0]
        if vq or vs_:
            named.append(f"{who}, {v:g} m/s: {vq or 'not run'} on the paper's damper, {vs_ or 'not run'} on the small "
                         "damper")
    if named:
        L += ["", "; ".join(named)[0].upper() + "; ".join(named)[1:] + "."]
    L += ["", "within: the interval inside the margin; unresolved: 0 inside the interval, which reaches past the "
          "margin; resolved: 0 outside, the interval reaching inside the margin; beyond: wholly outside the margin "
          "(rules.band). Where no velocity is reproduced, the fastest whose change is not resolved (the tables' last "
          "column) is a velocity the runs do not reject, not one they establish."]
    return L


def velocity_rules(root):
    return rules.section(rules.PageRules(
        module="vppdem.report.velocity_cycles",
        tests=[("paired", "every velocity against the slowest (or the paper's) of the same seed: a seed's velocities "
                          "all branch from its one prepared sample"),
               ("equivalence", "a faster velocity as a shortcut (W within the scatter of slower runs): the whole "
                               "interval within the margin of W at the slowest velocity")],
        which_w="W of each cycle (cycles.csv) compared cycle for cycle (cycle 1 with cycle 1); the paper's damper "
                "2 cycles, the small damper 3 (its paper-velocity runs 1); no W_settled, no extrapolation.",
        planned=f"the paper's damper {rules.planned_seeds(os.path.join(root, QUICK_STUDY))} (`seeds` of {QUICK_STUDY}), "
                f"the small damper {rules.planned_seeds(os.path.join(root, SMALL_STUDY))} (`seeds` of {SMALL_STUDY}), "
                "fixed before the runs; one seed at the paper's velocity on the paper's damper "
                "(studies/velocity/quick_paper.toml).",
        labels=["one run"],
        fixed_before=["the grids, the seeds and the cycles of the study files (the runs of 2026-11-23 made by the "
                      "script before the files, with the same grids): a plan, not a decision rule; the criterion of "
                      "the spec (section 5), W of a faster velocity within the scatter of slower runs, then read as "
                      "'0 inside the paired interval'"],
        fixed_after=["the equivalence margin (+-10%) as the reading of 'within the scatter', and every verdict here: "
                     "written after the data were seen (issue 60's rules module); the page named 0.01 m/s 'the "
                     "velocity the measurements justify' before, from intervals that contain 0"]))


def page_main(argv):
    """--page STUDIES.md QUICK.csv SMALL.csv"""
    args = [a for a in argv if a != "--page"]
    if len(args) != 3:
        fail(PAGE_USAGE, 2)
    page, quick_csv, small_csv = args
    quick, small = read_published(quick_csv), read_published(small_csv)
    from . import source_dir
    root = source_dir()
    lines = velocity_rules(root)
    lines[0] = "### Decision rules of the velocity results"
    blocks = {"quick": quick_block(quick), "small": small_block(small),
              "rules": verdict_block(quick, small) + [""] + lines}
    with open(page) as f:
        doc = f.read()
    head = (f"<!-- Generated by `python3 -m vppdem.report velocity_cycles --page {page} {quick_csv} {small_csv}` "
            "from the published tables; do not edit. -->")
    for name, text in blocks.items():
        b, e = f"<!-- velocity_cycles:{name} begin -->", f"<!-- velocity_cycles:{name} end -->"
        if b not in doc or e not in doc:
            fail(f"{page}: no block {b} ... {e}", 2)
        doc = doc[: doc.index(b)] + b + "\n" + head + "\n" + "\n".join(text).rstrip() + "\n" + doc[doc.index(e):]
    with open(page + ".part", "w") as f:
        f.write(doc)
    os.replace(page + ".part", page)
    print(f"vppdem.report velocity_cycles: wrote the velocity results' blocks of {page}")
    return 0


if __name__ == "__main__":
    main(sys.argv[1:])
