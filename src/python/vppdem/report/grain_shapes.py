"""docs/grains.md and its figure from the grain-shape study's records (issue 24, item 4).

usage: python3 -m vppdem.report grain_shapes DATA DOCS [--bench FILE] [--pressure DIR] [--study FILE]
  DATA   the records of scripts/grain_shapes.sh (docs/data/grains/shapes: one folder per case,
         grains.shape=S_simulation.seed=K, with summary.json and cycles.csv)
  DOCS   where grains.md and grains_shapes.png go (docs)
  --bench FILE  the table printed by bench/grain_shapes.sh (its cost per step), quoted as is
  --pressure DIR  the paper's underpressure study (docs/data/paper/radius_underpressure): the
         effect of the confining pressure on W beside the effect of the shape (Athanassiadis et
         al. 2014: "confining pressure has the largest overall effect")
  --study FILE  the study's plan (default studies/grains/shapes.toml): its shapes and seeds; while
         runs of it are missing the page says so and calls its numbers provisional

Per run: W of the stationary tail (summary.json W_settled; when the run did not become
stationary, the mean of its last two cycles, flagged), the peak force and the friction and
local-damping shares of the dissipation over the same cycles, the packing fraction at the start
of the cycling. Per shape: mean and 95% interval over the seeds (Student's t); against the
spheres the ratio of the means with its 95% interval (the shapes prepare their own samples:
unpaired; the delta method on ln R, Welch's degrees of freedom). Beside the experiment of
Athanassiadis et al.: the pressure's and each shape's effect on W as |ln| of the ratio, their
difference with its interval decides, by the direction rule of vppdem.report.rules (every
verdict and label on the page is the rules module's; the page states them in "Decision rules").
Runs under /usr/bin/python3.
"""
import json
import math
import os
import sys
import tomllib
from dataclasses import dataclass

from ..records import fail
from . import rules, source_dir
from .stats import LEVEL, interval, log_ratio, ratio, satterthwaite, t_quantile

COMMAND = ("bash scripts/grain_shapes.sh, then PYTHONPATH=src/python /usr/bin/python3 -m vppdem.report grain_shapes "
           "docs/data/grains/shapes docs "
           "--pressure docs/data/paper/radius_underpressure --bench docs/data/grains/cost_per_step.md")
FIGURE = "grains_shapes.png"
ORDER = ["sphere", "dimer", "trimer", "tetrahedron", "pellet", "template"]
# The seeds the paper's underpressure study (studies/paper/radius_underpressure.toml, whose 25.5 mm
# rows give the pressure's effect) fixed before it ran: 3; its seeds 4 and 5 came after a look at
# other claims (the study file; docs/paper_comparison.md, "Decision rules"), so they stand beside
# the verdict, not in it (vppdem.report.rules: seeds).
PRESSURE_PLANNED = 3


def parse_name(name):
    try:
        shape = name.split("grains.shape=")[1].split("_")[0]
        seed = int(name.split("simulation.seed=")[1])
    except (IndexError, ValueError):
        return None
    return shape, seed


def load(data):
    runs = {}
    if not os.path.isdir(data):
        fail(f"{data}: no such folder (run scripts/grain_shapes.sh first)", 2)
    for name in sorted(os.listdir(data)):
        k = parse_name(name)
        path = os.path.join(data, name, "summary.json")
        if k is None or not os.path.isfile(path):
            continue
        with open(path) as f:
            s = json.load(f)
        cyc = s["cycles"]
        if not cyc:
            continue
        stationary = s.get("W_settled") is not None and s.get("first_settled_cycle") is not None
        used = [c for c in cyc if c["cycle"] >= s["first_settled_cycle"]] if stationary else cyc[-2:]
        W = s["W_settled"] if stationary else sum(c["W"] for c in used) / len(used)
        diss = sum(c["friction_dissipation"] + c["damping_dissipation"] + c["viscous_dissipation"] for c in used)
        runs[k] = dict(
            name=name, W=W, stationary=stationary, W_last=cyc[-1]["W"], W_prev=cyc[-2]["W"] if len(cyc) > 1 else math.nan, cycles=[c["cycle"] for c in used], n_cycles=len(cyc),
            peak=sum(c["peak_force"] for c in used) / len(used),
            friction=sum(c["friction_dissipation"] for c in used) / diss if diss > 0 else math.nan,
            damping=sum(c["damping_dissipation"] for c in used) / diss if diss > 0 else math.nan,
            packing=s["start_of_cycling"]["packing_fraction"], grains=s["grains"], dt=s["dt"],
            velocity=s["inputs"]["process.velocity"],
            dp=s["inputs"]["process.underpressure"], radius=s["inputs"]["damper.radius"])
    if not runs:
        fail(f"{data}: no finished runs (case folders grains.shape=S_simulation.seed=K with summary.json)", 2)
    return runs


