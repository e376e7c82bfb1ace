"""docs/operation.md and its figures from the operation study's records (issue 23).

usage: python3 -m vppdem.report operation DATA DOCS [--runs OUT]
  DATA  the records of examples/operation/run.sh (docs/data/operation: pump/<case>/ and
        constant/<case>/ with summary.json, cycles.csv, case.toml, as `vppdem sweep --publish`
        keeps them; forces_last_cycle.csv for seed 1 at 10 and 20 Hz)
  DOCS  where operation.md and operation_*.png go (docs)
  --runs OUT  first the last cycle of forces.csv of each run in OUT/pump/<case>/ and
        OUT/constant/<case>/ (the sweeps' --out) at seed 1 and 10 or 20 Hz whose records DATA
        holds, into DATA/<study>/<case>/forces_last_cycle.csv (the header and every row of the
        largest cycle, byte for byte; a file only when it changed). Runs whose records were put
        back from DATA have no forces.csv: their published last cycle stays.

Every number comes from the runs' summary.json: W and peak force of the testing machine's loop
(summary.json "air", W_machine and peak_force_machine: grains + foil + the lid's -dp A, the
machine force that an experiment measures) of the last cycle, and the underpressure's range over
the samples. Means and 95% intervals over the seeds with Student's t (vppdem.report.stats);
pump minus constant paired by seed (the same prepared sample). What the page says of an effect on
W (none within the margin, none resolved, how large a change the intervals leave open) and its
verdicts are vppdem.report.rules' (the equivalence rule on the paired difference); the page
states them in "Decision rules". Runs under /usr/bin/python3.
"""
import json
import math
import os
import sys
from dataclasses import dataclass

from ..records import RecordError, fail, read_csv
from . import rules
from .stats import interval

P_ATM = 101325.0
COMMAND = "bash examples/operation/run.sh"
# The runs whose last cycle is kept (forces_last_cycle.csv, drawn by operation_onset.png and read
# by the reversal text): seed 1 at these frequencies, both waveforms, both studies.
LAST_CYCLE_SEED = 1
LAST_CYCLE_FREQUENCIES = (10.0, 20.0)


def parse_name(name):
    # process.waveform=W_process.frequency=F_simulation.seed=S
    try:
        w = name.split("process.waveform=")[1].split("_")[0]
        f = float(name.split("process.frequency=")[1].split("_")[0])
        s = int(name.split("simulation.seed=")[1])
    except (IndexError, ValueError):
        return None
    return dict(waveform=w, frequency=f, seed=s)


def load(data, study):
    runs = {}
    root = os.path.join(data, study)
    if not os.path.isdir(root):
        return runs
    for name in sorted(os.listdir(root)):
        k = parse_name(name)
        path = os.path.join(root, name, "summary.json")
        if k is None or not os.path.isfile(path):
            continue
        with open(path) as f:
            s = json.load(f)
        if "air" not in s:
            fail(f"{path}: no \"air\" record (a run of a vppdem before summary.json had it, or output.air off)", 2)
        last = s["cycles"][-1]
        air = s["air"]["cycles"][-1]
        set_dp = s["air"]["underpressure_set"]
        allc = s["air"]["cycles"]
        cyc = os.path.join(root, name, "cycles.csv")
        runs[(k["waveform"], k["frequency"], k["seed"])] = dict(
            name=name, W=last["W"], W_machine=air["W_machine"], peak=air["peak_force_machine"],
            dp_min=min(c["underpressure_min"] for c in allc), dp_max=max(c["underpressure_max"] for c in allc),
            dp_set=set_dp, gas_min=min(c["gas_volume_min"] for c in allc),
            gas_max=max(c["gas_volume_max"] for c in allc), inertial=s["inertial_number"],
            quasi=s["quasi_static"], cycles=len(s["cycles"]), radius=s["inputs"]["damper.radius"],
            amplitude=s["inputs"]["process.amplitude"], pump_speed=s["inputs"]["process.pump_speed"],
            restitution=s["inputs"]["grains.restitution"], dt=s["dt"], run_seconds=s["run_seconds"],
            cycles_bytes=open(cyc, "rb").read() if os.path.isfile(cyc) else None,
            forces=os.path.join(root, name, "forces_last_cycle.csv"))
    return runs


def last_cycle(forces):
    """The last cycle of a forces.csv as text: its header line and every row whose `cycle` equals
    the largest cycle in the file, each ending in a newline, the lines as they are in the file.
    Byte for byte what examples/operation/run.sh's awk wrote before (cycles compared as numbers, the
    last `cycle` column of the header counting; no row when no cycle exceeds 0)."""
    with open(forces, newline="") as f:
        text = f.read()
    lines = text.split("\n")
    if lines and lines[-1] == "":
        lines.pop()
    if not lines:
        raise RecordError(f"{forces} is empty")
    names = lines[0].split(",")
    if "cycle" not in names:
        raise RecordError(f"{forces}: no column 'cycle' (columns: {lines[0]})")
    k = len(names) - 1 - names[::-1].index("cycle")
    rows, top = [], 0.0
    for n, line in enumerate(lines[1:], start=2):
        cells = line.split(",")
        try:
            c = float(cells[k])
        except (IndexError, ValueError):
            raise RecordError(f"{forces}, line {n}: no cycle number in column {k + 1}") from None
        rows.append((c, line))
        top = max(top, c)
    return "".join(line + "\n" for line in [lines[0]] + [line for c, line in rows if c == top])


