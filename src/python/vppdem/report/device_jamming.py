"""The jamming gripper 25 grains across and its mechanisms (issue 61; docs/devices.md, "The
gripper's mechanisms").

Reads the published records of four device studies (docs/data/devices/<study>/<case>_s<seed>/):
gripper_vacuum (friction and suction on the cylinder at 0, 25, 50, 75 kPa), gripper_mechanisms
(the cylinder at 50 kPa with friction alone, suction alone, neither), gripper_mechanisms_sphere
(a sphere at 50 kPa: all three mechanisms, the shape alone) and gripper_size (cylinders of 8 and
16 mm diameter at 50 kPa; 12 mm is gripper_vacuum's both_dp50). Writes the table, the tests of the
studies' plan (fixed in their study files before the runs) and the figure
docs/devices_gripper_jamming_study.png, between <!-- device_report:gripper_jamming begin/end -->.

    python3 -m vppdem.report device gripper_jamming

The plan's rules, all vppdem.report.rules':
  holds       a case holds where the 95% Student-t interval of its mean holding force lies above 0
              (rules.one_sample against 0);
  differs     two cases differ where Welch's 95% interval of the difference of their means
              excludes 0 (rules.difference("Welch"));
  vacuum      the holding force grows with the vacuum where each step up (0 -> 25 -> 50 -> 75 kPa)
              is resolved upwards (rules.direction);
  dp          proportional to dp: the page's equivalence rule (rules.band on rules.ratio_diff) on
              F / (dp A) at 25 and at 75 kPa against its 50 kPa mean, a margin of +-10%: both within
              reproduces it, one beyond does not, else consistent, not established. The study files'
              plan had "the intervals at 25 and 75 kPa hold the 50 kPa mean", which calls any wide
              interval proportional; replaced after 2-3 seeds of each case had been seen (the rules
              section says so);
  size        the holding force grows with the object's diameter where each step (8 -> 12 -> 16 mm)
              is resolved upwards, and F / (dp A) falls with it where each step is resolved
              downwards (rules.direction on Welch's differences).
"""
import math
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from . import rules  # noqa: E402
from .device import fmt, mean_ci  # noqa: E402  (device imports this module only inside its functions)

STUDIES = ("gripper_vacuum", "gripper_mechanisms", "gripper_mechanisms_sphere", "gripper_size")
OBJECT_TOP = 0.006      # [m] both objects' top (the cylinder's end, the sphere's pole)
OBJECT_WEIGHT = 1000 * math.pi * 0.006 ** 2 * 0.012 * 9.81  # [N] the cylinder in a plastic of 1000 kg/m^3

# (study, case, label, dp [kPa], object, friction, suction)
CASES = [
    ("gripper_vacuum", "both_dp0", "friction + suction, no vacuum", 0, "cylinder 12 mm", True, True),
    ("gripper_vacuum", "both_dp25", "friction + suction", 25, "cylinder 12 mm", True, True),
    ("gripper_vacuum", "both_dp50", "friction + suction", 50, "cylinder 12 mm", True, True),
    ("gripper_vacuum", "both_dp75", "friction + suction", 75, "cylinder 12 mm", True, True),
    ("gripper_mechanisms", "friction_dp50", "friction alone", 50, "cylinder 12 mm", True, False),
    ("gripper_mechanisms", "suction_dp50", "suction alone", 50, "cylinder 12 mm", False, True),
    ("gripper_mechanisms", "none_dp50", "neither", 50, "cylinder 12 mm", False, False),
    ("gripper_mechanisms_sphere", "all_dp50", "friction + suction + shape", 50, "sphere", True, True),
    ("gripper_mechanisms_sphere", "shape_dp50", "the shape alone (interlocking)", 50, "sphere", False, False),
    ("gripper_size", "d8_dp50", "friction + suction", 50, "cylinder 8 mm", True, True),
    ("gripper_size", "d16_dp50", "friction + suction", 50, "cylinder 16 mm", True, True),
]
# The cylinders' diameters [mm] of the size steps, smallest first (12 mm: the default's).
SIZES = (("d8_dp50", 8), ("both_dp50", 12), ("d16_dp50", 16))


