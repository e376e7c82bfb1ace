"""The device studies' report (issue 47, docs/devices.md).

Reads the published records docs/data/devices/<study>/<case>_s<seed>/ (summary.json, tools.csv.gz,
as `vppdem sweep studies/devices/<study>.toml --publish docs/data/devices/<study>` leaves
them), computes each case's mean and 95% Student-t interval over its seeds, draws
docs/devices_<study>_study.png and writes the table into docs/devices.md between the markers
<!-- device_report:<study> begin --> and <!-- ... end -->.

usage: python3 -m vppdem.report device gripper|gripper_pour|beam|trends|gripper_jamming
       python3 -m vppdem.report device FOLDER [--out DIR] [--test Welch|paired]

    python3 -m vppdem.report device gripper
    python3 -m vppdem.report device gripper_pour   # the pour against the gripper's dp50
    python3 -m vppdem.report device beam
    python3 -m vppdem.report device gripper_jamming  # the gripper 25 grains across (report/device_jamming.py)
    python3 -m vppdem.report device trends         # only the trends table and the rules section
    python3 -m vppdem.report device out/my_study   # any device study's folder (study_report)

A FOLDER (any device study's: the --out or the --publish folder of `vppdem sweep STUDY.toml`; a
path, so ./beam for a folder named like a shipped study) gets study_report(): from its summary.csv
(else from its run folders' summary.json at stage done, <case>_s<seed>/ or <case>/), per case the
finished runs, the mean and 95% Student-t half width of every number the runs have, the difference
of each case from the first (Welch by default; --test paired pairs the seeds), written to
DIR/device_report.md with its figure DIR/device_report.png (DIR: --out, default FOLDER); the page's
path printed. Exit 2 naming what is wrong for a folder without finished runs.

Every study's run also rewrites, from the records of all three studies, the table "Beside the
published trends" (between <!-- device_report:trends begin/end -->) and the page's "Decision
rules" (<!-- device_report:rules begin/end -->). Every statement of an effect and every verdict
there is vppdem.report.rules' (paired or Welch differences, the direction rule, the equivalence
rule, label() for what no run measures).
"""
import argparse
import csv
import gzip
import json
import math
import os
import re
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from . import rules, source_dir  # noqa: E402
from .stats import interval  # noqa: E402
from .. import plot as vplot  # noqa: E402
from .. import records  # noqa: E402

ROOT = source_dir()
OBJECT_TOP = 0.006  # [m] the gripper's object: a sphere of 6 mm radius centred at z = 0


def mean_ci(v):
    """(mean, 95% Student-t half width, n) of the finite values (vppdem.report.stats.interval)."""
    n, m, _, h = interval([x for x in v if x is not None])
    return m, h, n


def fmt(m, h, digits=3, scale=1.0):
    if not math.isfinite(m):
        return "-"
    if not math.isfinite(h):
        return f"{m * scale:.{digits}g}"
    return f"{m * scale:.{digits}g} ± {h * scale:.2g}"


def read_tools(path):
    """tools.csv of a run's folder (published: tools.csv.gz, the rows from the press on)."""
    if not os.path.exists(path) and os.path.exists(path + ".gz"):
        f = gzip.open(path + ".gz", "rt")
    else:
        f = open(path)
    with f:
        r = csv.DictReader(f)
        return [{k: float(v) for k, v in row.items()} for row in r]


def load(study):
    base = os.path.join(ROOT, "docs", "data", "devices", study)
    runs = {}
    if not os.path.isdir(base):
        return runs
    for d in sorted(os.listdir(base)):
        m = re.match(r"(.+)_s(\d+)$", d)
        p = os.path.join(base, d, "summary.json")
        if not m or not os.path.exists(p):
            continue
        with open(p) as f:
            s = json.load(f)
        if s.get("stage") != "done":
            continue
        s["_dir"] = os.path.join(base, d)
        s["_seed"] = int(m.group(2))
        runs.setdefault(m.group(1), []).append(s)
    return runs


def replace_block(study, text):
    page = os.path.join(ROOT, "docs", "devices.md")
    with open(page) as f:
        doc = f.read()
    b, e = f"<!-- device_report:{study} begin -->", f"<!-- device_report:{study} end -->"
    block = f"{b}\n{text.rstrip()}\n{e}"
    if b in doc and e in doc:
        doc = doc[: doc.index(b)] + block + doc[doc.index(e) + len(e):]
    else:
        doc = doc.rstrip() + "\n\n" + block + "\n"
    with open(page, "w") as f:
        f.write(doc)


GRIPPER_CASES = [
    # name, label, dp [kPa], press force [N], what
    ("dp0", "no vacuum", 0, 2.0, "underpressure"),
    ("dp25", "25 kPa", 25, 2.0, "underpressure"),
    ("dp50", "50 kPa", 50, 2.0, "underpressure, immersion, mechanisms"),
    ("press1_dp50", "press 1 N", 50, 1.0, "immersion"),
    ("press4_dp50", "press 4 N", 50, 4.0, "immersion"),
    ("mu_membrane0_dp50", "membrane friction 0", 50, 2.0, "mechanisms"),
    ("mu_grains0_dp50", "grain friction 0", 50, 2.0, "mechanisms"),
]