def publish_last_cycles(runs, data):
    """forces_last_cycle.csv of the runs in RUNS/<study>/<case>/ that are kept (LAST_CYCLE_SEED at
    LAST_CYCLE_FREQUENCIES) and finished, into DATA/<study>/<case>/ where DATA holds the case's
    records; through a temporary name, and only when the text changed. Returns (written, same)."""
    written = same = 0
    for study in ("pump", "constant"):
        root = os.path.join(runs, study)
        if not os.path.isdir(root):
            continue
        for name in sorted(os.listdir(root)):
            k = parse_name(name)
            if k is None or k["seed"] != LAST_CYCLE_SEED or k["frequency"] not in LAST_CYCLE_FREQUENCIES:
                continue
            run = os.path.join(root, name)
            dest = os.path.join(data, study, name)
            if not (os.path.isfile(os.path.join(run, "summary.json")) and os.path.isfile(os.path.join(run, "forces.csv"))
                    and os.path.isfile(os.path.join(dest, "summary.json"))):
                continue
            text = last_cycle(os.path.join(run, "forces.csv"))
            path = os.path.join(dest, "forces_last_cycle.csv")
            if os.path.isfile(path) and open(path, newline="").read() == text:
                same += 1
                continue
            with open(path + ".part", "w", newline="") as f:
                f.write(text)
            os.replace(path + ".part", path)
            written += 1
    return written, same


def peak_speed(waveform, f, amplitude):
    return (2.0 if waveform == "triangle" else math.pi) * amplitude * f


def ci(vals, digits=0, unit=""):
    n, m, sd, h = interval(vals)
    if n == 0:
        return "-"
    u = f" {unit}" if unit else ""
    if n < 2 or not math.isfinite(h):
        return f"{m:.{digits}f}{u} (n = {n})"
    return f"{m:.{digits}f} +- {h:.{digits}f}{u}"


def save(fig, docs, name):
    """Writes the figure to DOCS/NAME through a temporary name; returns NAME."""
    import matplotlib.pyplot as plt
    fig.tight_layout()
    p = os.path.join(docs, name)
    fig.savefig(p + ".part.png", dpi=110)
    os.replace(p + ".part.png", p)
    plt.close(fig)
    return name


def figures(pump, const, docs, waveforms, freqs):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out = []
    fig, ax = plt.subplots(1, 3, figsize=(13.5, 4.0))
    for w, mk in zip(waveforms, ("o", "s")):
        xs, rows = [], []
        for f in freqs:
            vals = [r for (ww, ff, s), r in pump.items() if ww == w and ff == f]
            if vals:
                xs.append(f)
                rows.append(vals)
        for a, q, scale in ((ax[0], "W_machine", 1.0), (ax[1], "peak", 1.0)):
            st = [interval([r[q] * scale for r in v]) for v in rows]
            a.errorbar(xs, [s[1] for s in st], yerr=[0 if not math.isfinite(s[3]) else s[3] for s in st],
                       marker=mk, capsize=3, label=f"pump, {w}")
        exc = [max(100.0 * max(r["dp_max"] - r["dp_set"], r["dp_set"] - r["dp_min"]) / r["dp_set"] for r in v) for v in rows]
        ax[2].plot(xs, exc, marker=mk, label=w)
        cx, cst, cpk = [], [], []
        for f in freqs:
            vals = [r for (ww, ff, s), r in const.items() if ww == w and ff == f]
            if vals:
                cx.append(f)
                cst.append(interval([r["W_machine"] for r in vals]))
                cpk.append(interval([r["peak"] for r in vals]))
        if cx:
            for a, st in ((ax[0], cst), (ax[1], cpk)):
                a.errorbar(cx, [s[1] for s in st], yerr=[0 if not math.isfinite(s[3]) else s[3] for s in st],
                           marker=mk, mfc="none", ls=":", capsize=3, label=f"constant dp, {w}")
    ax[0].set_ylabel("W of the machine's loop [J/m$^2$] (last cycle)")
    ax[1].set_ylabel("peak machine force [N] (zeroed)")
    ax[2].set_ylabel("largest |dp - dp_set| / dp_set [%] (any seed)")
    for a in ax:
        a.set_xscale("log")
        a.set_xlabel("frequency [Hz]")
        a.grid(alpha=0.3)
    ax[0].legend(fontsize=8)
    ax[2].legend(fontsize=8)
    fig.suptitle(f"The damper with a 2 m$^3$/h pump, 0.06 MPa: mean and 95% interval over the seeds ({COMMAND})",
                 fontsize=9)
    out.append(save(fig, docs, "operation_frequency.png"))

    # The onset of compression: the last cycle's loop, pump against constant, seed 1.
    shown = [(w, f) for f in (20.0, 10.0) for w in waveforms
             if os.path.isfile(pump.get((w, f, 1), {}).get("forces", "")) and
             os.path.isfile(const.get((w, f, 1), {}).get("forces", ""))]
    if shown:
        fig, ax = plt.subplots(2, len(shown), figsize=(3.6 * len(shown), 6.4), squeeze=False)
        for j, (w, f) in enumerate(shown):
            for lab, runs, ls in (("pump", pump, "-"), ("constant dp", const, "--")):
                c = read_csv(runs[(w, f, 1)]["forces"])
                ax[0][j].plot([1e3 * d for d in c["displacement"]], c["force_machine_zeroed"], ls, lw=1, label=lab)
                ax[1][j].plot([1e3 * d for d in c["displacement"]], [1e-3 * v for v in c["underpressure"]], ls, lw=1,
                              label=lab)
            ax[0][j].set_title(f"{w}, {f:g} Hz, seed 1 (last cycle)", fontsize=9)
            ax[1][j].set_xlabel("displacement [mm] (compression positive)")
            ax[0][j].grid(alpha=0.3)
            ax[1][j].grid(alpha=0.3)
        ax[0][0].set_ylabel("machine force, zeroed [N]")
        ax[1][0].set_ylabel("underpressure [kPa]")
        ax[0][0].legend(fontsize=8)
        fig.suptitle(f"Where the pump falls behind: the loop and dp ({COMMAND})", fontsize=9)
        out.append(save(fig, docs, "operation_onset.png"))
    return out