def values(rs, key, scale=1.0):
    return {r["_seed"]: (r.get(key) * scale if r.get(key) is not None else None) for r in rs}


def proportionality(ratio):
    """F proportional to dp: F / (dp A) at 25 and at 75 kPa against 50 kPa's ({case: {seed: value}}
    of both_dp25, both_dp50, both_dp75), each ratio of means by rules.ratio_diff and the page's
    equivalence rule (rules.band, +-10%); (verdict, what decided it)."""
    d = {k: rules.ratio_diff(list(ratio["both_dp50"].values()), list(ratio[c].values()))
         for k, c in ((25, "both_dp25"), (75, "both_dp75"))}
    verdict = rules.verdict_equivalence([rules.band(x) for x in d.values()])
    text = "; ".join(f"at {k} kPa {x.d + 1:.2f} ± {x.h:.2f} times 50 kPa's" if x.ok else f"at {k} kPa pending"
                     for k, x in d.items())
    return verdict, text


def holds(hf):
    """The plan's 'holds': the 95% interval of the mean above 0."""
    d = rules.one_sample(list(hf.values()), 0.0)
    if not d.ok:
        return None
    return d.d - d.h > 0


def report(load, replace_block, root):
    """Writes the section from the published records (load(study) -> {case: [summary]}); returns
    {case: stats} or None while a study has no finished run."""
    data = {s: load(s) for s in STUDIES}
    if not any(data.values()):
        return None
    st, rows = {}, []
    for study, case, label, dp, obj, fr, su in CASES:
        rs = data[study].get(case, [])
        hf = values(rs, "holding_force")
        ratio = values(rs, "holding_ratio") if dp > 0 else {}
        sm = values(rs, "suction_force_max") if su else {}
        seal = values(rs, "seal_area", 1e6) if su else {}
        wrap = {r["_seed"]: (OBJECT_TOP - r["membrane_z_min"]) * 1e3 for r in rs}
        dv = values(rs, "volume_change_vacuum", 100)
        s = {"hf": hf, "ratio": ratio, "dp": dp, "obj": obj, "n": len(rs), "holds": holds(hf) if len(rs) >= 2 else None}
        st[case] = s
        hold_text = {None: "-", True: "yes", False: "no"}[s["holds"]]
        rows.append(
            f"| `{case}` | {obj} | {label} | {dp} | {len(rs)} | **{fmt(*mean_ci(hf.values())[:2])}** | "
            f"{fmt(*mean_ci(ratio.values())[:2]) if ratio else '-'} | {hold_text} | "
            f"{sum(1 for v in hf.values() if v > 0)} of {len(rs)} | "
            f"{fmt(*mean_ci(sm.values())[:2]) if sm else '-'} | {fmt(*mean_ci(seal.values())[:2]) if seal else '-'} | "
            f"{fmt(*mean_ci(wrap.values())[:2])} | {fmt(*mean_ci(dv.values())[:2])} | "
            f"{', '.join(f'{hf[k]:.3f}' for k in sorted(hf))} |")
    table = ["| case | object | mechanisms | dp [kPa] | n | holding force F [N] | F / (dp A) | holds (95% above 0) | "
             "seeds holding | suction's largest pull [N] | sealed area [mm^2] | membrane's lowest point below the object's top [mm] | "
             "volume change in the vacuum [%] | per seed (seeds in order) [N] |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"] + rows

    # The plan's differences (Welch) and the vacuum's steps.
    def welch(a, b):  # b - a
        return rules.difference("Welch", st[a]["hf"], st[b]["hf"])

    pairs = [("both_dp0", "both_dp25", "the vacuum: 0 -> 25 kPa"), ("both_dp25", "both_dp50", "25 -> 50 kPa"),
             ("both_dp50", "both_dp75", "50 -> 75 kPa"),
             ("none_dp50", "friction_dp50", "friction alone - neither"),
             ("none_dp50", "suction_dp50", "suction alone - neither"),
             ("friction_dp50", "both_dp50", "both - friction alone (what suction adds)"),
             ("suction_dp50", "both_dp50", "both - suction alone (what friction adds)"),
             ("none_dp50", "shape_dp50", "sphere, shape alone - cylinder, neither (what the sphere's shape adds)"),
             ("both_dp50", "all_dp50", "sphere - cylinder, all mechanisms on"),
             ("d8_dp50", "both_dp50", "the object's size: 8 -> 12 mm"), ("both_dp50", "d16_dp50", "12 -> 16 mm")]
    dtable = ["| difference | n | mean ± Welch 95% [N] | resolved from 0 |", "|---|---|---|---|"]
    diffs = {}
    for a, b, what in pairs:
        d = welch(a, b)
        diffs[(a, b)] = d
        res = rules.resolved(d)
        dtable.append(f"| {what} (`{b}` - `{a}`) | {d.n} | {fmt(d.d if d.d is not None else math.nan, d.h if d.ok else math.nan)} | "
                      f"{'-' if res is None else ('yes' if res == 'resolved' else 'no')} |")
    steps = [rules.direction(diffs[(a, b)], +1) for a, b, _ in pairs[:3]]
    vac_verdict = rules.verdict_direction(steps)
    # The size's steps: the force up, F / (dp A) down.
    size_pairs = list(zip(SIZES, SIZES[1:]))
    size_f = rules.verdict_direction([rules.direction(diffs[(a, b)], +1) for (a, _), (b, _) in size_pairs])
    size_r_d = [rules.difference("Welch", st[a]["ratio"], st[b]["ratio"]) for (a, _), (b, _) in size_pairs]
    size_r = rules.verdict_direction([rules.direction(d, -1) for d in size_r_d])
    size_r_text = ", ".join(f"{da} -> {db} mm {d.d:+.3f} ± {d.h:.3f}" if d.ok else f"{da} -> {db} mm pending"
                            for ((_, da), (_, db)), d in zip(size_pairs, size_r_d))
    prop, _ = proportionality({c: st[c]["ratio"] for c in ("both_dp25", "both_dp50", "both_dp75")})

    # The figure: against the vacuum, and the mechanisms at 50 kPa.
    fig, ax = plt.subplots(1, 3, figsize=(17, 4.2))
    vac = [c for c in ("both_dp0", "both_dp25", "both_dp50", "both_dp75") if st[c]["n"]]
    for c in vac:
        ax[0].plot([st[c]["dp"]] * st[c]["n"], list(st[c]["hf"].values()), "o", color="0.6", ms=4)
    if vac:
        ms = [mean_ci(st[c]["hf"].values()) for c in vac]
        ax[0].errorbar([st[c]["dp"] for c in vac], [m for m, _, _ in ms],
                       yerr=[h if math.isfinite(h) else 0 for _, h, _ in ms], fmt="s-", capsize=4, color="C0",
                       label="mean, 95% interval")
    ax[0].set_xlabel("underpressure dp [kPa]")
    ax[0].set_ylabel("holding force [N]")
    ax[0].set_title("cylinder, friction + suction (press 16 N)")
    ax[0].grid(alpha=0.3)
    ax[0].legend(fontsize=8)
    mech = [c for c in ("both_dp50", "friction_dp50", "suction_dp50", "none_dp50", "all_dp50", "shape_dp50")]
    names = {"both_dp50": "cylinder\nboth", "friction_dp50": "cylinder\nfriction", "suction_dp50": "cylinder\nsuction",
             "none_dp50": "cylinder\nneither", "all_dp50": "sphere\nall", "shape_dp50": "sphere\nshape"}
    for k, c in enumerate(mech):
        m, h, n = mean_ci(st[c]["hf"].values())
        if n:
            ax[1].bar(k, m, yerr=h if math.isfinite(h) else 0, capsize=4, color="C1" if st[c]["obj"] == "sphere" else "C0",
                      alpha=0.6)
            ax[1].plot([k] * n, list(st[c]["hf"].values()), "o", color="0.4", ms=4)
    ax[1].set_xticks(range(len(mech)), [names[c] for c in mech], fontsize=8)
    ax[1].set_ylabel("holding force [N]")
    ax[1].set_title("the mechanisms at 50 kPa")
    ax[1].grid(alpha=0.3, axis="y")
    sizes = [(c, d) for c, d in SIZES if st[c]["n"]]
    for c, d in sizes:
        ax[2].plot([d] * st[c]["n"], list(st[c]["hf"].values()), "o", color="0.6", ms=4)
    if sizes:
        ms = [mean_ci(st[c]["hf"].values()) for c, _ in sizes]
        ax[2].errorbar([d for _, d in sizes], [m for m, _, _ in ms], yerr=[h if math.isfinite(h) else 0 for _, h, _ in ms],
                       fmt="s-", capsize=4, color="C0", label="F, mean and 95% interval")
        rs = [mean_ci(st[c]["ratio"].values()) for c, _ in sizes]
        twin = ax[2].twinx()
        twin.errorbar([d + 0.25 for _, d in sizes], [m for m, _, _ in rs],  # beside F's bars yerr=[h if math.isfinite(h) else 0 for _, h, _ in rs],
                      fmt="^--", capsize=4, color="C3", label="F / (dp A)")
        twin.set_ylabel("F / (dp A) [-]", color="C3")
        twin.set_ylim(bottom=0)
        ax[2].legend(loc="upper left", fontsize=8)
        twin.legend(loc="upper right", fontsize=8)
    ax[2].set_xlabel("the cylinder's diameter [mm]")
    ax[2].set_ylabel("holding force [N]")
    ax[2].set_ylim(bottom=0)
    ax[2].set_title("against the object's size (50 kPa)")
    ax[2].grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(os.path.join(root, "docs", "devices_gripper_jamming_study.png"), dpi=110)
    plt.close(fig)

    n_done = sum(s["n"] for s in st.values())
    planned = sum(rules.planned_seeds(os.path.join(root, "studies", "devices", f"{c[0]}.toml")) or 0 for c in CASES)
    areas = {}
    for study, case, _, _, obj, _, _ in CASES:
        for r in data[study].get(case, []):
            areas.setdefault(obj, r.get("object_area"))
    area_text = ", ".join(f"the {o}'s {a:.4g} m^2" for o, a in sorted(areas.items()) if a)
    verdicts = [
        f"- **Against the vacuum** (each step up resolved upwards, Welch): {rules.verdict_text(vac_verdict)}.",
        "- **Proportional to dp** (F / (dp A) at 25 and at 75 kPa against its 50 kPa mean, the ratio's 95% "
        f"interval within +-10%): {prop}.",
        f"- The cylinder's weight in a plastic of 1000 kg/m^3 is {OBJECT_WEIGHT * 1e3:.1f} mN: the default "
        f"(`both_dp50`) holds {mean_ci(st['both_dp50']['hf'].values())[0] / OBJECT_WEIGHT:.0f} times it in the mean."
        if st["both_dp50"]["n"] else "- The default's runs are pending.",
        f"- **Against the object's size** (each step 8 -> 12 -> 16 mm resolved upwards, Welch): "
        f"{rules.verdict_text(size_f)}. **F / (dp A) against the size** (each step resolved downwards, Welch: "
        f"{size_r_text}): {rules.verdict_text(size_r)}.",
    ]
    text = "\n".join(
        [f"Made by `scripts/device_study.sh gripper_vacuum`, `... gripper_mechanisms`, `... gripper_mechanisms_sphere`, "
         f"`... gripper_size` and `python3 -m vppdem.report device gripper_jamming` from the records in `docs/data/devices/` "
         f"({n_done} of {planned} runs: {len(CASES)} cases x seeds 1-5). Mean ± the 95% Student-t half-width over the seeds; "
         f"A the object's cross-section normal to the pull, its facets projected ({area_text}); the membrane's lowest "
         "point: its lowest particle centre at the end of the vacuum, below the object's top (on the sphere the bag's skirt, "
         "outside the object, not a wrap: the slices).",
         "", *table, "", "The plan's differences (Welch's 95% interval; each case's runs have their own fills' "
         "paths from the press on):", "", *dtable, "", *verdicts, "",
         "![The jamming gripper's mechanisms](devices_gripper_jamming_study.png)"])
    replace_block("gripper_jamming", text)
    return st