def planned(study):
    """(shapes, seeds) of the study file's grid, or None when there is no such file."""
    if not study or not os.path.isfile(study):
        return None
    with open(study, "rb") as f:
        t = tomllib.load(f)
    shapes = t.get("grid", {}).get("grains.shape", [])
    return list(shapes), int(t.get("seeds", 1))


def pressure_effect(root, radius=0.0255):
    """The 25.5 mm rows of the paper's underpressure study: ({dp [Pa]: {seed: W}}, the runs'
    velocity, cycles, and the cases not stationary). W as load(): the mean over the stationary
    cycles, else the mean of the last two (flagged). Stationary by the current build's criterion,
    the paper report's re-analysis (ROOT/../report/<study>/summary.csv, `vppdem sweep
    --report-only`), because these runs were made by an older pinned build whose summary.json
    used an earlier one; without that table, by the runs' own summary.json."""
    out, info = {}, dict(velocity=None, cycles=set(), unsettled=[], criterion="the runs' own summary.json")
    if not os.path.isdir(root):
        return out, info
    settled = None
    table = os.path.join(os.path.dirname(os.path.normpath(root)), "report", os.path.basename(os.path.normpath(root)),
                         "summary.csv")
    if os.path.isfile(table):
        import csv
        with open(table, newline="") as f:
            settled = {r["case"]: r.get("W_settled", "") for r in csv.DictReader(f)}
        info["criterion"] = f"the current build's criterion ({os.path.relpath(table, os.getcwd())})"
    for name in sorted(os.listdir(root)):
        try:
            r = float(name.split("damper.radius=")[1].split("_")[0])
            dp = float(name.split("process.underpressure=")[1].split("_")[0])
            seed = int(name.split("simulation.seed=")[1])
        except (IndexError, ValueError):
            continue
        path = os.path.join(root, name, "summary.json")
        if abs(r - radius) > 1e-9 or not os.path.isfile(path):
            continue
        with open(path) as f:
            s = json.load(f)
        cyc = s["cycles"]
        if not cyc:
            continue
        ws = (settled[name] or None) if settled is not None and name in settled else s.get("W_settled")
        if ws is not None:
            W = float(ws)
        else:
            W = sum(c["W"] for c in cyc[-2:]) / len(cyc[-2:])
            info["unsettled"].append(name)
        out.setdefault(dp, {})[seed] = W
        info["velocity"] = s["inputs"]["process.velocity"]
        info["cycles"].add(len(cyc))
    return out, info


def ratio_text(R, h, n):
    return f"{R:.2f} +- {h:.2f}" if math.isfinite(h) else f"{R:.2f} (no interval: {n} run{'s' if n != 1 else ''})"


def ci(vals, digits=0, scale=1.0):
    n, m, sd, h = interval([v * scale for v in vals])
    if n == 0:
        return "-"
    if n < 2 or not math.isfinite(h):
        return f"{m:.{digits}f} (n = {n})"
    return f"{m:.{digits}f} +- {h:.{digits}f}"