def reversal_text(pump, f):
    """Where in the cycle the triangle's dp leaves the set point (seed 1's last cycle at f)."""
    r = pump.get(("triangle", f, 1))
    if not r or not os.path.isfile(r["forces"]):
        return ""
    c = read_csv(r["forces"])
    phase = [(t * f) % 1.0 for t in c["time"]]
    below = [ph for ph, dp in zip(phase, c["underpressure"]) if dp < r["dp_set"]]
    if not below:
        return ""
    near = sum(1 for ph in below if ph < 0.1 or 0.5 <= ph < 0.6)
    k = min(range(len(phase)), key=lambda i: c["underpressure"][i])
    return (f" In seed 1's last cycle at {f:g} Hz, {near} of the {len(below)} samples with dp below the set point "
            "lie within a tenth of a cycle after a reversal (phase 0: the onset of compression, where the paper "
            f"saw its mismatch; 0.5: the onset of extension), and the deepest dip is at phase {phase[k]:.2f} "
            f"({1e3 * c['displacement'][k]:.1f} mm).")


def w_by_seed(runs, w, f):
    """{seed: W of the machine's loop} of the runs at waveform w and frequency f."""
    return {s: r["W_machine"] for (ww, ff, s), r in runs.items() if ww == w and ff == f}


def study_seeds(docs, study):
    """The seeds examples/operation/STUDY.toml fixed before its runs (rules.planned_seeds), the
    repository's study file beside DOCS' parent, else the source tree's."""
    from . import source_dir
    for root in (os.path.dirname(os.path.abspath(docs)), source_dir()):
        n = rules.planned_seeds(os.path.join(root, "examples", "operation", f"{study}.toml"))
        if n is not None:
            return n
    return "?"


def frequency_statement(diffs, f0):
    """The frequency's effect on W by the equivalence rule: diffs [(waveform, f, paired difference
    against f0)]. The claim of no effect (W independent of the frequency) is reproduced only where
    every interval lies within the margin; the text names what the intervals resolve and what they
    do not exclude."""
    bands = [rules.band(d) for _, _, d in diffs]
    verdict = rules.verdict_equivalence(bands)
    res = [f"{w} {f:g} Hz" for (w, f, d), b in zip(diffs, bands) if b in ("resolved", "beyond")]
    within = [f"{w} {f:g} Hz" for (w, f, d), b in zip(diffs, bands) if b == "within"]
    reach = [(rules.reach(d), w, f) for w, f, d in diffs if rules.reach(d) is not None]
    widest = max(reach) if reach else None
    text = (f"a change from {f0:g} Hz resolved at {', '.join(res)}" if res else
            f"no change from {f0:g} Hz resolved at any frequency")
    if within:
        text += f"; within the +-{100 * rules.MARGIN:.0f}% margin at {', '.join(within)}"
    if widest:
        lo = min(r for r, _, _ in reach)
        text += (f"; changes up to {100 * lo:.0f}-{100 * widest[0]:.0f}% not excluded (the intervals' reach, "
                 f"in % of W at {f0:g} Hz; the widest {widest[1]} {widest[2]:g} Hz)")
    return (f"{text}. That W does not depend on the frequency is **{verdict}** (the equivalence rule, "
            f"+-{100 * rules.MARGIN:.0f}%: {len(within)} of {len(diffs)} intervals lie within the margin).")