BROWN25 = "Brown et al. 2010 (the gripper 25 grains across)"


def trend_rows(load):
    """The rows of "Beside the published trends" from the three jamming studies (published, what it
    says, the model, verdict); [] while they have no records. Every verdict by the plan's rules."""
    data = {s: load(s) for s in STUDIES}
    if not any(data.values()):
        return []
    hf = {case: values(data[study].get(case, []), "holding_force") for study, case, *_ in CASES}

    def m(case):
        mm, h, n = mean_ci(hf[case].values())
        return "pending" if not n else (f"{mm:.3f} ± {h:.3f} N" if math.isfinite(h) else f"{mm:.3f} N")

    def welch(a, b):  # b - a
        return rules.difference("Welch", hf[a], hf[b])

    def dN(d):
        return (f"{d.d:+.3f} ± {d.h:.3f} N" if d.ok else "pending")

    rows = []
    steps = [welch("both_dp0", "both_dp25"), welch("both_dp25", "both_dp50"), welch("both_dp50", "both_dp75")]
    vdir = rules.verdict_direction([rules.direction(d, +1) for d in steps])
    ratio = {c: values(data["gripper_vacuum"].get(c, []), "holding_ratio") for c in ("both_dp25", "both_dp50", "both_dp75")}
    r = {c: mean_ci(v.values()) for c, v in ratio.items()}
    prop, ptext = proportionality(ratio)
    rtext = ", ".join(f"{fmt(*r[c][:2])} at {k} kPa" for c, k in (("both_dp25", 25), ("both_dp50", 50), ("both_dp75", 75)))
    rows.append((BROWN25, "the holding force of each mechanism scales with the jammed state's strength, which is "
                 "proportional to the pressure difference: F roughly ∝ dp",
                 f"{m('both_dp0')} at 0 kPa, {m('both_dp25')} at 25, {m('both_dp50')} at 50, {m('both_dp75')} at 75 kPa "
                 f"(steps, Welch: {', '.join(dN(d) for d in steps)}); F / (dp A) {rtext}",
                 f"direction: {vdir}; proportionality: {prop} ({ptext})"))
    fr, su = welch("none_dp50", "friction_dp50"), welch("none_dp50", "suction_dp50")
    sh = rules.one_sample(list(hf["shape_dp50"].values()), 0.0)
    shape_holds = sh.ok and sh.d - sh.h > 0
    vfr = rules.verdict_direction([rules.direction(fr, +1)])
    vsu = rules.verdict_direction([rules.direction(su, +1)])
    if not sh.ok:
        vsh = "open (runs pending)"
    elif shape_holds:
        vsh = "reproduced (the sphere's shape alone holds: its interval above 0)"
    else:
        above = sum(1 for v in hf["shape_dp50"].values() if v > 0)
        vsh = rules.label("nothing measured", f"the sphere's shape alone holds {m('shape_dp50')} ({above} of "
                                              f"{len(hf['shape_dp50'])} seeds above 0): the bag reaches the sphere "
                                              "only down to its equator (the design runs' slices), so no case wraps an undercut "
                                              "to interlock with")
    rows.append((BROWN25, "three mechanisms: friction, interlocking, suction, each contributing",
                 f"on the cylinder at 50 kPa: friction alone {m('friction_dp50')}, suction alone {m('suction_dp50')}, "
                 f"neither {m('none_dp50')}, both {m('both_dp50')}; on the sphere: all three {m('all_dp50')}, the shape "
                 f"alone {m('shape_dp50')}",
                 f"friction: {vfr} (alone - neither {dN(fr)}); suction: {vsu} (alone - neither {dN(su)}); "
                 f"interlocking: {vsh}"))
    return rows
