"""The dissipation split into rearrangement events and the creep between them (issue 60, item 3):
the plan of studies/paper/mechanisms.toml, fixed before its runs, applied to the published records
of that study (docs/data/paper/mechanisms/<case>/cycles.csv).

Per run, over cycles 2-3 (cycle 1 compacts), from the events columns the damper writes with
analysis.event_threshold (vpp/analysis/events.h: a record is in an event where its kinetic energy
exceeds 3 times the cycle's median):
  total     the events' share of the dissipation, (friction + damping + viscous in events) / all three;
  friction  friction_in_events / friction_dissipation;
  damping   damping_in_events / damping_dissipation;
  time      the share of the record intervals inside events (event_fraction, the cycles' mean).
The plan's tests, each by vppdem.report.rules:
  C33       (the dissipation is the damping of grains released in rearrangements) reproduced where the
            events' share of the total lies above 0.5 at every lambda (the 95% Student-t interval over
            the seeds), contradicted where it lies below 0.5 at one lambda, else consistent, not
            established; open while a lambda has fewer than 2 runs;
  slopes    per seed the least-squares slope of each share against ln lambda, their mean with its 95%
            interval (the lambdas of a seed cycle one sample: paired); the same against ln v over
            mechanisms_velocity.toml's 0.005 and 0.02 m/s and this study's lambda 0.2 (0.01 m/s).
"""
import math
import os

from ..records import read_table
from . import rules, stats

LAMBDAS = (0.1, 0.2, 0.4)
CYCLES = (2, 3)
SHARES = (("total", "events' share of the dissipation"), ("friction", "friction in events / friction"),
          ("damping", "local damping in events / local damping"), ("time", "share of the time in events"))


def run_shares(cycles_csv):
    """The shares of one run over CYCLES from its cycles.csv ({name: value}), None where the file
    lacks the events columns, a cycle of CYCLES or any dissipation."""
    if not os.path.exists(cycles_csv):
        return None
    rows = [r for r in read_table(cycles_csv)[1] if r.get("cycle") and int(float(r["cycle"])) in CYCLES]
    need = ("friction_dissipation", "damping_dissipation", "viscous_dissipation", "friction_in_events",
            "damping_in_events", "viscous_in_events", "event_fraction")
    if len(rows) != len(CYCLES) or any(not r.get(k) for r in rows for k in need):
        return None
    s = {k: sum(float(r[k]) for r in rows) for k in need}
    allc = s["friction_dissipation"] + s["damping_dissipation"] + s["viscous_dissipation"]
    if allc <= 0 or s["friction_dissipation"] <= 0 or s["damping_dissipation"] <= 0:
        return None
    return {"total": (s["friction_in_events"] + s["damping_in_events"] + s["viscous_in_events"]) / allc,
            "friction": s["friction_in_events"] / s["friction_dissipation"],
            "damping": s["damping_in_events"] / s["damping_dissipation"],
            "time": s["event_fraction"] / len(CYCLES)}


def load(folder, key="process.local_damping"):
    """{(the case's value of key, seed): shares} of a study's published runs: the finished rows of its
    summary.csv (the mechanisms study: lambda; the velocity study, key "process.velocity": the
    loading speed) and each one's cycles.csv."""
    path = os.path.join(folder, "summary.csv")
    runs = {}
    for r in (read_table(path)[1] if os.path.isfile(path) else []):
        if r.get("status") != "ok" or not r.get(key) or not r.get("simulation.seed"):
            continue
        sh = run_shares(os.path.join(folder, r["case"], "cycles.csv"))
        if sh is not None:
            runs[(float(r[key]), int(float(r["simulation.seed"])))] = sh
    return runs


def table(runs, levels, name):
    """The table's lines: per level (name's column) the runs and each share's mean ± 95% over the seeds."""
    rows = [f"| {name} | runs | " + " | ".join(label for _, label in SHARES) + " |",
            "|---|---|" + "---|" * len(SHARES)]
    for x in levels:
        shs = [sh for (l, _), sh in sorted(runs.items()) if l == x]
        cells = []
        for key, _ in SHARES:
            n, m, _, h = rules.interval([sh[key] for sh in shs])
            cells.append("-" if not n else (f"{m:.3f} ± {h:.3f}" if n >= 2 and math.isfinite(h) else f"{m:.3f}"))
        rows.append(f"| {x:g} | {len(shs)} | " + " | ".join(cells) + " |")
    return rows


def slopes(runs, levels, what):
    """Each share's least-squares slope against ln(level) per seed that has every level, the mean
    with its 95% interval over those seeds (paired): text."""
    seeds = sorted({s for (_, s) in runs if all((x, s) in runs for x in levels)})
    out = []
    for key, label in SHARES[:3]:
        ss = [slope([math.log(x) for x in levels], [runs[(x, s)][key] for x in levels]) for s in seeds]
        d = rules.one_sample(ss, 0.0)
        out.append(f"{label} {d.d:+.3f} ± {d.h:.3f}" if d.ok else f"{label} pending")
    return f"slopes against ln {what} (paired over {len(seeds)} seeds): " + ", ".join(out)


VELOCITIES = (0.005, 0.01, 0.02)  # [m/s] 0.01: the mechanisms study's lambda 0.2 runs


def velocity(lam_runs, vel_runs, planned=5):
    """(text, table lines) of the shares against the loading speed: mechanisms_velocity.toml's
    0.005 and 0.02 m/s with the mechanisms study's lambda 0.2 runs as 0.01 m/s."""
    runs = dict(vel_runs)
    runs.update({(0.01, s): sh for (lam, s), sh in lam_runs.items() if lam == 0.2})
    done = sum(1 for (x, _) in vel_runs if x in VELOCITIES)
    return (slopes(runs, VELOCITIES, "v") + f" ({done} of {planned * 2} runs of mechanisms_velocity)",
            table(runs, VELOCITIES, "v [m/s]"))


def slope(xs, ys):
    """The least-squares slope of ys against xs (stats.ols with an intercept)."""
    return stats.ols([[1.0, x] for x in xs], ys)[0][1]


def analyse(runs, planned=5):
    """(C33's verdict, its text, the table's lines) from load()'s runs; `planned` the study's seeds."""
    by_lam = {lam: [sh for (l, _), sh in sorted(runs.items()) if l == lam] for lam in LAMBDAS}
    rows = table(runs, LAMBDAS, "lambda")
    # The events' share against 0.5 per lambda, the claim's way up; a share resolved below 0.5 at one
    # lambda reverses the mechanism: 'contradicted', the mechanism rule's word for it.
    outcomes = [rules.direction(rules.one_sample([sh["total"] for sh in by_lam[lam]], 0.5), +1) for lam in LAMBDAS]
    done = sum(len(v) for v in by_lam.values())
    verdict = rules.combine(outcomes, "yes", "against").replace("not reproduced", "contradicted")
    text = (f"the events' share of the dissipation (cycles {CYCLES[0]}-{CYCLES[-1]}, detector 3 x the cycle's median "
            f"kinetic energy) at lambda " + " / ".join(f"{lam:g}" for lam in LAMBDAS) + ": "
            + "; ".join({None: "pending", "yes": "above 0.5", "against": "below 0.5",
                         "unresolved": "not resolved from 0.5"}[o] for o in outcomes)
            + " (95% over the seeds); " + slopes(runs, LAMBDAS, "lambda")
            + f" ({done} of {planned * len(LAMBDAS)} runs)")
    return verdict, text, rows
