"""A cylinder given as a mesh (issue 47; docs/membrane.md): the damper's W with the lattice foil
and with the mesh foil (foil.builder = "mesh"), from the runs of studies/membrane/cylinder.toml.

usage: python3 -m vppdem.report membrane_cylinder DATA [--page FILE]

DATA holds one folder per run (summary.json, cycles.csv; scripts/membrane_cylinder_study.sh
publishes them into docs/data/membrane_cylinder). Every seed of every foil is its own prepared
sample, so the foils are compared as independent samples: mean(mesh) - mean(lattice) with Welch's
t and the Welch-Satterthwaite degrees of freedom (vppdem.report.stats welch(), the reports' one
Student t), its 95% interval, and |difference| against the seeds' standard deviation (each foil's
and the pooled one). The quantity fixed before the runs: W averaged over cycles 3-5 of each run
(cycles 1-2 compact the packing; on this damper W is stationary from cycle 2, the 4-cycle trial run
of the mesh foil said); cycle 5 alone each cycle alone and summary.json's W_settled beside it. The
verdict on issue 47's claim ("a cylinder given as a mesh gives the built-in one's W within the seed
scatter", a claim of no effect) is vppdem.report.rules' equivalence rule: the whole 95% interval
of the difference within +-10% of the lattice's mean W reproduces it; 0 inside an interval that
reaches past the margin leaves it consistent, not established. Prints Markdown (report.md, with its
"Decision rules"); --page FILE also writes the comparison and the verdict into FILE (docs/membrane.md)
between <!-- membrane_cylinder begin --> and <!-- membrane_cylinder end -->.
"""
import glob
import json
import math
import os
import sys

from . import rules
from .stats import interval, welch

PRIMARY = (3, 5)  # cycles averaged per run (inclusive)


def read_cycles(path):
    with open(path) as f:
        head = f.readline().strip().split(",")
        rows = [dict(zip(head, line.strip().split(","))) for line in f if line.strip()]
    return {int(r["cycle"]): float(r["W"]) for r in rows}


def load(data):
    runs = {"lattice": {}, "mesh": {}}
    for d in sorted(glob.glob(os.path.join(data, "*", "summary.json"))):
        folder = os.path.dirname(d)
        with open(d) as f:
            s = json.load(f)
        inputs = s.get("inputs", {})
        builder = "mesh" if inputs.get("foil.builder", 0) == 1 or s.get("foil_builder") == "mesh" else "lattice"
        seed = int(inputs["simulation.seed"])
        w = read_cycles(os.path.join(folder, "cycles.csv"))
        runs[builder][seed] = {"W": w, "summary": s, "name": os.path.basename(folder)}
    return runs


def per_run(run, what):
    w = run["W"]
    if what == "primary":
        cyc = range(PRIMARY[0], PRIMARY[1] + 1)
        return sum(w[c] for c in cyc) / len(cyc) if all(c in w for c in cyc) else None
    if isinstance(what, int):
        return w.get(what)
    if what == "settled":
        v = run["summary"].get("W_settled")
        return v if isinstance(v, (int, float)) and math.isfinite(v) and v > 0 else None
    return None


def ratio(x, y):
    return f"{x / y:.2f}" if y > 0 else "n/a"


def planned(data):
    """The seeds studies/membrane/cylinder.toml fixed before the runs (rules.planned_seeds)."""
    from . import source_dir
    for root in (os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(data)))), source_dir()):
        n = rules.planned_seeds(os.path.join(root, "studies", "membrane", "cylinder.toml"))
        if n is not None:
            return n
    return "?"


def verdict_text(d, ma, mb, pooled):
    """The verdict paragraph on W of cycles 3-5 (the quantity fixed before the runs): the claim of no
    effect by the equivalence rule (rules.band, verdict_equivalence, statement_equivalence)."""
    v = rules.verdict_equivalence([rules.band(d)])
    return (f"W (cycles {PRIMARY[0]}-{PRIMARY[1]}): mesh {mb:.1f} against lattice {ma:.1f} J/m^2, "
            f"difference {d.d:+.1f} J/m^2 ({100 * d.d / ma:+.1f}%), 95% interval "
            f"[{d.d - d.h:+.1f}, {d.d + d.h:+.1f}] J/m^2; |difference| is {ratio(abs(d.d), pooled)} of the "
            f"seeds' pooled SD ({pooled:.1f} J/m^2). By the equivalence rule (+-{100 * rules.MARGIN:.0f}% of the "
            f"lattice's mean): {rules.statement_equivalence(d)}. Issue 47's claim, the mesh foil's W within the seed "
            f"scatter of the lattice's, is therefore **{v}**"
            + {"reproduced": ": the whole interval lies within the margin.",
               "consistent, not established": (": 0 lies inside the interval (no difference resolved), but the "
                                               "interval reaches past the margin, so a difference of that size is "
                                               "not excluded." if not d.resolved else
                                               ": a difference is resolved, within reach of the margin."),
               "not reproduced": ": the interval lies wholly beyond the margin."}.get(v, "."))


