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
            interval (the lambdas of a seed cycle one sample: paired).
"""
import csv
import math
import os

from . import rules

LAMBDAS = (0.1, 0.2, 0.4)
CYCLES = (2, 3)
SHARES = (("total", "events' share of the dissipation"), ("friction", "friction in events / friction"),
          ("damping", "local damping in events / local damping"), ("time", "share of the time in events"))


def case_keys(name):
    """{key: value} of a case folder's name (key=value parts joined by '_'; the keys' own '_' written
    '-'), numbers as floats."""
    out = {}
    for part in name.split("_"):
        if "=" in part:
            k, v = part.split("=", 1)
            try:
                out[k] = float(v)
            except ValueError:
                out[k] = v
    return out


def run_shares(cycles_csv):
    """The shares of one run over CYCLES from its cycles.csv ({name: value}), None where the file
    lacks the events columns, a cycle of CYCLES or any dissipation."""
    if not os.path.exists(cycles_csv):
        return None
    with open(cycles_csv) as f:
        rows = [r for r in csv.DictReader(f) if r.get("cycle") and int(float(r["cycle"])) in CYCLES]
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


def load(folder):
    """{(lambda, seed): shares} of the study's published runs."""
    runs = {}
    if not os.path.isdir(folder):
        return runs
    for d in sorted(os.listdir(folder)):
        k = case_keys(d)
        lam, seed = k.get("process.local-damping"), k.get("simulation.seed")
        if lam is None or seed is None:
            continue
        sh = run_shares(os.path.join(folder, d, "cycles.csv"))
        if sh is not None:
            runs[(float(lam), int(seed))] = sh
    return runs


def slope(xs, ys):
    """The least-squares slope of ys against xs."""
    mx, my = sum(xs) / len(xs), sum(ys) / len(ys)
    sxx = sum((x - mx) ** 2 for x in xs)
    return sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sxx


def analyse(runs, planned=5):
    """(C33's verdict, its text, the table's lines) from load()'s runs; `planned` the study's seeds."""
    by_lam = {lam: [sh for (l, _), sh in sorted(runs.items()) if l == lam] for lam in LAMBDAS}
    rows = ["| lambda | runs | " + " | ".join(label for _, label in SHARES) + " |",
            "|---|---|" + "---|" * len(SHARES)]
    outcomes = []
    for lam in LAMBDAS:
        cells = []
        for key, _ in SHARES:
            n, m, _, h = rules.interval([sh[key] for sh in by_lam[lam]])
            cells.append("-" if not n else (f"{m:.3f} ± {h:.3f}" if n >= 2 and math.isfinite(h) else f"{m:.3f}"))
        rows.append(f"| {lam:g} | {len(by_lam[lam])} | " + " | ".join(cells) + " |")
        d = rules.one_sample([sh["total"] for sh in by_lam[lam]], 0.5)
        outcomes.append(None if not d.ok else ("above" if d.d - d.h > 0 else "below" if d.d + d.h < 0 else "unresolved"))
    seeds = sorted({s for (_, s) in runs if all((lam, s) in runs for lam in LAMBDAS)})
    slope_text = []
    for key, label in SHARES[:3]:
        ss = [slope([math.log(lam) for lam in LAMBDAS], [runs[(lam, s)][key] for lam in LAMBDAS]) for s in seeds]
        d = rules.one_sample(ss, 0.0)
        slope_text.append(f"{label} {d.d:+.3f} ± {d.h:.3f}" if d.ok else f"{label} pending")
    done = sum(len(v) for v in by_lam.values())
    if None in outcomes:
        verdict = "open (runs pending)"
    elif "below" in outcomes:
        verdict = "contradicted"
    elif all(o == "above" for o in outcomes):
        verdict = "reproduced"
    else:
        verdict = "consistent, not established"
    text = (f"the events' share of the dissipation (cycles {CYCLES[0]}-{CYCLES[-1]}, detector 3 x the cycle's median "
            f"kinetic energy) at lambda " + " / ".join(f"{lam:g}" for lam in LAMBDAS) + ": "
            + "; ".join({None: "pending", "above": "above 0.5", "below": "below 0.5",
                         "unresolved": "not resolved from 0.5"}[o] for o in outcomes)
            + " (95% over the seeds); slopes against ln lambda "
            "(paired over " + f"{len(seeds)} seeds): " + ", ".join(slope_text)
            + f" ({done} of {planned * len(LAMBDAS)} runs)")
    return verdict, text, rows