def effect_difference(peff, e):
    """|ln| of the pressure's effect less |ln| of a shape's (a halving as large as a doubling): the
    pressure's (mean of the paired ln ratios, its standard error, dof, n) and the shape's log_ratio
    (ln R, its standard error, Welch dof); their 95% interval by the Welch-Satterthwaite degrees of
    freedom of the two standard errors. A rules difference (test Welch, no reference)."""
    d = abs(peff[0]) - abs(e[0])
    v1, v2 = peff[1] ** 2, e[1] ** 2
    dof = satterthwaite([(v1, peff[2]), (v2, e[2])])
    return rules.from_interval("Welch", peff[3], d, t_quantile(LEVEL, dof) * math.sqrt(v1 + v2), dof, None)


def first_statement(compared):
    """Athanassiadis et al.'s "confining pressure has the largest overall effect", on W: each shape's
    difference (effect_difference) by the direction rule (the pressure's effect larger: +1), the
    claim's verdict over the shapes (rules.verdict_direction: reproduced only where every shape's
    is resolved the claim's way, not reproduced where one is resolved against it). (verdict, the
    shapes' texts)."""
    parts, outs = [], []
    for sh, d in compared:
        o = rules.direction(d, +1) if d is not None else None
        outs.append(o)
        if o is None:
            parts.append(f"{sh}: pending (fewer than 2 runs)")
            continue
        what = {"yes": "the pressure's larger, resolved", "against": "the shape's larger, resolved",
                "unresolved": "not resolved"}[o]
        parts.append(f"{sh}: {rules.verdict_direction([o])}, {what} ({d.d:+.2f} +- {d.h:.2f})")
    return rules.verdict_direction(outs), parts


def page_rules(study, plan, added):
    """The page's "## Decision rules" section (rules.section)."""
    seeds = plan[1] if plan else None
    return rules.section(rules.PageRules(
        module="vppdem.report.grain_shapes",
        tests=[("welch", "each shape against the spheres, and the pressure's effect against each shape's: each "
                         "shape prepares its own samples"),
               ("ratio", "W and the peak force of each shape against the spheres'; the pressure's effect is the "
                         "paired ratio W(0.08 MPa) / W(0.02 MPa) per seed of the paper's underpressure study"),
               ("direction", "the first statement: |ln| of the pressure's effect on W less each shape's, resolved "
                             "above 0 for every shape"),
               ("equivalence", "not applied: no row here claims the absence of an effect")],
        which_w="a run's W_settled (summary.json) where its loops settled, else the mean of its last two cycles "
                "(flagged 'not all stationary'); the pressure study's runs: W_settled by the current build's "
                "criterion, else the mean of their last two cycles.",
        planned=(f"{seeds} per shape (`seeds` of {os.path.relpath(study, os.getcwd()) if study else 'the study file'}), "
                 if seeds else "the study file's, ") + f"fixed before the runs; the pressure's effect: the "
                f"{PRESSURE_PLANNED} seeds the paper's underpressure study planned "
                "(studies/paper/radius_underpressure.toml).",
        added=(f"That study's seeds {', '.join(str(k) for k in added)} were added after a look at other claims "
               "(docs/paper_comparison.md): the verdict is the planned seeds', all seeds stand beside it in "
               "brackets." if added else ""),
        labels=["nothing measured"],
        fixed_before=["the shapes, the seeds and the cycles (studies/grains/shapes.toml), before the runs; a plan, "
                      "not a decision rule"],
        fixed_after=["every test, the direction rule of the first statement and the label of the second: this "
                     "study ran before issue 60's rules module (vppdem.report.rules), and they were applied to its "
                     "data after they had been seen (the first statement read 'undecided: equal within their "
                     "intervals' before, though the dimer's difference excluded 0)"]))


def figure(runs, shapes, docs, note=""):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(1, 4, figsize=(15, 3.8))
    for a, q, label, scale in ((ax[0], "W", "W [J/m$^2$] (stationary cycles)", 1.0),
                               (ax[1], "peak", "peak force [N]", 1.0),
                               (ax[2], "friction", "friction share of the dissipation [%]", 100.0),
                               (ax[3], "packing", "packing fraction at the start of cycling", 1.0)):
        for i, sh in enumerate(shapes):
            vals = [r[q] * scale for (s, _), r in runs.items() if s == sh]
            n, m, sd, h = interval(vals)
            a.bar(i, m, color="C%d" % i, alpha=0.5)
            if math.isfinite(h):
                a.errorbar(i, m, yerr=h, color="k", capsize=4)
            a.plot([i] * len(vals), vals, "k.", ms=5)
        a.set_xticks(range(len(shapes)))
        a.set_xticklabels(shapes)
        a.set_ylabel(label)
        a.grid(alpha=0.3, axis="y")
    fig.suptitle("Grain shape at 0.06 MPa: mean and 95% interval over the seeds (dots: the seeds)" + note, fontsize=10)
    fig.tight_layout()
    p = os.path.join(docs, FIGURE)
    fig.savefig(p + ".part.png", dpi=110)
    os.replace(p + ".part.png", p)
    plt.close(fig)
    return FIGURE