def page_rules(data):
    return rules.section(rules.PageRules(
        module="vppdem.report.membrane_cylinder",
        tests=[("welch", "mesh foil against lattice foil: every seed of every foil prepares its own sample"),
               ("equivalence", "issue 47's claim that the mesh foil gives the lattice's W within the seed scatter, "
                               "on W of cycles 3-5; the reference: the lattice's mean")],
        which_w=f"W averaged over cycles {PRIMARY[0]}-{PRIMARY[1]} of each run (cycles.csv), fixed before the runs; "
                "each cycle alone and summary.json's W_settled beside it, not in the verdict.",
        planned=f"{planned(data)} per foil (`seeds` of studies/membrane/cylinder.toml), fixed before the runs.",
        labels=[],
        fixed_before=["the quantity (W over cycles 3-5), the test (Welch's t, 95%) and the seeds, before the runs; "
                      "then 'within the seed scatter' read as '0 inside the 95% interval', which says only that no "
                      "difference was resolved"],
        fixed_after=["the equivalence margin (+-10% of the lattice's mean) and the verdict by it: written after the "
                     "data were seen (issue 60's rules module); the page said 'within the seed scatter' before"]))


def replace_block(page, text):
    """The lines between <!-- membrane_cylinder begin --> and <!-- membrane_cylinder end --> of page."""
    with open(page) as f:
        doc = f.read()
    b, e = "<!-- membrane_cylinder begin -->", "<!-- membrane_cylinder end -->"
    if b not in doc or e not in doc:
        raise SystemExit(f"vppdem.report membrane_cylinder: {page} has no {b} ... {e} block")
    doc = doc[: doc.index(b)] + f"{b}\n{text.rstrip()}\n{e}" + doc[doc.index(e) + len(e):]
    with open(page + ".part", "w") as f:
        f.write(doc)
    os.replace(page + ".part", page)