def page_rules(plan_pump, plan_constant):
    """The page's "## Decision rules" section (vppdem.report.rules.section)."""
    return rules.section(rules.PageRules(
        module="vppdem.report.operation",
        tests=[("paired", "every difference on this page: all cases of a seed cycle its one prepared sample, the "
                          "constant-dp twins by samples_from"),
               ("equivalence", "the frequency's effect on W against the slowest frequency, and the pump's, pump "
                               "minus constant dp; the reference: W at the slowest frequency, or with constant dp")],
        which_w="W of the testing machine's loop (summary.json \"air\" `W_machine`: grains + foil + the lid's "
                "-dp A) of the last cycle (cycle 3) of each run; not every run is stationary by then, and none is "
                "extrapolated.",
        planned=f"{plan_pump} per case (`seeds` of examples/operation/pump.toml; constant.toml: {plan_constant}), "
                "fixed before the runs.",
        labels=[],
        fixed_before=["the grid (waveforms, 1-20 Hz, the constant-dp twins at 1, 5, 10, 20 Hz), the seeds and the "
                      "cycles (examples/operation/pump.toml, constant.toml), before the runs; a plan, not a decision "
                      "rule"],
        fixed_after=["the tests and the equivalence margin as this page applies them: the study ran before issue "
                     "60's rules module (vppdem.report.rules), and they were applied to its data after they had been "
                     "seen (the page said before that W 'does not depend on the frequency' from intervals of "
                     "+-12-29%, and that a 2 m^3/h pump at a quasi-static stroke 'is the constant model')"]))


@dataclass
class Study:
    """The operation study's records, read once, and what every section of the page takes from them:
    the runs by (waveform, f, seed), the grid, the damper's radius R, stroke A, pump speed S and
    cross-section, and the paired pump minus constant differences (a table's rows, read again by
    two later sections)."""
    docs: str
    pump: dict
    const: dict
    waveforms: list
    freqs: list
    any_run: dict
    R: float
    A: float
    S: float
    area: float
    pairs: dict  # (waveform, f): pump minus constant, pump_minus_constant()
    effect: dict  # (waveform, f): (interval(dW), interval(rel), identical runs, pairs, rules' difference)


def pump_minus_constant(pump, const, waveforms):
    """{(waveform, f): the paired differences pump minus constant dp at f} in the table's order
    (waveforms, then the constant twins' frequencies): dW, rel (in % of the constant run's W), dP
    (peak force), same (pairs whose cycles.csv are byte-identical), n (pairs) and d (the rules'
    paired difference of W)."""
    out = {}
    for w in waveforms:
        for f in sorted({k[1] for k in const}):
            pairs = [(pump[k], const[k]) for k in const if k[0] == w and k[1] == f and k in pump]
            if not pairs:
                continue
            out[(w, f)] = dict(
                same=sum(1 for a, b in pairs
                         if a["cycles_bytes"] is not None and a["cycles_bytes"] == b["cycles_bytes"]),
                dW=[a["W_machine"] - b["W_machine"] for a, b in pairs],
                rel=[100.0 * (a["W_machine"] / b["W_machine"] - 1.0) for a, b in pairs],
                dP=[a["peak"] - b["peak"] for a, b in pairs],
                n=len(pairs),
                d=rules.difference("paired", w_by_seed(const, w, f), w_by_seed(pump, w, f)))
    return out


def read_study(data, docs):
    """DATA's pump and constant records as a Study; fails when DATA holds no finished pump run."""
    pump, const = load(data, "pump"), load(data, "constant")
    if not pump:
        fail(f"no finished run in {data}/pump: run bash examples/operation/run.sh first", 2)
    waveforms = [w for w in ("triangle", "sine") if any(k[0] == w for k in pump)]
    any_run = next(iter(pump.values()))
    R = any_run["radius"]
    pairs = pump_minus_constant(pump, const, waveforms)
    return Study(docs=docs, pump=pump, const=const, waveforms=waveforms,
                 freqs=sorted({k[1] for k in pump}), any_run=any_run, R=R, A=any_run["amplitude"],
                 S=any_run["pump_speed"], area=math.pi * R * R, pairs=pairs,
                 effect={k: (interval(p["dW"]), interval(p["rel"]), p["same"], p["n"], p["d"])
                         for k, p in pairs.items()})


# The page's sections, in its order: each takes the Study and returns its lines.