def gripper(runs):
    rows, stats = [], {}
    for name, label, dp, press, what in GRIPPER_CASES:
        rs = runs.get(name, [])
        hf = [r["holding_force"] for r in rs]
        wrap = [OBJECT_TOP - r["membrane_z_min"] for r in rs]
        travel = []
        for r in rs:
            t = read_tools(os.path.join(r["_dir"], "tools.csv"))
            pr = [row["holder_z"] for row in t if int(row["stage"]) == 2]
            travel.append(-pr[-1] if pr else float("nan"))
        dv = [r["volume_change_vacuum"] for r in rs]
        st = {"hf": mean_ci(hf), "wrap": mean_ci(wrap), "travel": mean_ci(travel), "dv": mean_ci(dv),
              "hf_all": hf, "wrap_all": wrap, "seeds": [r["_seed"] for r in rs], "dp": dp, "press": press}
        stats[name] = st
        rows.append(f"| `{name}` | {label} | {dp} | {press:g} | {st['hf'][2]} | **{fmt(*st['hf'][:2])}** | "
                    f"{fmt(*st['wrap'][:2], scale=1e3)} | {fmt(*st['travel'][:2], scale=1e3)} | "
                    f"{fmt(*st['dv'][:2], scale=100)} | {', '.join(f'{x:.3f}' for x in hf)} |")
    table = ["| case | | dp [kPa] | press [N] | n | holding force [N] | wrap depth [mm] | holder travel in the press [mm] | volume change in the vacuum [%] | per seed (seeds in order) [N] |",
             "|---|---|---|---|---|---|---|---|---|---|"] + rows
    n_done = sum(len(runs.get(c[0], [])) for c in GRIPPER_CASES)
    # Paired differences: a seed's cases share its fill (the jitter), so they differ by the case alone.
    pairs = [("dp25", "dp0"), ("dp50", "dp25"), ("dp50", "dp0"), ("press4_dp50", "dp50"), ("dp50", "press1_dp50"),
             ("dp50", "mu_membrane0_dp50"), ("dp50", "mu_grains0_dp50")]
    ptable = ["| difference (same seeds) | n | mean ± 95% [N] | seeds with a positive difference | resolved from 0 |",
              "|---|---|---|---|---|"]
    for a, b in pairs:
        da = dict(zip(stats[a]["seeds"], stats[a]["hf_all"]))
        db = dict(zip(stats[b]["seeds"], stats[b]["hf_all"]))
        d = [da[k] - db[k] for k in sorted(set(da) & set(db))]
        diff = rules.difference("paired", db, da)  # a - b, seed by seed
        m, h, n = (diff.d if diff.d is not None else math.nan), (diff.h if diff.ok else math.nan), diff.n
        res = "yes" if rules.resolved(diff) == "resolved" else "no"
        ptable.append(f"| `{a}` - `{b}` | {n} | {fmt(m, h)} | {sum(x > 0 for x in d)} of {n} | {res} |")

    fig, ax = plt.subplots(1, 3, figsize=(13, 4))
    for k, names, xkey, xlabel in ((0, ["dp0", "dp25", "dp50"], "dp", "underpressure dp [kPa]"),
                                   (1, ["press1_dp50", "dp50", "press4_dp50"], "wrap", "wrap depth at the end of the vacuum [mm]")):
        xs, ms, hs = [], [], []
        for nm in names:
            st = stats[nm]
            if not st["hf_all"]:
                continue
            x = st["dp"] if xkey == "dp" else st["wrap"][0] * 1e3
            xa = [st["dp"]] * len(st["hf_all"]) if xkey == "dp" else [w * 1e3 for w in st["wrap_all"]]
            ax[k].plot(xa, st["hf_all"], "o", color="0.6", ms=4)
            xs.append(x)
            ms.append(st["hf"][0])
            hs.append(st["hf"][1] if math.isfinite(st["hf"][1]) else 0)
        ax[k].errorbar(xs, ms, yerr=hs, fmt="s-", color="C0", capsize=4, label="mean, 95% interval")
        ax[k].set_xlabel(xlabel)
        ax[k].set_ylabel("holding force [N]")
        ax[k].grid(alpha=0.3)
    # Brown et al.: holding force roughly proportional to dp; anchored on the 50 kPa mean
    m50 = stats["dp50"]["hf"][0]
    if math.isfinite(m50):
        ax[0].plot([0, 50], [0, m50], "--", color="C3", label="∝ dp (Brown et al. 2010)")
    ax[0].legend(fontsize=8)
    ax[0].set_title("against underpressure (press 2 N)")
    ax[1].set_title("against immersion (dp 50 kPa; press 1, 2, 4 N)")
    labels, ms, hs = [], [], []
    for nm, lab in (("dp50", "default"), ("mu_membrane0_dp50", "membrane\nfriction 0"), ("mu_grains0_dp50", "grain\nfriction 0")):
        st = stats[nm]
        labels.append(lab)
        ms.append(st["hf"][0] if st["hf_all"] else 0)
        hs.append(st["hf"][1] if math.isfinite(st["hf"][1]) else 0)
        ax[2].plot([len(labels) - 1] * len(st["hf_all"]), st["hf_all"], "o", color="0.6", ms=4)
    ax[2].bar(range(len(labels)), ms, yerr=hs, capsize=4, color="C0", alpha=0.6)
    ax[2].set_xticks(range(len(labels)), labels)
    ax[2].set_ylabel("holding force [N]")
    ax[2].set_title("mechanisms (dp 50 kPa, press 2 N)")
    ax[2].grid(alpha=0.3, axis="y")
    fig.tight_layout()
    fig.savefig(os.path.join(ROOT, "docs", "devices_gripper_study.png"), dpi=110)

    text = "\n".join(
        [f"Made by `scripts/device_study.sh gripper` and `python3 -m vppdem.report device gripper` "
         f"from the records in `docs/data/devices/gripper/` ({n_done} of {5 * len(GRIPPER_CASES)} runs: "
         f"{len(GRIPPER_CASES)} cases x seeds 1-5). Mean ± the 95% Student-t half-width over the seeds; "
         f"wrap depth: how far the membrane's lowest particle centre reaches below the object's top at the "
         f"end of the vacuum (6 mm - `membrane_z_min`).", "", *table, "",
         "Paired by seed (Student t on the per-seed differences; resolved: 0 outside the 95% interval, "
         "vppdem.report.rules):", "", *ptable, "",
         "![The gripper study](devices_gripper_study.png)"])
    replace_block("gripper", text)
    return stats


