"""The first cycle at the paper's velocity beside the same sample's first cycles at the velocity
study's velocities (docs/studies.md, "Velocity convergence"; docs/data/paper_velocity_cycle1.csv,
by scripts/trust_studies.sh paper_velocity).

usage: python3 -m vppdem.report paper_velocity_cycle1 VELOCITY_DIR PAPER_DIR [--seed S] [--out FILE]

VELOCITY_DIR: the velocity study's sweep (studies/trust/velocity.toml: process.underpressure x
process.velocity x simulation.seed). PAPER_DIR: the run at the paper's velocity, a sweep's folder
(studies/trust/paper_velocity.toml, whose case branches from VELOCITY_DIR's sample of its seed:
its finished case of seed S, default 1, is taken) or a damper run's folder. The run's summary.json
gives its velocity, underpressure and seed (an older run's summary.json without
inputs.simulation.seed: the seed of its --from checkpoint's folder name ...simulation.seed=S...).

Writes FILE (default PAPER_DIR/paper_velocity_cycle1.csv; through FILE.part, renamed when whole):
  velocity,W_cycle1,peak_force_cycle1,run
one row per finished run (status ok in VELOCITY_DIR/summary.csv) of the velocity study at the paper
run's seed and underpressure, and one for the paper run, sorted by velocity: the velocity as `%g`,
W [J/m^2] and the peak force [N] of cycle 1 as their cycles.csv writes them, the run's folder name
(a case's, in its sweep). No statistics: one sample, paired runs. Runs under /usr/bin/python3.
"""
import argparse
import glob
import json
import os
import re
import sys

from ..records import RecordError, fail, finite_number, read_table

SEED = "simulation.seed"


def first_cycle(run_dir):
    """(W, peak_force) of the run's cycle 1, as text (cycles.csv's first row)."""
    try:
        header, rows = read_table(os.path.join(run_dir, "cycles.csv"))
    except RecordError as e:
        fail(str(e))
    missing = [c for c in ("W", "peak_force") if c not in header]
    if not rows or missing:
        fail(f"{os.path.join(run_dir, 'cycles.csv')}: no cycle" if not rows else
             f"{os.path.join(run_dir, 'cycles.csv')}: no column {', '.join(missing)}")
    return rows[0]["W"], rows[0]["peak_force"]


def run_inputs(run_dir):
    """(velocity, underpressure, seed) of a finished run, from its summary.json."""
    path = os.path.join(run_dir, "summary.json")
    try:
        with open(path) as f:
            summary = json.load(f)
    except (OSError, ValueError) as e:
        fail(f"cannot read {path}: {e}")
    inputs = summary.get("inputs", {})
    seed = inputs.get(SEED)
    if seed is None:  # an older vppdem's summary.json: the seed of the --from checkpoint's folder name
        m = re.search(re.escape(SEED) + r"=([^_/]+)", summary.get("from") or "")
        seed = finite_number(m.group(1)) if m else None
    v, dp = finite_number(inputs.get("process.velocity")), finite_number(inputs.get("process.underpressure"))
    if v is None or dp is None or finite_number(seed) is None:
        fail(f"{path}: no process.velocity, process.underpressure or simulation.seed in its inputs")
    return v, dp, finite_number(seed)


def paper_run(d, seed):
    """The paper run's folder: D itself (a damper run), or D's finished case of the seed (a sweep)."""
    if os.path.isfile(os.path.join(d, "summary.json")):
        return d
    if not os.path.isdir(d):
        fail(f"{d}: no such folder")
    found = [c for c in (os.path.dirname(p) for p in sorted(glob.glob(os.path.join(d, "*", "summary.json"))))
             if run_inputs(c)[2] == seed]
    if len(found) != 1:
        fail(f"{d}: {'no finished case' if not found else f'{len(found)} finished cases'} of seed {seed:g} "
             "(a damper run's folder, or a sweep's with one finished case of the seed)")
    return found[0]


def main(argv=None):
    ap = argparse.ArgumentParser(description="cycle 1 at the paper's velocity beside the velocity study's")
    ap.add_argument("velocity", help="the velocity study's sweep folder")
    ap.add_argument("paper", help="the paper-velocity run: a sweep's folder or a damper run's")
    ap.add_argument("--seed", type=float, default=1, help="the seed of the case taken from a sweep folder (default 1)")
    ap.add_argument("--out", help="the CSV (default PAPER/paper_velocity_cycle1.csv)")
    a = ap.parse_args(argv)
    paper = paper_run(os.path.normpath(a.paper), a.seed)
    v_paper, dp, seed = run_inputs(paper)
    try:
        _, summary = read_table(os.path.join(a.velocity, "summary.csv"))
    except RecordError as e:
        fail(str(e))
    rows = []
    for r in summary:
        if r.get("status") == "ok" and finite_number(r.get(SEED)) == seed and \
                finite_number(r.get("process.underpressure")) == dp:
            w, p = first_cycle(os.path.join(a.velocity, r["case"]))
            rows.append((float(r["process.velocity"]), w, p, r["case"]))
    if not rows:
        print(f"vppdem.report paper_velocity_cycle1: no finished run of seed {seed:g} at {dp:g} Pa in {a.velocity}",
              file=sys.stderr)
    w, p = first_cycle(paper)
    rows.append((v_paper, w, p, os.path.basename(paper)))
    out = a.out or os.path.join(a.paper, "paper_velocity_cycle1.csv")
    with open(out + ".part", "w") as f:
        f.write("velocity,W_cycle1,peak_force_cycle1,run\n")
        for v, w, p, name in sorted(rows):
            f.write(f"{v:g},{w},{p},{name}\n")
    os.replace(out + ".part", out)
    print(f"wrote {out}")
    return 0