def section_question(c):
    """The title, the generated-by line and the question."""
    L = []
    L.append("# The damper at its working frequencies, with the air inside")
    L.append("")
    L.append(f"Generated by `{COMMAND}` (`python3 -m vppdem.report operation`) from the runs in `docs/data/operation/` "
             "(do not edit by hand; the study files are `examples/operation/pump.toml` and `constant.toml`).")
    L.append("")
    L.append("## The question")
    L.append("The paper holds the underpressure constant and tests at 3.33e-4 m/s. A VPP damper in service is "
             "a sealed foil kept at underpressure by a pump through a regulator, cycled at 1-20 Hz. Compressing "
             "it shrinks the gas in its pores; when the pump cannot draw that gas away as fast as the stroke "
             "squeezes it, the inside pressure rises, dp falls, and the damper softens just when it is loaded. "
             "This study measures where that starts and what it costs, with the pump model of "
             "docs/damper.md (\"The air inside\").")
    L.append("")
    return L


def section_runs(c):
    """The runs section: the damper, the pump, the dissipation, the grid, which W."""
    any_run, R, A, S = c.any_run, c.R, c.A, c.S
    L = []
    L.append("## The runs")
    L.append(f"- The paper's damper (radius {1e3 * R:g} mm, the calibrated defaults) at dp = 0.06 MPa, stroke "
             f"{1e3 * A:g} mm, {any_run['cycles']} cycles; the last cycle's loop is reported. 3 seeds: each "
             "seed's prepared sample (the default preparation) serves every case of that seed, so differences "
             "between cases of one seed are paired.")
    L.append(f"- The pump: S = {S * 3600:g} m^3/h ({S:.3g} m^3/s), a small rotary-vane pump (single-stage "
             "rotary-vane pumps for laboratory vacuum are sold at about 1-5 m^3/h; at 40 kPa absolute, far "
             "above their ultimate pressure, they run near their nominal speed). An ideal two-way regulator "
             "holds the set point: the pump draws whenever the inside pressure is above it, a bleed of the "
             "same conductance admits air whenever it is below (process.bleed_rate, 2 m^3/h). No leak.")
    L.append(f"- Dissipation: grain restitution {any_run['restitution']:g} from the vacuum on and no local "
             "damping (process.local_damping = 0; the preparation keeps its 0.2). At these speeds local damping "
             "would dissipate in proportion to the shaking, which is not the material's physics "
             "(docs/damper.md, \"Waveforms and frequency\"). 0.5 for the grains is a mid value for polymer "
             "pellets (the paper gives none); the frequency trend, not the value, is the point.")
    L.append("- Triangle (the paper's constant-speed stroke) and sine, 1 Hz (peak speeds 0.02 and 0.031 m/s: "
             "quasi-static by the inertial-number mark, below 5e-4; the table's inertial numbers) to 20 Hz; the "
             "constant-dp twin of every case at 1, 5, 10 and 20 Hz (`constant.toml`).")
    L.append("- W and the peak force are those of the **testing machine's** force, `force_machine_zeroed` = "
             "grains + foil + the lid's -dp A (summary.json \"air\": `W_machine`, `peak_force_machine`). With "
             "a constant dp the lid adds a constant and this is the W of every other page.")
    L.append("")
    return L


def section_frequency_table(c):
    """Table 1: W, peak force and dp against frequency, the pump runs."""
    pump, waveforms, freqs, A, S, area = c.pump, c.waveforms, c.freqs, c.A, c.S, c.area
    L = []
    L.append("## W, peak force and dp against frequency (pump, 2 m^3/h)")
    L.append("Mean +- 95% interval over the seeds (Student t, n - 1 degrees of freedom). dp range: the smallest "
             "and largest underpressure at any sample of any seed's run. Rigid flow / S: the gas flow a rigid "
             "cylinder would need at the stroke's peak speed (speed times cross-section) over the pump's speed; "
             "the foil bulges as the cap comes down, so the real flow is a fraction of it (below).")
    L.append("")
    L.append("| waveform | f [Hz] | peak speed [m/s] | inertial number | seeds | W [J/m^2] | peak force [N] | "
             "dp range [kPa] | largest excursion from the set point | rigid flow / S |")
    L.append("|---|---|---|---|---|---|---|---|---|---|")
    for w in waveforms:
        for f in freqs:
            rs = [r for (ww, ff, s), r in pump.items() if ww == w and ff == f]
            if not rs:
                continue
            v = peak_speed(w, f, A)
            exc = max(max(r["dp_max"] - r["dp_set"], r["dp_set"] - r["dp_min"]) for r in rs) / rs[0]["dp_set"]
            moved = sum(1 for r in rs if r["dp_min"] != r["dp_set"] or r["dp_max"] != r["dp_set"])
            L.append(f"| {w} | {f:g} | {v:.3g} | {max(r['inertial'] for r in rs):.2g} | {len(rs)} | "
                     f"{ci([r['W_machine'] for r in rs])} | {ci([r['peak'] for r in rs])} | "
                     f"{1e-3 * min(r['dp_min'] for r in rs):.3f} ... {1e-3 * max(r['dp_max'] for r in rs):.3f} | "
                     f"{exc * rs[0]['dp_set']:.3g} Pa ({exc:.1e}), {moved} of {len(rs)} runs | {v * area / S:.2f} |")
    L.append("")
    return L