def gripper_pour(runs):
    """The pour (docs/data/devices/gripper_pour/pour_dp50_s*) against the lattice fill (the gripper
    study's dp50_s*): the same device file, seeds and dp; the fills differ (a seed's jitter acts on
    another lattice), so the two are compared as independent samples (Welch), not paired."""
    lattice = load("gripper").get("dp50", [])
    pour = runs.get("pour_dp50", [])

    def packing_seal(r):  # the lattice's records predate summary.json's packing_seal
        return r["grain_volume"] / r["volume_seal"]

    def packing_vacuum(r):
        return r["grain_volume"] / r["volume_vacuum"]

    def fill_ke(r):  # [J] the grains' kinetic energy at the end of the fill (from the warning; nan: at rest)
        for w in r.get("warnings", []):
            m = re.search(r"kinetic energy ([0-9.eE+-]+) J", w)
            if w.startswith("fill:") and m:
                return float(m.group(1))
        return float("nan")

    metrics = [
        # key, label, function, scale
        ("hf", "holding force [N]", lambda r: r["holding_force"], 1.0),
        ("dv", "volume change in the vacuum [%]", lambda r: r["volume_change_vacuum"], 100.0),
        ("dvs", "volume change, seal to end of vacuum [%]", lambda r: r["volume_change"], 100.0),
        ("ps", "packing at the seal", packing_seal, 1.0),
        ("pv", "packing after the vacuum", packing_vacuum, 1.0),
        ("n", "grains in the bag", lambda r: r["grains"], 1.0),
        ("wrap", "wrap depth [mm]", lambda r: OBJECT_TOP - r["membrane_z_min"], 1e3),
        ("ke", "grains' kinetic energy at the fill's end [µJ]", fill_ke, 1e6),
    ]
    cases = [("dp50", "lattice, settled at friction 0.5 (the gripper study's `dp50`)", lattice),
             ("lattice_mu0_dp50", "lattice, settled frictionless (`lattice_mu0_dp50`)", runs.get("lattice_mu0_dp50", [])),
             ("pour_dp50", "pour, frictionless (`pour_dp50`)", pour)]
    stats = {}
    head = "| fill | n | " + " | ".join(m[1] for m in metrics) + " |"
    table = [head, "|" + "---|" * (2 + len(metrics))]
    for name, label, rs in cases:
        st = {"seeds": [r["_seed"] for r in rs]}
        cells = []
        for key, _, fn, sc in metrics:
            vals = [fn(r) for r in rs]
            st[key + "_all"] = vals
            st[key] = mean_ci(vals)
            cells.append(fmt(*st[key][:2], scale=sc) if key != "hf" else f"**{fmt(*st[key][:2], scale=sc)}**")
        stats[name] = st
        table.append(f"| {label} | {len(rs)} | " + " | ".join(cells) + " |")
    dtable = ["| | pour - lattice frictionless: the fill's way (Welch 95%) | resolved | pour - lattice at 0.5 (Welch 95%) | resolved |",
              "|---|---|---|---|---|"]
    for key, lab, _, sc in metrics:
        cells = []
        for other in ("lattice_mu0_dp50", "dp50"):
            diff = rules.difference("Welch", stats[other][key + "_all"], stats["pour_dp50"][key + "_all"])
            m, h = (diff.d if diff.d is not None else math.nan), (diff.h if diff.ok else math.nan)
            res = "yes" if rules.resolved(diff) == "resolved" else "no"
            cells += [fmt(m, h, scale=sc), res]
        dtable.append(f"| {lab} | " + " | ".join(cells) + " |")
    extra = []
    if pour:
        placed = pour[0].get("grains_placed", float("nan"))
        removed = [r.get("grains_removed_at_seal", 0) for r in pour]
        spilled = [r.get("grains_spilled", 0) for r in pour]
        overlap = [r.get("seal_max_overlap", 0) for r in pour]
        settled = sum(bool(r.get("fill_settled")) for r in pour)
        extra = [f"The pour: {placed:g} grains placed per seed; struck off at the seal "
                 f"{', '.join(f'{x:g}' for x in removed)}, spilled over the rim in the pour "
                 f"{', '.join(f'{x:g}' for x in spilled)} (seeds in order); the largest overlap of a grain with a "
                 f"membrane particle at the seal {max(overlap) * 1e3:.2g} mm; at rest before `stages.fill_time` "
                 f"in {settled} of {len(pour)} seeds."]

    fig, ax = plt.subplots(1, 3, figsize=(12, 3.8))
    for k, (key, lab, sc) in enumerate((("hf", "holding force [N]", 1.0), ("dv", "volume change in the vacuum [%]", 100.0),
                                         ("ps", "packing at the seal", 1.0))):
        ms, hs = [], []
        for x, (name, _, _) in enumerate(cases):
            st = stats[name]
            ax[k].plot([x] * len(st[key + "_all"]), [v * sc for v in st[key + "_all"]], "o", color="0.5", ms=4)
            ms.append(st[key][0] * sc if st[key][2] else 0)
            hs.append(st[key][1] * sc if math.isfinite(st[key][1]) else 0)
        ax[k].bar(range(len(cases)), ms, yerr=hs, capsize=4, color=["C0", "C2", "C1"], alpha=0.6)
        ax[k].set_xticks(range(len(cases)), ["lattice\nfill μ 0.5", "lattice\nfill μ 0", "pour\nfill μ 0"])
        ax[k].set_ylabel(lab)
        ax[k].grid(alpha=0.3, axis="y")
    fig.suptitle("the gripper at 50 kPa: the lattice fills against the pour (seeds 1-5; mean, 95% interval)")
    fig.tight_layout()
    fig.savefig(os.path.join(ROOT, "docs", "devices_gripper_pour_study.png"), dpi=110)
    text = "\n".join(
        [f"Made by `scripts/device_study.sh gripper_pour` and `python3 -m vppdem.report device gripper_pour` "
         f"from the records in `docs/data/devices/gripper_pour/` ({len(pour) + len(runs.get('lattice_mu0_dp50', []))} of 10 runs: 2 cases x seeds 1-5) and the gripper study's `dp50` "
         f"(`docs/data/devices/gripper/`, {len(lattice)} runs). Mean ± the 95% Student-t half-width over the seeds; "
         f"packing: the grains' volume over the volume enclosed by the membrane particles' centres.",
         "", *table, "", *extra, "", "The difference of the means (independent samples: a seed's jitter acts on "
         "another lattice in the pour's column than in the bag):", "", *dtable, "", "![The pour against the lattice](devices_gripper_pour_study.png)"])
    replace_block("gripper_pour", text)
    return stats


BEAM_CASES = [("dp0", "no vacuum", 0), ("dp25", "25 kPa", 25), ("dp50", "50 kPa", 50)]
# The beam's steps in dp, and their test: Welch's t, as the page has compared them since the study
# ran (a seed's cases share its fill, so a paired test would be valid too; it resolves the same steps).
BEAM_STEPS = [("dp0", "dp25"), ("dp25", "dp50"), ("dp0", "dp50")]
BEAM_TEST = "Welch"


def loss_ratio(r):
    """The loop's work over the peak load's work at the cycle's amplitude, W / (P_max |a| / 2): 1 for a
    rectangle (friction at a constant load), small for a narrow, elastic loop."""
    cyc = [g for g in r["inputs"]["tools.loader.program"] if g.get("kind") == "cycle"][0]
    return r["work_per_cycle"] / (r["peak_force"] * abs(cyc["amplitude"]) / 2)


def beam_values(runs):
    """{case: {quantity: {seed: value}}} of the beam's runs: k (stiffness), w (work per cycle), loss
    (loss_ratio)."""
    out = {}
    for name, _, _ in BEAM_CASES:
        rs = runs.get(name, [])
        out[name] = {"k": {r["_seed"]: r["stiffness"] for r in rs}, "w": {r["_seed"]: r["work_per_cycle"] for r in rs},
                     "loss": {r["_seed"]: loss_ratio(r) for r in rs}}
    return out


def dtext(diff, spec=".3g", unit="", scale=1.0):
    """A difference as the page prints it: mean +- half width (format spec) [unit], resolved or not
    (rules.resolved)."""
    u = f" {unit}" if unit else ""
    if diff is None or diff.d is None:
        return "pending"
    if not diff.ok:
        return f"{diff.d * scale:+{spec}}{u} (no interval)"
    res = {"resolved": "resolved", "unresolved": "not resolved"}[rules.resolved(diff)]
    return f"{diff.d * scale:+{spec}} ± {diff.h * scale:{spec}}{u}, {res}"


