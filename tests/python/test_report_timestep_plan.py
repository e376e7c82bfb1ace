# The time step decided by intervals (issue 60, item 2): vppdem.report.rules.within_margin_level and the
# paper page's section (vppdem.report.paper.timestep_plan_section) on synthetic runs whose stationary W
# is known, and C33's elasticity of the damping's energy (paper.damping_elasticity) on runs made to a
# chosen power of lambda.
import csv
import math
import os
import sys
import types

import pytest

from conftest import SOURCE_DIR

sys.path.insert(0, os.path.join(SOURCE_DIR, "src", "python"))
from vppdem.report import paper, rules, stats  # noqa: E402


def interval_of(xs):
    return stats.interval(xs)


def test_the_largest_level_whose_whole_interval_lies_within_the_margin():
    # 0.45: +6% +- 1% (resolves 7%), 0.3: +1% +- 2% (resolves 3%), 0.2: +0.5% +- 0.5%.
    bias = {0.45: (10, 0.06, 0.0, 0.01), 0.3: (10, 0.01, 0.0, 0.02), 0.2: (10, 0.005, 0.0, 0.005)}
    level, resolves = rules.within_margin_level(bias, 0.05)
    assert level == 0.3
    assert resolves[0.45] == pytest.approx(0.07)
    assert resolves[0.3] == pytest.approx(0.03)
    # A mean inside the margin whose interval reaches past it does not qualify (the old rule's flaw).
    bias[0.45] = (10, 0.01, 0.0, 0.045)
    assert rules.within_margin_level(bias, 0.05)[0] == 0.3
    bias[0.45] = (10, 0.01, 0.0, 0.039)
    assert rules.within_margin_level(bias, 0.05)[0] == 0.45
    # One seed resolves nothing; no level qualifying means the reference.
    assert rules.within_margin_level({0.45: (1, 0.0, math.nan, math.nan)}, 0.05) == (None, {0.45: None})


def write_run(folder, case, cycles, settled=None):
    os.makedirs(os.path.join(folder, case), exist_ok=True)
    with open(os.path.join(folder, case, "cycles.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["cycle", "W"])
        for i, x in enumerate(cycles, 1):
            w.writerow([i, x])


def write_leg(folder, rows, level_column):
    os.makedirs(folder, exist_ok=True)
    head = ([paper.TS_KEY] if level_column else []) + [paper.SEED, "W", "status", "case", "W_settled", "settled_cycles"]
    with open(os.path.join(folder, "summary.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(head)
        for level, seed, ws in rows:
            case = (f"simulation.dt-safety={level:g}_" if level_column else "") + f"simulation.seed={seed}"
            write_run(folder, case, [2 * ws, ws, ws, ws, ws])
            w.writerow(([level] if level_column else []) + [seed, ws, "ok", case, ws, 4])


def plan_page(tmp_path, seeds, w_of):
    """A page context over synthetic legs: seeds' runs with stationary W w_of(level, seed) (settled)."""
    raw = str(tmp_path)
    write_leg(os.path.join(raw, "timestep_045"), [(0.45, i, w_of(0.45, i)) for i in seeds], False)
    write_leg(os.path.join(raw, "timestep_stationary"),
              [(s, i, w_of(s, i)) for i in seeds for s in (0.3, 0.15)], True)
    return types.SimpleNamespace(raw=raw)


def test_the_page_decides_the_default_from_the_bias_intervals(tmp_path, monkeypatch):
    monkeypatch.chdir(SOURCE_DIR)  # the current default from docs/config.md
    default = paper.current_default(paper.TS_KEY)
    assert default is not None
    jitter = [0.004, -0.004, 0.002, -0.002, 0.0, 0.003, -0.003, 0.001, -0.001, 0.0]
    # W(0.15) = 1500 + 20 i; 0.3: +1% +- the jitter; 0.45: +8% +- the jitter: 0.3 is the rule's level.
    w = {0.15: lambda i: 1500 + 20 * i, 0.3: lambda i: (1500 + 20 * i) * (1.01 + jitter[i - 1]),
         0.45: lambda i: (1500 + 20 * i) * (1.08 + jitter[i - 1])}
    one = plan_page(tmp_path / "one", [1], lambda s, i: w[s](i))
    lines, c5, level = paper.timestep_plan_section(one)
    assert level is None and "1 of 10 planned seeds so far" in c5
    assert any("Bias and default: pending" in x for x in lines)
    three = plan_page(tmp_path / "three", [1, 2, 3], lambda s, i: w[s](i))
    lines, c5, level = paper.timestep_plan_section(three)
    text = "\n".join(lines)
    assert level == 0.3
    n, m, _, h = interval_of([w[0.3](i) / w[0.15](i) - 1 for i in (1, 2, 3)])
    assert f"0.3: {100 * m:+.1f}% +- {100 * h:.1f}%" in text
    assert "(provisional: 3 of 10 planned seeds)" in text
    assert "unchanged until the planned seeds are in" in text or f"the current default ({default:g}) is that level" in text
    # Ten seeds: no longer provisional; the rule's level against the default.
    ten = plan_page(tmp_path / "ten", list(range(1, 11)), lambda s, i: w[s](i))
    lines, c5, level = paper.timestep_plan_section(ten)
    text = "\n".join(lines)
    assert level == 0.3 and "provisional" not in text
    assert ("default to change to 0.3" in text) == (default != 0.3)
    # Both coarse levels within the margin: 0.45 chosen.
    w45 = plan_page(tmp_path / "w45", list(range(1, 11)),
                    lambda s, i: w[0.15](i) * (1 if s == 0.15 else 1.02 + jitter[i - 1]))
    assert paper.timestep_plan_section(w45)[2] == 0.45
    # Neither: the reference.
    far = plan_page(tmp_path / "far", list(range(1, 11)),
                    lambda s, i: w[0.15](i) * (1 if s == 0.15 else 1.10 + jitter[i - 1]))
    lines, _, level = paper.timestep_plan_section(far)
    assert level == 0.15 and any("the reference, **0.15**" in x for x in lines)


def test_the_damping_energys_elasticity_in_lambda(tmp_path):
    # E_damping = c lambda^k per run (k 0 at mu 0, 1 at mu 0.6), a 1% alternating scatter: slopes 0 and 1.
    rows = []
    for mu, k in ((0.0, 0.0), (0.6, 1.0)):
        for lam in (0.1, 0.2, 0.4):
            for seed in (1, 2, 3):
                e = 2.0 * lam ** k * (1 + 0.01 * (-1) ** seed)
                rows.append({"grains.friction": mu, "simulation.local_damping": lam, "simulation.seed": seed,
                             "status": "ok", "dissipated_energy": e / 0.5, "damping_share": 0.5})
    study = types.SimpleNamespace(runs=[{k: str(v) for k, v in r.items()} for r in rows])
    el = paper.damping_elasticity({"damping": study})
    assert el[0.0][1] == pytest.approx(0.0, abs=1e-9)
    assert el[0.6][1] == pytest.approx(1.0, abs=1e-9)
    assert 0 < el[0.0][2] < 0.05
    assert rules.verdict_mechanism(False) == "consistent, not established"
    assert rules.verdict_mechanism(True) == "contradicted"
    assert rules.verdict_mechanism(True, measured=False).startswith("not decidable")