def section_frequency_paired(c):
    """The frequency trend, each frequency paired by seed against the slowest."""
    pump, waveforms, freqs = c.pump, c.waveforms, c.freqs
    L = []
    f0 = freqs[0]
    L.append(f"## The frequency's own effect (paired against {f0:g} Hz, same seed, same sample)")
    L.append("W(f) - W(f0) per seed, mean +- 95% interval; an interval that excludes 0 is a change the seed "
             f"scatter cannot explain. By the rules: the equivalence rule (+-{100 * rules.MARGIN:.0f}% of W(f0)'s "
             "mean) on the paired difference of W, its interval in % of that mean (\"Decision rules\").")
    L.append("")
    L.append("| waveform | f [Hz] | pairs | W(f) - W(f0) [J/m^2] | relative | peak(f) - peak(f0) [N] | W by the rules |")
    L.append("|---|---|---|---|---|---|---|")
    for w in waveforms:
        for f in freqs[1:]:
            pairs = [(pump[(w, f, s)], pump[(w, f0, s)]) for (ww, ff, s) in pump if ww == w and ff == f and (w, f0, s) in pump]
            if not pairs:
                continue
            dW = [a["W_machine"] - b["W_machine"] for a, b in pairs]
            rel = [100.0 * (a["W_machine"] / b["W_machine"] - 1.0) for a, b in pairs]
            dP = [a["peak"] - b["peak"] for a, b in pairs]
            d = rules.difference("paired", w_by_seed(pump, w, f0), w_by_seed(pump, w, f))
            L.append(f"| {w} | {f:g} | {len(pairs)} | {ci(dW)} | {ci(rel, 1, '%')} | {ci(dP)} | "
                     f"{rules.statement_equivalence(d)} |")
    L.append("")
    return L


def section_pump_effect(c):
    """Pump against constant dp, paired (the rows of c.pairs)."""
    L = []
    L.append("## The pump's effect: pump minus constant dp (paired: same seed, same sample, same stroke)")
    L.append("\"bit for bit\": the pump run's cycles.csv is byte-identical to the constant run's (the regulator "
             "held the set point at every step, so every step was the constant model's; docs/damper.md). By the "
             f"rules: the equivalence rule (+-{100 * rules.MARGIN:.0f}% of the constant runs' mean W) on the paired "
             "difference of W.")
    L.append("")
    L.append("| waveform | f [Hz] | pairs | W pump - constant [J/m^2] | relative | peak force pump - constant [N] | "
             "identical runs | W by the rules |")
    L.append("|---|---|---|---|---|---|---|---|")
    for (w, f), p in c.pairs.items():
        L.append(f"| {w} | {f:g} | {p['n']} | {ci(p['dW'], 1)} | {ci(p['rel'], 2, '%')} | {ci(p['dP'], 1)} | "
                 f"{p['same']} of {p['n']} bit for bit | {rules.statement_equivalence(p['d'])} |")
    L.append("")
    return L


