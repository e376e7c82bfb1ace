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


def load(folder, key="process.local-damping"):
    """{(the case's value of key, seed): shares} of a study's published runs (the mechanisms study:
    lambda; the velocity study, key "process.velocity": the loading speed)."""
    runs = {}
    if not os.path.isdir(folder):
        return runs
    for d in sorted(os.listdir(folder)):
        k = case_keys(d)
        x, seed = k.get(key), k.get("simulation.seed")
        if x is None or seed is None:
            continue
        sh = run_shares(os.path.join(folder, d, "cycles.csv"))
        if sh is not None:
            runs[(float(x), int(seed))] = sh
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
    """The least-squares slope of ys against xs."""
    mx, my = sum(xs) / len(xs), sum(ys) / len(ys)
    sxx = sum((x - mx) ** 2 for x in xs)
    return sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sxx


def analyse(runs, planned=5):
    """(C33's verdict, its text, the table's lines) from load()'s runs; `planned` the study's seeds."""
    by_lam = {lam: [sh for (l, _), sh in sorted(runs.items()) if l == lam] for lam in LAMBDAS}
    rows = table(runs, LAMBDAS, "lambda")
    outcomes = []
    for lam in LAMBDAS:
        d = rules.one_sample([sh["total"] for sh in by_lam[lam]], 0.5)
        outcomes.append(None if not d.ok else ("above" if d.d - d.h > 0 else "below" if d.d + d.h < 0 else "unresolved"))
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
            + " (95% over the seeds); " + slopes(runs, LAMBDAS, "lambda")
            + f" ({done} of {planned * len(LAMBDAS)} runs)")
    return verdict, text, rows