@dataclass
class Page:
    """The study's records, read once, and what the page's sections take from them: the runs by
    (shape, seed), the plan (shapes, seeds) or None, the shapes present in ORDER, the planned runs
    still pending, the spheres' W (every comparison's reference), the --bench table, and the
    pressure study's bullet and paired effects (pressure_bullet: the first statement and the
    decision rules read them)."""
    docs: str
    study: str
    runs: dict
    plan: tuple | None
    shapes: list
    pending: list
    ref: list
    bench: str | None
    pressure: str | None
    pressure_line: str | None
    peffs: dict
    added: list


def pressure_bullet(pressure):
    """The pressure's effect on W from the paper's underpressure study in PRESSURE (pressure_effect),
    paired by seed between its lowest and highest dp: (the page's bullet, or None with fewer than two
    pressures; peffs, {"planned" / "all": (mean of ln W(hi) / W(lo), its standard error, dof, n)}
    where n >= 2; the study's seeds beyond its planned ones)."""
    line = None
    pe, pinfo = pressure_effect(pressure) if pressure else ({}, {})
    peffs = {}  # "planned" / "all": the pressure's effect, paired ln W(hi) / W(lo): (mean, se, dof, n, seeds)
    added = []  # the pressure study's seeds beyond its planned ones
    if len(pe) >= 2:
        lo, hi = min(pe), max(pe)
        seeds = sorted(set(pe[lo]) & set(pe[hi]))
        planned_p = [k for k in seeds if k <= PRESSURE_PLANNED]
        added = [k for k in seeds if k > PRESSURE_PLANNED]
        texts = {}
        for key, ss in (("planned", planned_p), ("all", seeds)):
            n, m, sd, h = interval([math.log(pe[hi][k] / pe[lo][k]) for k in ss])
            _, mr, _, hr = interval([pe[hi][k] / pe[lo][k] for k in ss])
            texts[key] = (ratio_text(mr, hr, n), n)
            if n >= 2:
                peffs[key] = (m, sd / math.sqrt(n), n - 1, n)
        uns = [c for c in pinfo["unsettled"] if any(f"process.underpressure={int(d)}_" in c for d in (lo, hi))]
        n_all = texts["all"][1]
        over = (f"{texts['planned'][0]} times W at {lo / 1e6:g} MPa over its {texts['planned'][1]} planned seeds "
                f"({texts['all'][0]} over all {n_all} seeds; seeds {', '.join(str(k) for k in added)} were added to "
                "that study after a look at other claims, docs/paper_comparison.md) (the ratio per seed, paired; "
                if added and planned_p else
                f"{texts['all'][0]} times W at {lo / 1e6:g} MPa (the ratio per seed, paired, {n_all} seeds; ")
        line = (f"- Confining pressure: W at {hi / 1e6:g} MPa is {over}25.5 mm, {pinfo['velocity']:g} m/s, "
                 f"{'/'.join(str(c) for c in sorted(pinfo['cycles']))} cycles: the paper's underpressure study, "
                 f"{pressure}; stationary by {pinfo['criterion']}"
                 + (f"; {len(uns)} of these {2 * n_all} runs not stationary: their last two cycles" if uns else "")
                 + "). Its velocity is half the shape runs', within 1% in W (docs/paper_comparison.md, C22).")
    return line, peffs, added