def section_paper_speed(c):
    """The paper's speed (3.33e-4 m/s): what the stroke asks of the pump, the quasi-static runs' dips,
    and the pump's effect at 1 Hz."""
    pump, freqs, A, S, area, effect = c.pump, c.freqs, c.A, c.S, c.area, c.effect
    f0 = freqs[0]
    L = []
    qs = [r for (w, f, s), r in pump.items() if f == f0 and w == "triangle"] or list(pump.values())
    swing = max(r["gas_max"] - r["gas_min"] for r in qs)
    v_paper = 3.33e-4
    flow_paper = swing / (A / v_paper)
    quasi = [r for r in pump.values() if r["quasi"]]
    qexc = max((max(r["dp_max"] - r["dp_set"], r["dp_set"] - r["dp_min"]) for r in quasi), default=0.0)
    qmoved = sum(1 for r in quasi if r["dp_min"] != r["dp_set"] or r["dp_max"] != r["dp_set"])
    # The largest dip per frequency of the triangle: does it shrink with the stroke's speed?
    def dip(f):
        rs = [r for (w, ff, s), r in pump.items() if w == "triangle" and ff == f]
        return max((r["dp_set"] - r["dp_min"] for r in rs), default=None)
    tri = [f for f in freqs if dip(f) is not None]
    dips_text = ""
    if len(tri) >= 2:
        dips_text = ("The largest dip in the triangle runs: " +
                     ", ".join(f"{dip(f):.2g} Pa at {f:g} Hz" for f in tri[:3]) + "; ")
        if dip(tri[0]) < dip(tri[1]):
            dips_text += (f"they shrink with the stroke's speed, so at the paper's stroke, "
                          f"{peak_speed('triangle', tri[0], A) / v_paper:.0f} times slower than {tri[0]:g} Hz, they "
                          f"are smaller still, if any.")
        else:
            dips_text += "they do not shrink with the stroke's speed here, so the paper's stroke may see them too."
    L.append("## At the paper's 3.33e-4 m/s")
    L.append(f"The stroke itself asks little of the pump: in the {f0:g} Hz triangle runs the gas volume swings by "
             f"{1e6 * swing:.2f} cm^3 over the {1e3 * A:g} mm stroke ({100 * swing / (area * A):.0f}% of the cap's "
             f"swept volume {1e6 * area * A:.2f} cm^3: the foil bulges as the cap comes down), so at 3.33e-4 m/s "
             f"the gas must be drawn off at about {flow_paper:.3g} m^3/s on average, {S / flow_paper:.0f} times "
             f"less than the pump's {S:.3g} m^3/s; a pump slower than about {flow_paper * 3600 * 1000:.1f} L/h "
             "would be needed to fall behind the stroke.")
    L.append("")
    L.append(f"What does move dp in the quasi-static runs ({len(quasi)} runs below the inertial-number mark) are "
             "the grains' sudden rearrangements: the pores shrink in short bursts, much faster than the stroke's "
             f"average, and the pump lags a burst by a little. {qmoved} of those runs show such a dip, the largest "
             f"{qexc:.2g} Pa ({qexc / 0.06e6:.1e} of dp), in single samples. " + dips_text +
             " What they do to the loop is the paired pump minus constant difference at the slowest frequency "
             "(the table above): DEM is chaotic, and a perturbation of 1e-5 sends the grains along another path, "
             "so that difference is the spread of equally likely loops of one sample, not a bias.")
    if ("triangle", 1.0) in effect:
        (n, m, sd, h), (rn, rm, rsd, rh), same, npairs, d = effect[("triangle", 1.0)]
        L.append("")
        L.append(f"**The pump's effect at the paper's speed** is at most that of 1 Hz: W {rm:+.2f} +- "
                 f"{rh:.2f}% ({m:+.1f} +- {h:.1f} J/m^2, {npairs} pairs, {same} of them identical bit for bit), "
                 f"against a seed-to-seed scatter of W of several percent: {rules.statement_equivalence(d)}. "
                 "That a pump of 2 m^3/h at a quasi-static stroke is the constant model in W is therefore "
                 f"**{rules.verdict_equivalence([rules.band(d)])}** (the equivalence rule); in dp the pump held "
                 f"the set point to {qexc / 0.06e6:.1e} of it in the quasi-static runs (above). Since the pump keeps "
                 "up with the stroke, the paper's \"pump struggled to keep pace\" at the onset of compression "
                 "points to its control rather than its speed: a regulator with "
                 "a switching band, a throttled line, or a leak (`process.leak_rate`), none of which the paper "
                 "describes.")
    L.append("")
    return L


def section_shows(c):
    """What it shows: per waveform the pump's limit and its effect, the waveforms against each
    other at the fastest frequency, the frequency's own effect on W."""
    pump, const, waveforms, freqs, effect = c.pump, c.const, c.waveforms, c.freqs, c.effect
    A, S, area = c.A, c.S, c.area
    f0 = freqs[0]
    L = []
    L.append("## What it shows")
    for w in waveforms:
        fs = [f for f in freqs if any(k[0] == w and k[1] == f for k in pump)]
        thr = S / area / (2.0 if w == "triangle" else math.pi) / A
        big = [f for f in fs if any(max(r["dp_max"] - r["dp_set"], r["dp_set"] - r["dp_min"]) > 1e-3 * r["dp_set"]
                                    for (ww, ff, s), r in pump.items() if ww == w and ff == f)]
        L.append(f"- **{w}**: a cap speed of S / (pi r^2) = {S / area:.3g} m/s is the pump's limit for a rigid "
                 f"cylinder, i.e. {thr:.3g} Hz for this stroke; dp left the set point by more than 0.1% at "
                 f"{', '.join(f'{f:g}' for f in big) if big else 'no frequency up to ' + format(fs[-1], 'g')} Hz.")
        for f in sorted({k[1] for k in const}):
            if (w, f) in effect:
                (n, m, sd, h), (rn, rm, rsd, rh), same, npairs, d = effect[(w, f)]
                if same == npairs:
                    L.append(f"  - {f:g} Hz: no effect (all {npairs} pairs identical bit for bit).")
                else:
                    sig = rules.statement_equivalence(d)
                    L.append(f"  - {f:g} Hz: W {rm:+.2f} +- {rh:.2f}% ({m:+.1f} J/m^2, 95% interval "
                             f"{m - h:+.1f} ... {m + h:+.1f}; {same} of {npairs} pairs identical bit "
                             f"for bit) when the pump replaces the constant dp: {sig}.")
    # The waveforms against each other at the fastest frequency.
    fmax = freqs[-1]
    ex = {}
    for w in waveforms:
        rs = [r for (ww, ff, s), r in pump.items() if ww == w and ff == fmax]
        if rs:
            ex[w] = max(max(r["dp_max"] - r["dp_set"], r["dp_set"] - r["dp_min"]) for r in rs)
    if "triangle" in ex and "sine" in ex and ex["sine"] > 0:
        L.append(f"- At {fmax:g} Hz the triangle moves dp {ex['triangle'] / ex['sine']:.0f} times more than the "
                 f"sine ({ex['triangle']:.3g} Pa against {ex['sine']:.3g} Pa), though the sine's peak speed is "
                 f"{math.pi / 2:.2f} times the triangle's: the triangle reverses at once at each end of the stroke, "
                 "the sine slows down into it." + reversal_text(pump, fmax))
    # The frequency's own effect on W: the largest paired change from the slowest frequency.
    worst, diffs = None, []
    for w in waveforms:
        for f in freqs[1:]:
            pairs = [(pump[(w, f, sd)], pump[(w, f0, sd)]) for (ww, ff, sd) in pump
                     if ww == w and ff == f and (w, f0, sd) in pump]
            if len(pairs) >= 2:
                n, m, sd_, h = interval([100.0 * (a["W_machine"] / b["W_machine"] - 1.0) for a, b in pairs])
                if worst is None or abs(m) > abs(worst[2]):
                    worst = (w, f, m, h)
                diffs.append((w, f, rules.difference("paired", w_by_seed(pump, w, f0), w_by_seed(pump, w, f))))
    if worst:
        w, f, m, h = worst
        L.append(f"- W against the frequency from {f0:g} to {fmax:g} Hz: "
                 + frequency_statement(diffs, f0) +
                 f" The largest paired change from {f0:g} Hz is {m:+.1f} +- {h:.1f}% ({w}, {f:g} Hz). With "
                 "restitution as the dissipation, the grains' inertia and the dashpots add little at these speeds "
                 f"(inertial number up to {max(r['inertial'] for r in pump.values()):.2g}), as far as these "
                 "intervals can tell.")
    L.append("")
    return L


