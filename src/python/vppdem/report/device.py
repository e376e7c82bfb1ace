"""The device studies' report (issue 47, docs/devices.md).

Reads the published records docs/data/devices/<study>/<case>_s<seed>/ (summary.json, tools.csv.gz,
as `vppdem sweep studies/devices/<study>.toml --publish docs/data/devices/<study>` leaves
them), computes each case's mean and 95% Student-t interval over its seeds, draws
docs/devices_<study>_study.png and writes the table into docs/devices.md between the markers
<!-- device_report:<study> begin --> and <!-- ... end -->.

usage: python3 -m vppdem.report device gripper|gripper_pour|beam

    python3 -m vppdem.report device gripper
    python3 -m vppdem.report device gripper_pour   # the pour against the gripper's dp50
    python3 -m vppdem.report device beam
"""
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

from . import source_dir  # noqa: E402
from .stats import interval, welch as welch_diff  # noqa: E402

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
    pairs = [("dp25", "dp0"), ("dp50", "dp25"), ("press4_dp50", "dp50"), ("dp50", "press1_dp50"),
             ("dp50", "mu_membrane0_dp50"), ("dp50", "mu_grains0_dp50")]
    ptable = ["| difference (same seeds) | n | mean ± 95% [N] | seeds with a positive difference | resolved from 0 |",
              "|---|---|---|---|---|"]
    for a, b in pairs:
        da = dict(zip(stats[a]["seeds"], stats[a]["hf_all"]))
        db = dict(zip(stats[b]["seeds"], stats[b]["hf_all"]))
        d = [da[k] - db[k] for k in sorted(set(da) & set(db))]
        m, h, n = mean_ci(d)
        res = "yes" if n > 1 and math.isfinite(h) and abs(m) > h else "no"
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
         "Paired by seed (Student t on the per-seed differences):", "", *ptable, "",
         "![The gripper study](devices_gripper_study.png)"])
    replace_block("gripper", text)
    return stats


def welch(a, b):
    """mean(a) - mean(b) and its 95% half width for two independent samples (Welch's t with the
    Welch-Satterthwaite degrees of freedom: vppdem.report.stats.welch)."""
    d = welch_diff(b, a)
    return (d.d if d.d is not None else math.nan), (d.h if d.ok else math.nan)


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
            m, h = welch(stats["pour_dp50"][key + "_all"], stats[other][key + "_all"])
            res = "yes" if math.isfinite(h) and abs(m) > h else "no"
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


def beam(runs):
    rows, stats = [], {}
    for name, label, dp in BEAM_CASES:
        rs = runs.get(name, [])
        k = mean_ci([r["stiffness"] for r in rs])
        w = mean_ci([r["work_per_cycle"] for r in rs])
        p = mean_ci([r["peak_force"] for r in rs])
        dv = mean_ci([r["volume_change_vacuum"] for r in rs])
        ph = mean_ci([r["packing_vacuum"] for r in rs])
        stats[name] = {"k": k, "w": w, "dp": dp, "k_all": [r["stiffness"] for r in rs],
                       "w_all": [r["work_per_cycle"] for r in rs], "runs": rs}
        rows.append(f"| `{name}` | {label} | {k[2]} | **{fmt(*k[:2])}** | **{fmt(*w[:2], scale=1e6)}** | "
                    f"{fmt(*p[:2])} | {fmt(*dv[:2], scale=100)} | {fmt(*ph[:2])} |")
    table = ["| case | dp | n | stiffness [N/m] | work per cycle [µJ] | peak force [N] | volume change in the vacuum [%] | packing after the vacuum |",
             "|---|---|---|---|---|---|---|---|"] + rows
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
    text = "\n".join(
        [f"Made by `scripts/device_study.sh beam` and `python3 -m vppdem.report device beam` from the "
         f"records in `docs/data/devices/beam/` ({n_done} of {3 * len(BEAM_CASES)} runs: {len(BEAM_CASES)} "
         f"underpressures x seeds 1-3). The second (last) of the 2 cycles; mean ± the 95% Student-t half-width over the seeds.",
         "", *table, "", "![The beam study](devices_beam_study.png)"])
    replace_block("beam", text)
    return stats


def main(argv=None):
    args = sys.argv[1:] if argv is None else list(argv)
    study = args[0] if args else "gripper"
    runs = load(study)
    stats = {"gripper": gripper, "gripper_pour": gripper_pour, "beam": beam}[study](runs)
    for name, st in stats.items():
        print(name, {k: v for k, v in st.items() if isinstance(v, tuple)})


if __name__ == "__main__":
    sys.exit(main())