def read_page(data, docs, study, pressure, bench):
    """DATA's runs, the plan of STUDY and the pressure study's effect as a Page."""
    runs = load(data)
    plan = planned(study)
    pending = []
    if plan:
        pending = [(sh, k) for sh in plan[0] for k in range(1, plan[1] + 1) if (sh, k) not in runs]
    line, peffs, added = pressure_bullet(pressure)
    return Page(docs=docs, study=study, runs=runs, plan=plan,
                shapes=[s for s in ORDER if any(k[0] == s for k in runs)], pending=pending,
                ref=[r["W"] for (s, _), r in runs.items() if s == "sphere"], bench=bench, pressure=pressure,
                pressure_line=line, peffs=peffs, added=added)


# The page's sections, in its order: each takes the Page and returns its lines.

def section_shapes(c):
    """The title, the setup, the shapes table against the spheres and the figure (drawn here)."""
    runs, plan, shapes, pending, study, ref = c.runs, c.plan, c.shapes, c.pending, c.study, c.ref
    fig = figure(runs, shapes, c.docs, f" - provisional: {len(runs)} of {len(plan[0]) * plan[1]} runs" if pending else "")
    any_run = next(iter(runs.values()))
    L = []
    L.append("# Grain shape under vacuum")
    L.append("")
    L.append(f"<!-- Generated by `{COMMAND}`; do not edit. -->")
    L.append("")
    L.append(f"The damper (radius {1e3 * any_run['radius']:g} mm, the other keys the calibrated defaults) at "
             f"{any_run['dp'] / 1e6:g} MPa, "
             f"{any_run['velocity']:g} m/s, filled with grains of one volume (the sphere of radius grains.radius) "
             "in different shapes by the same packing procedure (docs/damper.md, \"Grain shapes\"; the clumps: "
             "docs/scene.md#clumps). Each shape prepares its own samples, so shapes are compared unpaired.")
    L.append("")
    if pending:
        total = len(plan[0]) * plan[1]
        L.append(f"**Provisional: {total - len(pending)} of the study's {total} runs have finished** "
                 f"({os.path.relpath(study, os.getcwd())}); pending: "
                 + ", ".join(f"{sh} seed {k}" for sh, k in pending)
                 + ". The numbers below change as they finish; a shape with one run has no interval yet.")
        L.append("")
    L.append("| shape | runs | grains | packing at cycling | W [J/m^2] | W - spheres' [%] | peak force [N] | friction share [%] | damping share [%] |")
    L.append("|---|---|---|---|---|---|---|---|---|")
    for sh in shapes:
        rs = [r for (s, _), r in sorted(runs.items()) if s == sh]
        vals = [r["W"] for r in rs]
        if sh == "sphere" or not ref:
            rel = "-"
        else:
            R, h, _, nb = ratio(ref, vals)
            rel = f"{100 * (R - 1):+.0f} +- {100 * h:.0f}" if math.isfinite(h) else f"{100 * (R - 1):+.0f} (n = {nb})"
        flag = "" if all(r["stationary"] for r in rs) else " (not all stationary)"
        count = f"{len(rs)} of {plan[1]}" if plan and sh in plan[0] else f"{len(rs)}"
        L.append(f"| {sh} | {count} | {ci([r['grains'] for r in rs])} | {ci([r['packing'] for r in rs], 3)} | "
                 f"{ci(vals)}{flag} | {rel} | {ci([r['peak'] for r in rs])} | {ci([r['friction'] for r in rs], 1, 100)} | "
                 f"{ci([r['damping'] for r in rs], 1, 100)} |")
    for sh in ([x for x in plan[0] if x not in shapes] if plan else []):
        L.append(f"| {sh} | 0 of {plan[1]} | pending | | | | | | |")
    L.append("")
    L.append("Mean +- half width of the 95% interval over the seeds (Student's t); against the spheres the "
             "ratio of the means less 1, in %, with its 95% interval (the scatter of both shapes: the delta method "
             "on ln R with Welch's degrees of freedom). (not all stationary): W of a run whose loops did not settle "
             "is the mean of its last two cycles.")
    L.append("")
    L.append(f"![W, peak force, friction share and packing by shape]({fig})")
    L.append("")
    return L