def beam(runs):
    rows, stats = [], {}
    for name, label, dp in BEAM_CASES:
        rs = runs.get(name, [])
        k = mean_ci([r["stiffness"] for r in rs])
        w = mean_ci([r["work_per_cycle"] for r in rs])
        p = mean_ci([r["peak_force"] for r in rs])
        dv = mean_ci([r["volume_change_vacuum"] for r in rs])
        ph = mean_ci([r["packing_vacuum"] for r in rs])
        lr = mean_ci([loss_ratio(r) for r in rs])
        stats[name] = {"k": k, "w": w, "dp": dp, "k_all": [r["stiffness"] for r in rs],
                       "w_all": [r["work_per_cycle"] for r in rs], "runs": rs}
        rows.append(f"| `{name}` | {label} | {k[2]} | **{fmt(*k[:2])}** | **{fmt(*w[:2], scale=1e6)}** | "
                    f"{fmt(*p[:2])} | {fmt(*dv[:2], scale=100)} | {fmt(*ph[:2])} | {fmt(*lr[:2], digits=2)} |")
    table = ["| case | dp | n | stiffness [N/m] | work per cycle [µJ] | peak force [N] | volume change in the vacuum [%] | packing after the vacuum | W / (P_max a / 2) |",
             "|---|---|---|---|---|---|---|---|---|"] + rows
    vals = beam_values(runs)
    steps = [f"| difference ({BEAM_TEST} 95%) | stiffness [N/m] | work per cycle [µJ] | W / (P_max a / 2) |",
             "|---|---|---|---|"]
    for a, b in BEAM_STEPS:
        cells = [dtext(rules.difference(BEAM_TEST, vals[a][q], vals[b][q]), digits, scale=sc)
                 for q, digits, sc in (("k", ".0f", 1.0), ("w", ".1f", 1e6), ("loss", ".3f", 1.0))]
        steps.append(f"| `{b}` - `{a}` | " + " | ".join(cells) + " |")
    n_done = sum(len(runs.get(c[0], [])) for c in BEAM_CASES)
    fig, ax = plt.subplots(1, 3, figsize=(13, 4))
    for nm, col in zip([c[0] for c in BEAM_CASES], ("C2", "C1", "C0")):
        for r in stats[nm]["runs"][:1]:
            t = read_tools(os.path.join(r["_dir"], "tools.csv"))
            ld = [row for row in t if int(row["stage"]) == 4]
            if not ld:
                continue
            # the cycles: the last cycles x 2 |a| / speed of the load stage (the loader's program)
            cyc = [g for g in r["inputs"]["tools.loader.program"] if g.get("kind") == "cycle"][0]
            period = 2 * abs(cyc["amplitude"]) / cyc["speed"]
            ncyc = cyc["cycles"]
            ld = [row for row in ld if row["time"] >= ld[-1]["time"] - ncyc * period - 1e-9]
            z0 = ld[0]["loader_z"]
            ax[0].plot([-(row["loader_z"] - z0) * 1e3 for row in ld], [row["loader_fz"] for row in ld], color=col,
                       lw=0.8, label=f"{stats[nm]['dp']} kPa, seed {r['_seed']}")
    ax[0].set_xlabel("mid-span deflection from the cycles' start [mm]")
    ax[0].set_ylabel("mid-span force [N]")
    ax[0].set_title("the 2 cycles (after contact and preload)")
    ax[0].legend(fontsize=8)
    for k, key, lab, sc in ((1, "k", "bending stiffness [N/m]", 1.0), (2, "w", "work per cycle [µJ]", 1e6)):
        xs, ms, hs = [], [], []
        for nm, _, dp in BEAM_CASES:
            st = stats[nm]
            vals = st[key + "_all"]
            if not vals:
                continue
            ax[k].plot([dp] * len(vals), [v * sc for v in vals], "o", color="0.6", ms=4)
            xs.append(dp)
            ms.append(st[key][0] * sc)
            hs.append(st[key][1] * sc if math.isfinite(st[key][1]) else 0)
        ax[k].errorbar(xs, ms, yerr=hs, fmt="s-", capsize=4)
        ax[k].set_xlabel("underpressure dp [kPa]")
        ax[k].set_ylabel(lab)
        ax[k].grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(os.path.join(ROOT, "docs", "devices_beam_study.png"), dpi=110)
    seeds = rules.planned_seeds(os.path.join(ROOT, "studies", "devices", "beam.toml")) or 3
    text = "\n".join(
        [f"Made by `scripts/device_study.sh beam` and `python3 -m vppdem.report device beam` from the "
         f"records in `docs/data/devices/beam/` ({n_done} of {seeds * len(BEAM_CASES)} runs: {len(BEAM_CASES)} "
         f"underpressures x seeds 1-{seeds}). The second (last) of the 2 cycles; mean ± the 95% Student-t half-width over the seeds. "
         f"W / (P_max a / 2): the loop's work over the peak load's work at the amplitude a (1: a rectangle).",
         "", *table, "", f"The steps in dp (independent samples, {BEAM_TEST}'s t; resolved: 0 outside the 95% "
         "interval, vppdem.report.rules):", "", *steps, "", "![The beam study](devices_beam_study.png)"])
    replace_block("beam", text)
    return stats



# ---------------------------------------------------------------------------------------------
# Beside the published trends, and the page's decision rules (issue 60, items 1 and 5): from the
# records of all three studies, every verdict by vppdem.report.rules.

BROWN = "Brown et al., PNAS 107, 18809 (2010): the jamming gripper"
GOETZ = ("Götz & Pöschel, Granular Matter 25 (2023): a simply supported beam of jammed grains")
BAJKOWSKI = "Bajkowski, Dyniewicz & Bajer; Zalewski et al. (VPP beams and dampers)"
BROWN_VOLUME = 0.005  # Brown et al.: volume changes below 0.5% suffice to grip


def by_seed(rs, fn):
    return {r["_seed"]: fn(r) for r in rs}


def n_of(vals, scale=1.0, digits=3):
    """mean +- 95% half width of the values, as the tables print it."""
    m, h, _ = mean_ci(vals)
    return fmt(m, h, digits, scale)


