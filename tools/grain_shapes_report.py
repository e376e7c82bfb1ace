#!/usr/bin/env python3
"""docs/grains.md and its figure from the grain-shape study's records (issue 24, item 4).

usage: grain_shapes_report.py DATA DOCS [--bench FILE] [--pressure DIR] [--study FILE]
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
spheres the difference of the means with Welch's 95% interval (the shapes prepare their own
samples: unpaired). Runs under /usr/bin/python3.
"""
import json
import math
import os
import sys
import tomllib

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from paired_velocity import interval, t_quantile  # noqa: E402  (one Student t for the tools)

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "src", "python"))
from vppdem.records import fail  # noqa: E402

COMMAND = ("bash scripts/grain_shapes.sh, then /usr/bin/python3 tools/grain_shapes_report.py docs/data/grains/shapes docs "
           "--pressure docs/data/paper/radius_underpressure --bench docs/data/grains/cost_per_step.md")
ORDER = ["sphere", "dimer", "trimer", "tetrahedron", "pellet", "template"]


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
            name=name, W=W, stationary=stationary, cycles=[c["cycle"] for c in used], n_cycles=len(cyc),
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
    """{dp [Pa]: {seed: W}} of the 25.5 mm rows of the paper's underpressure study (W as load())."""
    out = {}
    if not os.path.isdir(root):
        return out
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
        if s.get("W_settled") is not None:
            W = s["W_settled"]
        else:
            W = sum(c["W"] for c in cyc[-2:]) / len(cyc[-2:])
        out.setdefault(dp, {})[seed] = W
    return out


def welch(a, b):
    """(difference of the means b - a, half width of Welch's 95% interval)."""
    na, ma, sa, _ = interval(a)
    nb, mb, sb, _ = interval(b)
    if na < 2 or nb < 2:
        return mb - ma, math.nan
    va, vb = sa * sa / na, sb * sb / nb
    if va + vb == 0:
        return mb - ma, 0.0
    dof = (va + vb) ** 2 / (va * va / (na - 1) + vb * vb / (nb - 1))
    return mb - ma, t_quantile(0.975, dof) * math.sqrt(va + vb)


def ci(vals, digits=0, scale=1.0):
    n, m, sd, h = interval([v * scale for v in vals])
    if n == 0:
        return "-"
    if n < 2 or not math.isfinite(h):
        return f"{m:.{digits}f} (n = {n})"
    return f"{m:.{digits}f} +- {h:.{digits}f}"


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
    p = os.path.join(docs, "grains_shapes.png")
    fig.savefig(p + ".part.png", dpi=110)
    os.replace(p + ".part.png", p)
    plt.close(fig)
    return "grains_shapes.png"