def section_runs(c):
    """The runs table: one row per run, in ORDER and by seed."""
    L = []
    L.append("## The runs")
    L.append("")
    L.append("| case | W [J/m^2] | cycles used | peak [N] | friction [%] | packing | dt [s] |")
    L.append("|---|---|---|---|---|---|---|")
    for (sh, seed), r in sorted(c.runs.items(), key=lambda kv: (ORDER.index(kv[0][0]) if kv[0][0] in ORDER else 99, kv[0][1])):
        used = f"{r['cycles'][0]}-{r['cycles'][-1]} of {r['n_cycles']}" + ("" if r["stationary"] else " (last two: not stationary)")
        L.append(f"| {r['name']} | {r['W']:.0f} | {used} | {r['peak']:.0f} | {100 * r['friction']:.1f} | "
                 f"{r['packing']:.3f} | {r['dt']:.3g} |")
    L.append("")
    return L


def shape_bullets(c):
    """Each shape's W and peak force against the spheres': (the bullets; compared, {"planned" / "all":
    [(shape, |ln| of the pressure's effect less the shape's as a rules difference, or None)]}; peaks,
    [(shape, the peak force's ratio to the spheres' as a rules difference)])."""
    runs, shapes, ref, peffs = c.runs, c.shapes, c.ref, c.peffs
    L = []
    compared = {"planned": [], "all": []}  # (shape, the rules' difference of |ln| or None)
    peaks = []  # (shape, the peak force's ratio to the spheres' as a rules difference)
    if ref:
        for sh in [x for x in shapes if x != "sphere"]:
            rs = [r for (s_, _), r in runs.items() if s_ == sh]
            vals = [r["W"] for r in rs]
            R, h, _, nb = ratio(ref, vals)
            pk_ref = [r["peak"] for (s_, _), r in runs.items() if s_ == "sphere"]
            P, ph, _, _ = ratio(pk_ref, [r["peak"] for r in rs])
            uns = [r for r in rs if not r["stationary"]]
            falling = [r for r in uns if r["W_last"] < r["W_prev"]]
            flag = ""
            if uns:
                flag = (f"; {len(uns)} of its {len(rs)} runs not stationary (W of their last two cycles"
                        + (f", {len(falling)} still falling: an upper bound of their stationary W" if falling else "")
                        + ")")
            pk = rules.ratio_diff(pk_ref, [r["peak"] for r in rs])
            pk_res = {None: "", "resolved": " (resolved)", "unresolved": " (not resolved from 1)"}[rules.resolved(pk)]
            peaks.append((sh, pk))
            L.append(f"- {sh}: W {ratio_text(R, h, nb)} times the spheres'{flag}; peak force over the stroke "
                     f"{ratio_text(P, ph, nb)} times{pk_res}.")
            e = log_ratio(ref, vals)
            for key in compared:
                compared[key].append((sh, effect_difference(peffs[key], e) if key in peffs and e else None))
    return L, compared, peaks


def statements(c, compared, peaks):
    """Athanassiadis et al.'s two statements against the runs (nothing without the pressure's effect
    over the planned seeds)."""
    pending, added, peffs = c.pending, c.added, c.peffs
    L = []
    if compared["planned"] and "planned" in peffs:
        verdict, parts = first_statement(compared["planned"])
        text = (f"- Their first statement (pressure has the largest effect), on W: "
                f"{'provisionally ' if pending and not verdict.startswith('open') else ''}**{verdict}** "
                f"(per shape, |ln| of the pressure's effect less the shape's, Welch 95%, the direction rule: "
                f"{'; '.join(parts)})")
        if added and "all" in peffs:
            v_all, p_all = first_statement(compared["all"])
            text += (f" [seeds {', '.join(str(k) for k in added)} of the pressure study added after a look, all "
                     f"{peffs['all'][3]} seeds: {v_all}: {'; '.join(p_all)}]")
        L.append(text + ". Reproduced needs the pressure's effect resolved larger for every shape; one shape's "
                 "resolved larger than the pressure's would not reproduce it.")
        outs = {sh: rules.resolved(d) for sh, d in peaks}
        # resolved: the ratio's 95% interval excludes 1 (rules.resolved on rules.ratio_diff)
        moved = [sh for sh, d in peaks if outs[sh] == "resolved"]
        still = [sh for sh, d in peaks if outs[sh] == "unresolved"]
        L.append("- Their second (shape tunes stiffness and yielding), in the damper's terms: **"
                 + rules.label("nothing measured") + "**: its separate modulus and yield stress are not measured "
                 "here; the peak force over the 10 mm stroke, which mixes the two, "
                 + (f"changes with the shape for {', '.join(moved)} (resolved)" if moved
                    else "changes with no shape (resolved)")
                 + (f", not resolved for {', '.join(still)}" if still else "") + ".")
    return L