def trend_rows(gr, pour, bm):
    """The rows of "Beside the published trends": (published, what it says, the model, verdict), each
    verdict from the rules' outcomes on the records (gr, pour, bm: load() of the three studies)."""
    hf = {c: by_seed(gr.get(c, []), lambda r: r["holding_force"]) for c, *_ in GRIPPER_CASES}
    wrap = {c: [OBJECT_TOP - r["membrane_z_min"] for r in gr.get(c, [])] for c, *_ in GRIPPER_CASES}

    def pd(a, b):  # a - b, paired by seed
        return rules.difference("paired", hf[b], hf[a])

    def ups(a, b):
        return sum(1 for k in hf[a] if k in hf[b] and hf[a][k] > hf[b][k])

    def mean_text(c):
        v = list(hf[c].values())
        if v and all(x == 0 for x in v):
            return "0"
        m, h, _ = mean_ci(v)
        return f"{m:.3f} ± {h:.3f}" if math.isfinite(h) else f"{m:.3f}"

    def dN(d):
        return dtext(d, ".3f", "N")

    rows = []
    n0 = len(hf["dp0"])
    total = sum(len(v) for v in hf.values())
    zero0 = sum(1 for v in hf["dp0"].values() if v == 0)
    d50 = pd("dp50", "dp0")
    v1 = rules.verdict_direction([rules.direction(d50, +1)])
    above = sum(1 for v in hf["dp50"].values() if v > 0)
    grips = [k for k, v in hf["dp50"].items() if v > 0 and k in hf["dp0"]]
    every = bool(grips) and all(hf["dp50"][k] > hf["dp0"][k] for k in grips)
    nseed = len(hf["dp50"])
    rows.append((BROWN, "an unjammed bag holds little; the vacuum hardens it and it holds",
                 (f"0 N without the vacuum in every seed ({total} runs: {nseed} seeds x {len(GRIPPER_CASES)} cases, "
                  f"the {n0} at dp = 0 all 0 N)" if zero0 == n0 else f"0 N without the vacuum in {zero0} of {n0} seeds")
                 + f"; {mean_text('dp50')} N with 50 kPa, above 0 in {above} of {nseed} seeds (the paired "
                 f"difference {dN(d50)})",
                 rules.verdict_text(v1, (("the direction in every seed that grips, " if every else "")
                                         + f"the grip itself too weak and scattered for {nseed} seeds")
                                    if v1 != "reproduced" else "the paired difference resolved above 0")))

    s1, s2 = pd("dp25", "dp0"), pd("dp50", "dp25")
    vdir = rules.verdict_direction([rules.direction(s1, +1), rules.direction(s2, +1)])
    R = rules.ratio_diff(list(hf["dp50"].values()), list(hf["dp25"].values()))  # F(25) / F(50) - 1
    prop = None
    if R.ok:  # F(25) / F(50) against the 0.5 of F proportional to dp
        prop = rules.from_interval("ratio", R.n, (R.d + 1.0) - 0.5, R.h, R.dof, 0.5)
    vprop = rules.verdict_equivalence([rules.band(prop)])
    rows.append(("Brown et al. 2010", "the holding force of each mechanism scales with the jammed state's strength, "
                 "which is proportional to the pressure difference: F roughly ∝ dp",
                 f"{mean_text('dp0')} N at 0 kPa, {mean_text('dp25')} N at 25 kPa, {mean_text('dp50')} N at 50 kPa; "
                 f"higher at each step in {ups('dp25', 'dp0')} and {ups('dp50', 'dp25')} of {len(hf['dp50'])} seeds "
                 f"(paired steps {dN(s1)} and {dN(s2)}); F(25) / F(50) = "
                 + (f"{R.d + 1:.2f} ± {R.h:.2f}" if R.ok else "pending") + " where ∝ dp gives 0.5",
                 f"direction: {vdir}; proportionality: {vprop}"
                 + (" (" + {"within": "F(25) / F(50) within +-10% of 0.5",
                            "beyond": "F(25) / F(50) beyond +-10% of 0.5, resolved",
                            "resolved": "F(25) / F(50) away from 0.5, resolved, its interval reaching inside +-10% of it",
                            "unresolved": "0.5 inside the interval of F(25) / F(50), which reaches past +-10% of 0.5"}
                    [rules.band(prop)] + ")" if prop else "")))

    i1, i2 = pd("dp50", "press1_dp50"), pd("press4_dp50", "dp50")
    vimm = rules.verdict_direction([rules.direction(i1, +1), rules.direction(i2, +1)])
    wm = [mean_ci(wrap[c])[0] * 1e3 for c in ("press1_dp50", "dp50", "press4_dp50")]
    rows.append(("Brown et al. 2010", "the grip depends on how far the bag wraps the object; interlocking needs it "
                 "to reach past the object's widest section",
                 f"presses of 1, 2, 4 N wrap to {wm[0]:.1f}, {wm[1]:.1f}, {wm[2]:.1f} mm below the top (the equator at "
                 f"{OBJECT_TOP * 1e3:g} mm) and hold {mean_ci(list(hf['press1_dp50'].values()))[0]:.3f}, "
                 f"{mean_ci(list(hf['dp50'].values()))[0]:.3f}, {mean_ci(list(hf['press4_dp50'].values()))[0]:.3f} N in "
                 f"the mean; more from 1 to 2 N in {ups('dp50', 'press1_dp50')} of {len(hf['dp50'])} seeds, from 2 to 4 N "
                 f"in {ups('press4_dp50', 'dp50')} of {len(hf['dp50'])} (paired {dN(i1)} and {dN(i2)})",
                 rules.verdict_text(vimm, ("higher in the mean at each step, no step resolved"
                                           if i1.ok and i2.ok and i1.d > 0 and i2.d > 0 else "")
                                    if vimm == "consistent, not established" else "")))

    def dv(rs):
        return [-r["volume_change_vacuum"] for r in rs]

    def seal(rs):
        return [r["grain_volume"] / r["volume_seal"] for r in rs]
    lat, pr = gr.get("dp50", []), pour.get("pour_dp50", [])
    o_lat, o_pr = rules.one_sample(dv(lat), BROWN_VOLUME), rules.one_sample(dv(pr), BROWN_VOLUME)
    vvol = rules.verdict_direction([rules.direction(o_lat, -1), rules.direction(o_pr, -1)])
    dpour = rules.difference("Welch", dv(lat), dv(pr))
    rows.append(("Brown et al. 2010", "volume changes below 0.5% suffice to grip",
                 f"{n_of([r['volume_change_vacuum'] for r in lat], 100)}% in the vacuum stage (50 kPa); poured "
                 f"(a packing of {mean_ci(seal(pr))[0]:.3f} at the seal against the lattice's {mean_ci(seal(lat))[0]:.3f}) "
                 f"{n_of([r['volume_change_vacuum'] for r in pr], 100)}%",
                 rules.verdict_text(vvol, "the vacuum stage's shrinkage "
                                    + ("lies above 0.5%, resolved, in both fills" if vvol == "not reproduced" else
                                       "against 0.5%: " + ", ".join(f"{n} {dtext(o, '.1f', 'points', 100)}" for n, o in
                                                                    (("lattice", o_lat), ("pour", o_pr))))
                                    + f"; the denser pour shrinks {-dpour.d * 100:.1f} points less "
                                    f"({rules.resolved(dpour)}, Welch), still "
                                    f"{mean_ci(dv(pr))[0] / BROWN_VOLUME:.0f} times more")))

    fm, fg = pd("dp50", "mu_membrane0_dp50"), pd("dp50", "mu_grains0_dp50")
    vfr = rules.verdict_direction([rules.direction(fm, +1), rules.direction(fg, +1)])
    zero_m = sum(1 for v in hf["mu_membrane0_dp50"].values() if v == 0)
    rows.append(("Brown et al. 2010", "three mechanisms: friction, interlocking, suction",
                 f"membrane friction off: {'0 N in every seed' if zero_m == len(hf['mu_membrane0_dp50']) else f'0 N in {zero_m} seeds'} "
                 f"(the default grips in {above} of {len(hf['dp50'])}; paired {dN(fm)}); grains' friction off: "
                 f"{mean_text('mu_grains0_dp50')} N (the default less it, paired: {dN(fg)}; "
                 f"{rules.statement_equivalence(rules.difference('paired', hf['dp50'], hf['mu_grains0_dp50']))}); "
                 "suction off (this study ran before it; the 25-grain gripper's rows below measure it)",
                 f"friction: {vfr}"
                 + (f" (without friction on the membrane no seed holds, so what grip there is goes through it, but "
                    f"neither difference is resolved by {len(hf['dp50'])} seeds)"
                    if zero_m == len(hf["mu_membrane0_dp50"]) and vfr == "consistent, not established" else "")
                 + "; interlocking: "
                 + rules.label("nothing measured", f"no case removes it alone, and at the 2 N press the bag reaches "
                               f"{wm[1]:.1f} mm of the {OBJECT_TOP * 1e3:g} mm to the object's equator") + "; suction: "
                 + rules.label("nothing measured", "this study ran without it (the 25-grain gripper's rows below)")))

    bv = beam_values(bm)
    ks = [rules.difference(BEAM_TEST, bv[a]["k"], bv[b]["k"]) for a, b in BEAM_STEPS[:2]]
    ws = [rules.difference(BEAM_TEST, bv[a]["w"], bv[b]["w"]) for a, b in BEAM_STEPS[:2]]
    ls = [rules.difference(BEAM_TEST, bv[a]["loss"], bv[b]["loss"]) for a, b in BEAM_STEPS[:2]]
    vk = rules.verdict_direction([rules.direction(d, +1) for d in ks])
    kmean = {c: mean_ci(list(bv[c]["k"].values())) for c, *_ in BEAM_CASES}
    lmean = {c: mean_ci(list(bv[c]["loss"].values())) for c, *_ in BEAM_CASES}
    rows.append((GOETZ, "the jammed beam responds elastically (viscoelastic) to a weak, quasi-static load; its "
                 "stiffness comes from the confining pressure and the packing (D'Angelo, Götz & Pöschel 2023: from "
                 "the volume fraction the preparation leaves)",
                 f"the loop is narrow on loading (W / (P_max a / 2) {fmt(*lmean['dp25'][:2], 2)} at 25 kPa, "
                 f"{fmt(*lmean['dp50'][:2], 2)} at 50 kPa); the loading branch's slope {fmt(*kmean['dp25'][:2], 4)} N/m "
                 f"at 25 kPa, {fmt(*kmean['dp50'][:2], 4)} N/m at 50 kPa, {fmt(*kmean['dp0'][:2], 3)} N/m without the "
                 f"vacuum ({BEAM_TEST} steps {dtext(ks[0], '.0f')} and {dtext(ks[1], '.0f')} N/m)",
                 f"the stiffness rising with the confining pressure: {vk}; the elastic response: "
                 + rules.label("nothing measured", "the cycles ran at 25 mm/s, not quasi-static, and no rule here "
                               "decides 'elastic'; the modulus the stiffness implies (about 1.0 MPa at 50 kPa) is not "
                               "compared")))

    wm_ = {c: mean_ci(list(bv[c]["w"].values()))[0] * 1e6 for c, *_ in BEAM_CASES}
    vw = rules.verdict_direction([rules.direction(d, +1) for d in ws])
    vl = rules.verdict_direction([rules.direction(d, +1) for d in ls])
    rows.append((BAJKOWSKI, "bending stiffness and damping grow with the underpressure",
                 f"stiffness: {kmean['dp0'][0]:.0f}, {kmean['dp25'][0]:.0f}, {kmean['dp50'][0]:.0f} N/m at 0, 25, 50 kPa; "
                 f"work per cycle at a fixed amplitude: {wm_['dp0']:.0f}, {wm_['dp25']:.0f}, {wm_['dp50']:.1f} µJ "
                 f"({BEAM_TEST} steps {dtext(ws[0], '.1f', 'µJ', 1e6)} and {dtext(ws[1], '.1f', 'µJ', 1e6)}); relative "
                 f"to the load's work (W / (P_max a / 2)) {lmean['dp0'][0]:.2f}, {lmean['dp25'][0]:.2f}, "
                 f"{lmean['dp50'][0]:.2f} (steps {dtext(ls[0], '.3f')} and {dtext(ls[1], '.3f')})",
                 f"stiffness: {vk} ({'every step resolved' if vk == 'reproduced' else 'not every step resolved'}); "
                 f"damping as energy per cycle at a fixed displacement: {vw}"
                 + (" (up from 0 to 25 kPa, resolved; from 25 to 50 kPa not resolved, and no step resolved against "
                    "it)" if vw == "consistent, not established" else "")
                 + f"; as the loop's share of the load's work: {vl}"
                 + (" (it falls at both steps, resolved)" if vl == "not reproduced" else "")))
    return rows