def main(argv=None):
    args = sys.argv[1:] if argv is None else list(argv)
    page = None
    if "--page" in args:
        i = args.index("--page")
        if i + 1 >= len(args):
            sys.stderr.write(__doc__)
            return 2
        page = args[i + 1]
        args = args[:i] + args[i + 2:]
    if len(args) != 1:
        sys.stderr.write(__doc__)
        return 2
    data = args[0]
    runs = load(data)
    out = []
    n = {b: len(runs[b]) for b in runs}
    out.append("# A cylinder given as a mesh: W of the lattice foil against the mesh foil\n")
    out.append(f"Runs: {n['lattice']} lattice, {n['mesh']} mesh (`{data}`; "
               "studies/membrane/cylinder.toml, scripts/membrane_cylinder_study.sh).\n")
    if runs["lattice"] and runs["mesh"]:
        any_run = next(iter(runs["lattice"].values()))["summary"]
        mesh_run = next(iter(runs["mesh"].values()))["summary"]
        out.append(f"Damper: radius {any_run['foil_radius'] * 1e3:.2f} mm (foil ring), height "
                   f"{any_run['height'] * 1e3:.2f} mm, grains {min(r['summary']['grains'] for b in runs for r in runs[b].values())}-"
                   f"{max(r['summary']['grains'] for b in runs for r in runs[b].values())}; foil particles: lattice "
                   f"{any_run['foil_particles']:.0f}, mesh {min(r['summary']['foil_particles'] for r in runs['mesh'].values()):.0f}-"
                   f"{max(r['summary']['foil_particles'] for r in runs['mesh'].values()):.0f} "
                   f"({mesh_run.get('foil_vacancies', 0):.0f} vacancies in seed "
                   f"{next(iter(runs['mesh']))}).\n")
    # Per run.
    seeds = sorted(set(runs["lattice"]) | set(runs["mesh"]))
    cycles = sorted({c for b in runs for r in runs[b].values() for c in r["W"]})
    out.append("## W per run [J/m^2]\n")
    out.append("| foil | seed | " + " | ".join(f"cycle {c}" for c in cycles) +
               f" | cycles {PRIMARY[0]}-{PRIMARY[1]} | W_settled |")
    out.append("|---|---|" + "---|" * (len(cycles) + 2))
    for b in ("lattice", "mesh"):
        for s in seeds:
            if s not in runs[b]:
                continue
            r = runs[b][s]
            cells = [f"{r['W'][c]:.1f}" if c in r["W"] else "" for c in cycles]
            p, st = per_run(r, "primary"), per_run(r, "settled")
            out.append(f"| {b} | {s} | " + " | ".join(cells) + " | " + (f"{p:.1f}" if p is not None else "") + " | " +
                       (f"{st:.1f}" if st is not None else "not stationary") + " |")
    out.append("")
    out.append("## Comparison (mesh - lattice; independent samples, Welch's t, 95%)\n")
    out.append("| quantity | lattice mean +- SD (n) | mesh mean +- SD (n) | difference [95% interval] | "
               f"difference / mean lattice | dof | abs(difference) / SD lattice, mesh, pooled | "
               f"by the rules (+-{100 * rules.MARGIN:.0f}% of the lattice's mean) |")
    out.append("|---|---|---|---|---|---|---|---|")
    brief = ["| W [J/m^2] | lattice, mean +- SD (5 seeds) | mesh, mean +- SD (5 seeds) | mesh - lattice [95% interval] | "
             "relative | abs(difference) / SD (lattice, mesh, pooled) |", "|---|---|---|---|---|---|"]
    verdict = None
    rows = [("primary", f"W, cycles {PRIMARY[0]}-{PRIMARY[1]}")] + [(c, f"W, cycle {c}") for c in cycles] + \
        [("settled", "W_settled (runs stationary by summary.json)")]
    for what, label in rows:
        a = [per_run(r, what) for r in runs["lattice"].values()]
        b = [per_run(r, what) for r in runs["mesh"].values()]
        a = [x for x in a if x is not None]
        b = [x for x in b if x is not None]
        na, ma, sa, _ = interval(a)
        nb, mb, sb, _ = interval(b)
        d = welch(a, b)
        if not d.ok:
            out.append(f"| {label} | {ma:.1f} ({na}) | {mb:.1f} ({nb}) | too few runs | | | | |")
            continue
        pooled = math.sqrt(((na - 1) * sa * sa + (nb - 1) * sb * sb) / (na + nb - 2))
        if what == "primary":
            verdict = (d, pooled, ma, mb)
        rel = (f"{100 * d.d / ma:+.1f}% [{100 * (d.d - d.h) / ma:+.1f}%, {100 * (d.d + d.h) / ma:+.1f}%]")
        sds = f"{ratio(abs(d.d), sa)}, {ratio(abs(d.d), sb)}, {ratio(abs(d.d), pooled)}"
        out.append(f"| {label} | {ma:.1f} +- {sa:.1f} ({na}) | {mb:.1f} +- {sb:.1f} ({nb}) | "
                   f"{d.d:+.1f} [{d.d - d.h:+.1f}, {d.d + d.h:+.1f}] | {rel} | {d.dof:.1f} | {sds} | "
                   f"{rules.statement_equivalence(d)} |")
        if isinstance(what, int) or what == "primary":
            name = f"cycles {PRIMARY[0]}-{PRIMARY[1]}" if what == "primary" else f"cycle {what}"
            brief.append(f"| {name} | {ma:.1f} +- {sa:.1f} | {mb:.1f} +- {sb:.1f} | {d.d:+.1f} [{d.d - d.h:+.1f}, "
                         f"{d.d + d.h:+.1f}] | {rel.replace(' [', ' [').replace('%]', '%]')} | {sds} |")
    out.append("")
    if verdict:
        d, pooled, ma, mb = verdict
        out.append("## Verdict\n")
        out.append(verdict_text(d, ma, mb, pooled))
        out.append("")
        if page:
            rel = (f"`python3 -m vppdem.report membrane_cylinder {data} --page {page}` (do not edit by hand; "
                   f"per run and the rules: `{data}/report.md`).")
            replace_block(page, "\n".join([f"Made by {rel}", ""] + brief + ["", "**Verdict.** " + verdict_text(d, ma, mb, pooled)]))
    out += page_rules(data)
    print("\n".join(out).rstrip("\n"))
    return 0


if __name__ == "__main__":
    sys.exit(main())