def section_rules(c):
    """The decision rules (page_rules), with the seeds the study files planned."""
    return page_rules(study_seeds(c.docs, "pump"), study_seeds(c.docs, "constant"))


def section_figures(c):
    """Draws the figures into c.docs; the figures section links them (nothing when there is none)."""
    L = []
    figs = figures(c.pump, c.const, c.docs, c.waveforms, c.freqs)
    if figs:
        L.append("## Figures")
        for p in figs:
            L.append(f"![{p}]({p})")
            L.append("")
    return L


def section_reproduce(c):
    """Reproduce: the command and what it does."""
    L = []
    L.append("## Reproduce")
    L.append(f"`{COMMAND}` runs both studies, one `vppdem sweep STUDY.toml --publish docs/data/operation/STUDY` "
             "each: `pump.toml` prepares each seed's sample, `constant.toml` prepares nothing and branches from "
             "those (`samples_from = \"pump\"`); the records in `docs/data/operation/` count as finished, so the "
             "same command resumes and runs only what they lack (about 2.5 hours on 2 cores from nothing; "
             "`JOBS=N`). It then keeps the last cycle of seed 1's 10 and 20 Hz runs and writes this page "
             f"(`python3 -m vppdem.report operation docs/data/operation docs --runs OUT`); `{COMMAND} --report-only` "
             "only rewrites the page and figures from the records. The build and time step of the published runs, "
             "and what a run of this build would change: the script's header.")
    return L


SECTIONS = (section_question, section_runs, section_frequency_table, section_frequency_paired, section_pump_effect,
            section_paper_speed, section_shows, section_rules, section_figures, section_reproduce)


def parse_args(argv):
    """(DATA, DOCS, the --runs folder or None); fails with the usage on anything else."""
    runs = None
    if "--runs" in argv:
        i = argv.index("--runs")
        runs = argv[i + 1] if i + 1 < len(argv) else None
        argv = argv[:i] + argv[i + 2:]
        if runs is None or not os.path.isdir(runs):
            fail(f"--runs {runs or ''}: not a folder (the sweeps' --out folders' parent)", 2)
    if len(argv) != 2 or argv[0].startswith("-") or argv[1].startswith("-"):
        fail("usage: python3 -m vppdem.report operation DATA DOCS [--runs OUT]", 2)
    data, docs = argv
    return data, docs, runs


def main(argv=None):
    data, docs, runs = parse_args(list(sys.argv[1:] if argv is None else argv))
    if runs is not None:
        try:
            written, same = publish_last_cycles(runs, data)
        except RecordError as e:
            fail(str(e), 1)
        print(f"vppdem.report operation: last cycles from {runs}: {written} written, {same} unchanged")
    c = read_study(data, docs)
    L = []
    for section in SECTIONS:
        L += section(c)
    md = "\n".join(L) + "\n"
    path = os.path.join(docs, "operation.md")
    with open(path + ".part", "w") as f:
        f.write(md)
    os.replace(path + ".part", path)
    print(f"vppdem.report operation: wrote {path} ({len(c.pump)} pump runs, {len(c.const)} constant runs)")


if __name__ == "__main__":
    main(sys.argv[1:])