def device_rules(seeds):
    """The page's "## Decision rules" section (rules.section): seeds {study: planned seeds}."""
    return rules.section(rules.PageRules(
        module="vppdem.report.device",
        tests=[("paired", "the gripper study's cases against each other: a seed's cases share its fill (the "
                          "jitter), so they differ by the case alone"),
               ("welch", "the pour against the lattice fills (a seed's jitter acts on another lattice), and the "
                         "beam's steps in dp, the page's test since the beam study ran (a seed's cases share its "
                         "fill there too: the paired test resolves the same steps); the 25-grain gripper's cases "
                         "against each other (its studies' plan)"),
               ("direction", "every trend of the table 'Beside the published trends': each step of the trend "
                             "(0 -> 25 -> 50 kPa; press 1 -> 2 -> 4 N; a friction switched off against the "
                             "default) must be resolved the published way; Brown et al.'s 0.5% against the mean "
                             "volume change of the vacuum stage with its 95% Student-t interval"),
               ("ratio", "F(25) / F(50) of the gripper's holding force; the 25-grain gripper's F / (dp A) at 25 "
                         "and at 75 kPa over its 50 kPa mean"),
               ("equivalence", "F(25) / F(50) against the 0.5 of a force proportional to dp (the margin: 10% of "
                               "0.5), the grains' friction switched off against the default, and the 25-grain "
                               "gripper's ratios of F / (dp A) against 1 (the margin: 10%)")],
        which_w="no W here: the gripper's holding force (summary.json `holding_force`, the largest pull on the "
                "object in the lift) and the vacuum stage's volume change; the beam's `stiffness` and "
                "`work_per_cycle` of the second (last) of its 2 cycles, and their ratio to the peak load's work.",
        planned="; ".join(f"{k}: {v} (`seeds` of studies/devices/{k}.toml)" for k, v in seeds.items() if v is not None)
                + ", fixed before the runs.",
        added="The beam's seeds 4-5 were added after a look: its first study (issue 47, seeds 1-3) had been seen; "
              "for issue 61 every run was made again by one pinned build with 5 seeds, the tests unchanged (seeds "
              "1-3 gave every summary number as before, to the last digit).",
        labels=["nothing measured"],
        fixed_before=["the 25-grain gripper's four studies (gripper_vacuum, gripper_mechanisms, "
                      "gripper_mechanisms_sphere, gripper_size): their cases, seeds 1-5 and every test of their rows, "
                      "written in their study files before their runs (the design runs of seed 1 that chose the gripper "
                      "came before the plan; none of them is a study run; the size study was planned after the other "
                      "three had been seen, before its own runs)",
                      "the cases and the seeds of the three study files (the gripper's seeds 1-5, the pour's 1-5, "
                      "the beam's 1-3) before their runs: a plan, not a decision rule; the beam's rerun with seeds 1-5 "
                      "(issue 61) was decided before its runs, its rules unchanged"],
        fixed_after=["the 25-grain gripper's proportionality test: its study files' plan read 'the intervals of "
                     "F / (dp A) at 25 and 75 kPa hold the 50 kPa mean', which calls any wide interval proportional; "
                     "after 2-3 seeds of each case had been seen it became the page's equivalence rule on the ratio "
                     "of the means (+-10%)",
                     "every test and verdict of the small gripper's, the pour's and the beam's rows: those studies ran before issue 60's rules module "
                     "(vppdem.report.rules), and the rules were applied to their records after they had been "
                     "seen (the table's verdicts were hand-written before: the beam's damping 'not reproduced' "
                     "without a step resolved against the trend, the mechanisms 'partly', Götz & Pöschel "
                     "'consistent' without a test); the beam's protocol (the fcc fill, no gravity, the loader's "
                     "preload) was settled on seed 1 at 50 kPa, whose run is the study's `dp50_s1`"]))