def section_beside(c):
    """Beside the experiment of Athanassiadis et al.: the pressure's effect, each shape's, and their two
    statements."""
    L = []
    L.append("## Beside the experiment of Athanassiadis et al.")
    L.append("")
    L.append("Athanassiadis et al. (Soft Matter 10, 48, 2014) jammed 3D-printed grains of many shapes by vacuum "
             "at four confining pressures and measured the effective modulus, the yield stress and the energy "
             "lost per loading cycle. Only their abstract could be read for this page: \"confining pressure has "
             "the largest overall effect\" on the mechanical response, while shape \"controls the details\" and "
             "can tune stiffness and yielding. vppdem's runs against those two statements, effects as ratios of "
             "means with 95% intervals:")
    L.append("")
    if c.pressure_line is not None:
        L.append(c.pressure_line)
    bullets, compared, peaks = shape_bullets(c)
    L += bullets
    L += statements(c, compared, peaks)
    L.append("")
    return L


def section_rules(c):
    """The decision rules (page_rules)."""
    return page_rules(c.study, c.plan, c.added)


def section_cost(c):
    """Cost per step: the --bench table as it is (nothing without one)."""
    L = []
    if c.bench:
        L.append("")
        L.append("## Cost per step")
        L.append("")
        L.append(c.bench)
    return L


SECTIONS = (section_shapes, section_runs, section_beside, section_rules, section_cost)


def parse_args(argv):
    """(DATA, DOCS, the --bench table's text or None, the --pressure DIR or None, the study FILE);
    fails with the usage on anything else."""
    argv = ["grain_shapes"] + list(argv)
    args = [a for a in argv[1:] if not a.startswith("--")]
    bench = pressure = None
    if "--bench" in argv:
        i = argv.index("--bench")
        if i + 1 >= len(argv):
            fail("--bench needs a FILE", 2)
        bench = open(argv[i + 1]).read().strip()
        args = [a for a in args if a != argv[i + 1]]
    if "--pressure" in argv:
        i = argv.index("--pressure")
        if i + 1 >= len(argv):
            fail("--pressure needs a DIR", 2)
        pressure = argv[i + 1]
        args = [a for a in args if a != pressure]
    study = os.path.join(source_dir(), "studies", "grains", "shapes.toml")
    if "--study" in argv:
        i = argv.index("--study")
        if i + 1 >= len(argv) or not os.path.isfile(argv[i + 1]):
            fail(f"--study needs a study FILE (got {argv[i + 1] if i + 1 < len(argv) else 'nothing'})", 2)
        study = argv[i + 1]
        args = [a for a in args if a != study]
    if len(args) != 2:
        fail(__doc__.strip().splitlines()[2], 2)
    data, docs = args
    return data, docs, bench, pressure, study


def main(argv=None):
    data, docs, bench, pressure, study = parse_args(sys.argv[1:] if argv is None else argv)
    c = read_page(data, docs, study, pressure, bench)
    L = []
    for section in SECTIONS:
        L += section(c)
    path = os.path.join(docs, "grains.md")
    with open(path + ".part", "w") as f:
        f.write("\n".join(L) + "\n")
    os.replace(path + ".part", path)
    print(f"vppdem.report grain_shapes: {len(c.runs)} runs of {len(c.shapes)} shapes -> {path}, {FIGURE}")


if __name__ == "__main__":
    main(sys.argv[1:])