def main(argv):
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
    study = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "studies", "grains", "shapes.toml")
    if "--study" in argv:
        i = argv.index("--study")
        if i + 1 >= len(argv) or not os.path.isfile(argv[i + 1]):
            fail(f"--study needs a study FILE (got {argv[i + 1] if i + 1 < len(argv) else 'nothing'})", 2)
        study = argv[i + 1]
        args = [a for a in args if a != study]
    if len(args) != 2:
        fail(__doc__.strip().splitlines()[2], 2)
    data, docs = args
    runs = load(data)
    plan = planned(study)
    shapes = [s for s in ORDER if any(k[0] == s for k in runs)]
    pending = []
    if plan:
        pending = [(sh, k) for sh in plan[0] for k in range(1, plan[1] + 1) if (sh, k) not in runs]
    fig = figure(runs, shapes, docs, f" - provisional: {len(runs)} of {len(plan[0]) * plan[1]} runs" if pending else "")
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
    ref = [r["W"] for (s, _), r in runs.items() if s == "sphere"]
    _, m_ref, _, _ = interval(ref)
    for sh in shapes:
        rs = [r for (s, _), r in sorted(runs.items()) if s == sh]
        vals = [r["W"] for r in rs]
        if sh == "sphere" or not ref:
            rel = "-"
        else:
            d, h = welch(ref, vals)
            rel = f"{100 * d / m_ref:+.0f} +- {100 * h / m_ref:.0f}" if math.isfinite(h) else f"{100 * d / m_ref:+.0f}"
        flag = "" if all(r["stationary"] for r in rs) else " (not all stationary)"
        count = f"{len(rs)} of {plan[1]}" if plan and sh in plan[0] else f"{len(rs)}"
        L.append(f"| {sh} | {count} | {ci([r['grains'] for r in rs])} | {ci([r['packing'] for r in rs], 3)} | "
                 f"{ci(vals)}{flag} | {rel} | {ci([r['peak'] for r in rs])} | {ci([r['friction'] for r in rs], 1, 100)} | "
                 f"{ci([r['damping'] for r in rs], 1, 100)} |")
    for sh in ([x for x in plan[0] if x not in shapes] if plan else []):
        L.append(f"| {sh} | 0 of {plan[1]} | pending | | | | | | |")
    L.append("")
    L.append("Mean +- half width of the 95% interval over the seeds (Student's t); against the spheres the "
             "difference of the means with Welch's 95% interval, in % of the spheres' mean.")
    L.append("")
    L.append(f"![W, peak force, friction share and packing by shape]({fig})")
    L.append("")
    L.append("## The runs")
    L.append("")
    L.append("| case | W [J/m^2] | cycles used | peak [N] | friction [%] | packing | dt [s] |")
    L.append("|---|---|---|---|---|---|---|")
    for (sh, seed), r in sorted(runs.items(), key=lambda kv: (ORDER.index(kv[0][0]) if kv[0][0] in ORDER else 99, kv[0][1])):
        used = f"{r['cycles'][0]}-{r['cycles'][-1]} of {r['n_cycles']}" + ("" if r["stationary"] else " (last two: not stationary)")
        L.append(f"| {r['name']} | {r['W']:.0f} | {used} | {r['peak']:.0f} | {100 * r['friction']:.1f} | "
                 f"{r['packing']:.3f} | {r['dt']:.3g} |")
    L.append("")
    L.append("## Beside the experiment of Athanassiadis et al.")
    L.append("")
    L.append("Athanassiadis et al. (Soft Matter 10, 48, 2014) jammed 3D-printed grains of many shapes in a "
             "membrane by vacuum at four confining pressures and measured the effective modulus, the yield "
             "stress and the energy lost per loading cycle. Only their abstract could be read for this page: "
             "\"confining pressure has the largest overall effect\" on the mechanical response, while shape "
             "\"controls the details\" and can tune stiffness and yielding. vppdem's runs against those two "
             "statements:")
    L.append("")
    pe = pressure_effect(pressure) if pressure else {}
    if ref:
        for sh in [x for x in shapes if x != "sphere"]:
            vals = [r["W"] for (s, _), r in runs.items() if s == sh]
            _, m, _, _ = interval(vals)
            pk = [r["peak"] for (s, _), r in runs.items() if s == sh]
            pk_ref = [r["peak"] for (s, _), r in runs.items() if s == "sphere"]
            L.append(f"- {sh}: W {m / m_ref:.2f} times the spheres', peak force {interval(pk)[1] / interval(pk_ref)[1]:.2f} "
                     "times (the loop's stiffness and the load it yields at).")
    if len(pe) >= 2:
        lo, hi = min(pe), max(pe)
        seeds = sorted(set(pe[lo]) & set(pe[hi]))
        ratios = [pe[hi][k] / pe[lo][k] for k in seeds]
        n, m, sd, h = interval(ratios)
        L.append(f"- the confining pressure: W at {hi / 1e6:g} MPa is {m:.2f}"
                 + (f" +- {h:.2f}" if math.isfinite(h) else "")
                 + f" times W at {lo / 1e6:g} MPa (paired by seed, {n} seeds; {pressure}).")
        shape_max = max((interval([r["W"] for (s, _), r in runs.items() if s == sh])[1] / m_ref
                         for sh in shapes if sh != "sphere"), default=math.nan)
        if math.isfinite(shape_max):
            verdict = ("reproduced: the pressure changes W more than the shape does" if m > shape_max
                       else f"not reproduced: in the model the shape changes W more than a {hi / lo:.0f}-fold pressure does")
            L.append(f"- their first statement, {'provisionally ' if pending else ''}{verdict} ({m:.2f} against {shape_max:.2f}).")
    L.append("")
    if bench:
        L.append("")
        L.append("## Cost per step")
        L.append("")
        L.append(bench)
    path = os.path.join(docs, "grains.md")
    with open(path + ".part", "w") as f:
        f.write("\n".join(L) + "\n")
    os.replace(path + ".part", path)
    print(f"grain_shapes_report.py: {len(runs)} runs of {len(shapes)} shapes -> {path}, {fig}")


if __name__ == "__main__":
    main(sys.argv)