def trends():
    """Writes the trends table and the rules section into docs/devices.md from the three studies'
    records; nothing while a study has no records."""
    gr, pour, bm = load("gripper"), load("gripper_pour"), load("beam")
    if not (gr and pour and bm):
        return False
    rows = trend_rows(gr, pour, bm)
    from . import device_jamming
    rows += device_jamming.trend_rows(load)
    table = ["Made by `python3 -m vppdem.report device trends` (and by each study's report) from the records of "
             "the three studies; each verdict by the rules below (vppdem.report.rules), the paired and Welch "
             "differences with their 95% intervals.", "",
             "| published | what it says | the model | verdict |", "|---|---|---|---|"]
    table += [f"| {a} | {b} | {c} | {d} |" for a, b, c, d in rows]
    replace_block("trends", "\n".join(table))
    root = os.path.join(ROOT, "studies", "devices")
    seeds = {k: rules.planned_seeds(os.path.join(root, f"{k}.toml"))
             for k in ("gripper", "gripper_pour", "beam", "gripper_vacuum", "gripper_mechanisms", "gripper_mechanisms_sphere",
                       "gripper_size")}
    replace_block("rules", "\n".join(device_rules(seeds)))
    return True


# ---------------------------------------------------------------------------------------------
# Any device study's folder (issue 61, item 2): its cases' numbers with their intervals.

SHIPPED = ("gripper", "gripper_pour", "beam", "trends", "gripper_jamming")


class StudyError(ValueError):
    """A folder the study report cannot read: the message names the folder and what is wrong."""


def study_runs(folder):
    """(source, numbers, {case: [{"seed": s, "folder": f, number: value or None}]}) of a device
    study's folder: from summary.csv (its rows of status ok, its number columns between
    case,seed,folder and status), else from the run folders' summary.json at stage done (case and
    seed from the folder's name, <case>_s<seed> or <case>; the numbers of vppdem.plot.DEVICE_NUMBERS).
    Cases in the table's order (file order), else by name."""
    path = os.path.join(folder, "summary.csv")
    runs = {}
    if os.path.isfile(path):
        header, rows = records.read_table(path)
        if header[:3] != ["case", "seed", "folder"] or "status" not in header:
            raise StudyError(f"{path}: not a device study's table (expected case,seed,folder, its numbers, status; "
                             f"columns: {', '.join(header)})")
        numbers = header[3:header.index("status")]
        for r in rows:
            if r.get("status") != "ok":
                continue
            seed = records.finite_number(r.get("seed"))
            run = {"seed": int(seed) if seed is not None else 0, "folder": r["folder"]}
            run.update({q: records.finite_number(r.get(q)) for q in numbers})
            runs.setdefault(r["case"], []).append(run)
        return "summary.csv", numbers, runs
    numbers = list(vplot.DEVICE_NUMBERS)
    for d in sorted(os.listdir(folder)) if os.path.isdir(folder) else []:
        p = os.path.join(folder, d, "summary.json")
        if not os.path.isfile(p):
            continue
        try:
            with open(p) as f:
                js = json.load(f)
        except (OSError, ValueError):
            continue
        if not isinstance(js, dict) or js.get("stage") != "done":
            continue
        m = re.match(r"(.+)_s(\d+)$", d)
        run = {"seed": int(m.group(2)) if m else 0, "folder": d}
        run.update({q: records.finite_number(js.get(q)) for q in numbers})
        runs.setdefault(m.group(1) if m else d, []).append(run)
    return "the run folders' summary.json", numbers, runs


def study_stats(runs, numbers):
    """{number: {case: (n, mean, sd, half width)}} (vppdem.report.stats.interval) of the numbers a
    finished run has; a number with no value in any run is left out."""
    out = {}
    for q in numbers:
        per = {c: interval([r[q] for r in rs]) for c, rs in runs.items()}
        if any(v[0] for v in per.values()):
            out[q] = per
    return out


def study_report(folder, out=None, test="Welch", command=None):
    """DIR/device_report.md and DIR/device_report.png of any device study's folder (DIR: out, default
    the folder): per case the finished runs and each number's mean with its 95% Student-t half
    width, then each case's difference from the first case by `test` ("Welch": independent samples;
    "paired": seed by seed). Returns the page's path; StudyError for a folder without finished runs."""
    folder = os.fspath(folder)
    out = os.fspath(out) if out else folder
    if not os.path.isdir(folder):
        raise StudyError(f"'{folder}': no such folder")
    try:
        source, numbers, runs = study_runs(folder)
    except records.RecordError as e:
        raise StudyError(str(e)) from None
    if not runs:
        raise StudyError(f"'{folder}': no finished run (a device study's folder holds summary.csv, or run folders "
                         "<case>_s<seed>/ with summary.json at stage done)")
    stats = study_stats(runs, numbers)
    cases = list(runs)
    # The figure's numbers: those whose runs differ; the others named once.
    per = {q: {c: (st[1], st[3] if math.isfinite(st[3]) else None, [r[q] for r in runs[c] if r[q] is not None])
               for c, st in stats[q].items() if st[0]} for q in stats}
    varying, constant = vplot.split_constant(per)
    name = os.path.basename(os.path.abspath(folder))
    command = command or f"python3 -m vppdem.report device {folder}"
    n_runs = sum(len(rs) for rs in runs.values())
    seeds = sorted({r["seed"] for rs in runs.values() for r in rs})

    def cell(st, scale):
        n, m, _, h = st
        return fmt(m, h, 3, scale) if n else "-"

    lines = [f"# Device study `{name}`", "",
             f"Made by `{command}` from {source} of `{folder}` ({n_runs} finished runs: {len(cases)} cases, "
             + (f"seeds {', '.join(map(str, seeds))}" if seeds != [0] else "the device file's seed") +
             "). Mean ± the 95% Student-t half-width over the seeds "
             "(vppdem.report.stats, as summary_cases.csv); n: the finished runs of the case (a number fewer runs "
             "have says its own n).", ""]
    heads = [(q,) + vplot.device_number_label(q) for q in varying]
    lines.append("| case | n | " + " | ".join(h[1] for h in heads) + " |")
    lines.append("|---|---|" + "---|" * len(heads))
    for c in cases:
        n = len(runs[c])
        cells = []
        for q, _, scale in heads:
            st = stats[q][c]
            cells.append(cell(st, scale) + (f" (n = {st[0]})" if 0 < st[0] < n else ""))
        lines.append(f"| `{c}` | {n} | " + " | ".join(cells) + " |")
    if constant:
        text = vplot.constant_text(constant)
        lines += ["", text[0].upper() + text[1:] + "."]
    if len(cases) > 1 and heads:
        ref = cases[0]
        how = ("independent samples: Welch's t, valid whether or not a seed's cases share their fill" if test == "Welch"
               else "paired by seed: Student's t on the per-seed differences, for cases that share a seed's fill")
        lines += ["", f"Each case against `{ref}` ({how}; 95%; resolved: 0 outside the interval, "
                  "vppdem.report.rules):", "",
                  "| difference | " + " | ".join(h[1] for h in heads) + " |", "|---|" + "---|" * len(heads)]
        for c in cases[1:]:
            cells = []
            for q, _, scale in heads:
                a = {r["seed"]: r[q] for r in runs[ref] if r[q] is not None}
                b = {r["seed"]: r[q] for r in runs[c] if r[q] is not None}
                cells.append(dtext(rules.difference(test, a, b), ".3g", scale=scale) if a and b else "-")
            lines.append(f"| `{c}` - `{ref}` | " + " | ".join(cells) + " |")
    os.makedirs(out, exist_ok=True)
    fig = vplot.device_numbers_figure(name, cases, {q: per[q] for q in varying}, True)
    fig.savefig(os.path.join(out, "device_report.png"), dpi=110)
    lines += ["", "![the study](device_report.png)", ""]
    page = os.path.join(out, "device_report.md")
    with open(page, "w") as f:
        f.write("\n".join(lines))
    return page


def main(argv=None):
    args = sys.argv[1:] if argv is None else list(argv)
    ap = argparse.ArgumentParser(
        prog="vppdem.report device",
        description="docs/devices.md's tables and figures of a shipped device study (gripper, gripper_pour, beam; "
                    "trends: only the trends table and the rules section), or the report of any device study's "
                    "folder: DIR/device_report.md and DIR/device_report.png.")
    ap.add_argument("study", nargs="?", default="gripper",
                    help="gripper, gripper_pour, beam or trends (default gripper), or a device study's folder (the "
                         "--out or --publish folder of `vppdem sweep`; ./NAME for a folder named like a shipped study)")
    ap.add_argument("--out", metavar="DIR", help="a folder's report: where to write it (default: the folder)")
    ap.add_argument("--test", choices=("Welch", "paired"), default=None,
                    help="a folder's report: the test of each case against the first (default Welch)")
    a = ap.parse_args(args)
    if a.study not in SHIPPED:
        if not os.path.isdir(a.study):
            ap.error(f"'{a.study}' is neither a shipped study ({', '.join(SHIPPED)}) nor a folder")
        try:
            print(study_report(a.study, a.out, a.test or "Welch"))
        except StudyError as e:
            print(f"vppdem.report device: {e}", file=sys.stderr)
            return 2
        return 0
    if a.out or a.test:
        ap.error(f"--out and --test are for a study's folder, not the shipped study '{a.study}' (its report writes "
                 "docs/devices.md)")
    study = a.study
    if study == "gripper_jamming":
        from . import device_jamming
        if device_jamming.report(load, replace_block, ROOT) is None:
            print("device: gripper_jamming: no finished run in docs/data/devices/gripper_vacuum, gripper_mechanisms, "
                  "gripper_mechanisms_sphere yet")
            return 2
        if not trends():
            print("device: the trends table and the rules section wait for the records of all three studies")
        return 0
    if study != "trends":
        runs = load(study)
        stats = {"gripper": gripper, "gripper_pour": gripper_pour, "beam": beam}[study](runs)
        for name, st in stats.items():
            print(name, {k: v for k, v in st.items() if isinstance(v, tuple)})
    if not trends():
        print("device: the trends table and the rules section wait for the records of all three studies")


if __name__ == "__main__":
    sys.exit(main())
