# The study pages' decision rules (issue 60, items 1 and 5): every verdict and label of the grains,
# operation, devices, velocity and membrane pages comes from vppdem.report.rules. For each page a
# synthetic study, small hand-made records in the layout its report reads, written to a tmp
# folder: a resolved effect gives its verdict, an unresolved one "consistent, not established",
# an interval within the margin "reproduced", one beyond it "not reproduced"; a single run its
# label. And rules.label() and rules.section(), the rules section every page states. Seconds each.
import json
import math
import os
import subprocess

import pytest

from conftest import SOURCE_DIR

PYTHON = "/usr/bin/python3" if os.path.exists("/usr/bin/python3") else "python3"
SOURCE_PACKAGE = os.path.join(SOURCE_DIR, "src", "python")


def source_report():
    """vppdem.report: the copy beside the compiled module (build/python, as ctest runs it), or the
    source tree's when the package in use has none."""
    import vppdem
    try:
        from vppdem.report import rules  # noqa: F401
    except ImportError:
        vppdem.__path__.append(os.path.join(SOURCE_PACKAGE, "vppdem"))
    import vppdem.report as report
    return report


REPORT = source_report()
from vppdem.report import rules  # noqa: E402


def run_report(args, env=None):
    """`python3 -m vppdem.report ARGS` from the package this test imports (its parent folder on
    PYTHONPATH), in a process of its own."""
    package = os.path.dirname(os.path.dirname(os.path.dirname(REPORT.__file__)))
    e = dict(os.environ, PYTHONPATH=package, **(env or {}))
    r = subprocess.run([PYTHON, "-m", "vppdem.report"] + [str(a) for a in args], env=e, capture_output=True,
                       text=True)
    assert r.returncode == 0, r.stdout + r.stderr
    return r


def write_json(path, obj):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as f:
        json.dump(obj, f)


# ---------------------------------------------------------------------------------------------
# rules.label(), rules.section() and the functions the pages added


def test_label_names_every_kind_and_refuses_others():
    assert rules.label("one run") == "consistent, not established (one run)"
    assert rules.label("nothing measured") == "not decidable (nothing measured)"
    assert rules.label("input") == "input"
    assert rules.label("protocol", "the paper's stroke") == "protocol: the paper's stroke"
    assert rules.label("definition") == "definition"
    assert rules.label("choice") == "a choice, measured"
    with pytest.raises(ValueError, match="unknown kind 'guess'"):
        rules.label("guess")


def test_section_states_tests_margin_which_w_seeds_labels_and_when():
    page = rules.PageRules(module="vppdem.report.example", tests=[("paired", "the frequencies"),
                                                                  ("equivalence", "W against f")],
                           which_w="W of the last cycle.", planned="3 per case, fixed before the runs.",
                           added="Seeds 4-5 were added after a look; beside the verdict.",
                           labels=["one run", "nothing measured"], fixed_before=["the grid"],
                           fixed_after=["the margin"])
    text = "\n".join(rules.section(page))
    assert text.startswith("## Decision rules\n")
    assert "`vppdem.report.example`" in text
    assert "**Paired t**" in text and "(the frequencies)." in text
    assert "+-10% of the reference's mean" in text and "(W against f)." in text
    assert "- **Which W**: W of the last cycle." in text
    assert "- **Seeds**: 3 per case, fixed before the runs. Seeds 4-5 were added after a look" in text
    assert "**consistent, not established (one run)**" in text and "**not decidable (nothing measured)**" in text
    assert "Fixed before the data: the grid" in text
    assert "Written after the data were seen (a reader should weigh them so): the margin" in text
    for v, _ in rules.VERDICTS:
        assert f"**{v}**" in text
    # Nothing added: said so; another margin: stated.
    plain = "\n".join(rules.section(rules.PageRules(module="m", tests=[("equivalence", "")], which_w="W.",
                                                    planned="5.", margin=0.05)))
    assert "No seeds were added after a look." in plain and "+-5% of the reference's mean" in plain
    with pytest.raises(ValueError, match="unknown rule"):
        rules.section(rules.PageRules(module="m", tests=[("eyeball", "")], which_w="", planned=""))


def test_added_rules_on_hand_made_differences(tmp_path):
    d = rules.from_interval("paired", 3, 5.0, 3.0, 2, 100.0)
    assert rules.resolved(d) == "resolved" and rules.band(d) == "within"
    assert rules.reach(d) == pytest.approx(0.08)
    assert rules.statement_equivalence(d).startswith("no change beyond the +-10% margin")
    u = rules.from_interval("paired", 3, 2.0, 13.0, 2, 100.0)
    assert rules.resolved(u) == "unresolved" and rules.band(u) == "unresolved"
    assert rules.statement_equivalence(u) == "no change resolved; changes up to 15.0% not excluded (-11.0% to +15.0%)"
    b = rules.from_interval("paired", 3, -30.0, 5.0, 2, 100.0)
    assert rules.statement_equivalence(b).startswith("a change beyond the +-10% margin, resolved")
    r = rules.from_interval("paired", 3, 8.0, 5.0, 2, 100.0)
    assert rules.statement_equivalence(r).startswith("a change resolved from 0, not beyond the +-10% margin")
    assert rules.statement_equivalence(rules.from_interval("paired", 1, 1.0, None, 0, 100.0)).startswith("pending")
    assert rules.resolved(rules.from_interval("paired", 1, 1.0, None, 0, 1.0)) is None
    # One sample against a published value: 10, 11, 12 against 5 (t_{0.975,2} 1 / sqrt 3 = 2.48).
    o = rules.one_sample([10.0, 11.0, 12.0], 5.0)
    assert o.d == pytest.approx(6.0) and o.h == pytest.approx(2.4841, abs=1e-4) and o.ref == 5.0
    assert rules.direction(o, -1) == "against" and rules.direction(o, +1) == "yes"
    # The ratio of means less 1 (stats.ratio): 2 with an interval that excludes 1.
    q = rules.ratio_diff([10.0, 11.0, 9.0], [20.0, 22.0, 18.0])
    assert q.d == pytest.approx(1.0) and rules.resolved(q) == "resolved" and q.ref == 1.0
    (tmp_path / "s.toml").write_text("seeds = 4\n")
    assert rules.planned_seeds(str(tmp_path / "s.toml")) == 4
    (tmp_path / "t.toml").write_text("description = 'x'\n")
    assert rules.planned_seeds(str(tmp_path / "t.toml")) == 1
    assert rules.planned_seeds(str(tmp_path / "none.toml")) is None


# ---------------------------------------------------------------------------------------------
# docs/grains.md (vppdem.report grain_shapes): the first statement by the direction rule per shape


def grain_summary(W, peak=500.0, dp=60000.0):
    cyc = [{"cycle": k, "W": W + (50.0 if k == 1 else 0.0), "peak_force": peak, "friction_dissipation": 3.0,
            "damping_dissipation": 1.0, "viscous_dissipation": 0.0} for k in (1, 2)]
    return {"inputs": {"process.velocity": 0.02, "process.underpressure": dp, "damper.radius": 0.0255},
            "grains": 1100, "dt": 1.8e-6, "cycles": cyc, "W_settled": W, "first_settled_cycle": 2,
            "start_of_cycling": {"packing_fraction": 0.6}}


def grains_page(tmp_path, shapes, pressure, name):
    """The page of shapes {shape: [W per seed]} (spheres among them) against the pressure's runs
    {seed: (W at 0.02 MPa, W at 0.08 MPa)}."""
    root = tmp_path / name
    for sh, ws in shapes.items():
        for s, w in enumerate(ws, 1):
            write_json(root / "data" / f"grains.shape={sh}_simulation.seed={s}" / "summary.json",
                       grain_summary(w, 500.0 * (w / 100.0)))
    for s, (lo, hi) in pressure.items():
        for dp, w in ((20000, lo), (80000, hi)):
            write_json(root / "pressure" / f"damper.radius=0.0255_process.underpressure={dp}_simulation.seed={s}"
                       / "summary.json", grain_summary(w, dp=dp))
    (root / "docs").mkdir()
    (root / "plan.toml").write_text(f"seeds = {len(shapes['sphere'])}\n[grid]\n\"grains.shape\" = "
                                    f"[{', '.join(repr(k).replace(chr(39), chr(34)) for k in shapes)}]\n")
    run_report(["grain_shapes", root / "data", root / "docs", "--pressure", root / "pressure",
                "--study", root / "plan.toml"])
    return (root / "docs" / "grains.md").read_text()


def first_statement(md):
    return next(line for line in md.splitlines() if line.startswith("- Their first statement"))


SPHERES = [100.0, 101.0, 99.0]
PRESSURE = {1: (100.0, 200.0), 2: (110.0, 221.0), 3: (90.0, 179.0)}  # a doubling, nearly without scatter


def test_grains_every_shape_resolved_below_the_pressure_is_reproduced(tmp_path):
    md = grains_page(tmp_path, {"sphere": SPHERES, "dimer": [110.0, 111.0, 109.0], "pellet": [120.0, 122.0, 119.0]},
                     PRESSURE, "all")
    line = first_statement(md)
    assert "**reproduced**" in line, line
    assert "dimer: reproduced, the pressure's larger, resolved" in line and "pellet: reproduced" in line
    assert "## Decision rules" in md and "**Direction**" in md
    # The second statement: nothing measures the modulus or the yield stress.
    assert "**not decidable (nothing measured)**: its separate modulus" in md


def test_grains_one_shape_unresolved_is_consistent_not_established(tmp_path):
    # Pellets twice the spheres with a wide scatter: their effect cannot be told from the pressure's.
    md = grains_page(tmp_path, {"sphere": SPHERES, "dimer": [110.0, 111.0, 109.0], "pellet": [150.0, 200.0, 260.0]},
                     PRESSURE, "mixed")
    line = first_statement(md)
    assert "**consistent, not established**" in line, line
    assert "dimer: reproduced, the pressure's larger, resolved" in line
    assert "pellet: consistent, not established, not resolved" in line
    assert "equal" not in line and "undecided" not in line


def test_grains_a_shape_resolved_above_the_pressure_is_not_reproduced(tmp_path):
    md = grains_page(tmp_path, {"sphere": SPHERES, "pellet": [300.0, 303.0, 297.0]}, PRESSURE, "against")
    line = first_statement(md)
    assert "**not reproduced**" in line and "pellet: not reproduced, the shape's larger, resolved" in line, line


def test_grains_the_pressure_studys_added_seeds_stand_beside_the_verdict(tmp_path):
    # Seeds 1-3 of the pressure study (planned) leave the dimer unresolved; with seeds 4-5 (added
    # after a look) it resolves: the verdict stays the planned seeds', all seeds in brackets.
    scatter = {1: (100.0, 150.0), 2: (100.0, 260.0), 3: (100.0, 190.0), 4: (100.0, 200.0), 5: (100.0, 195.0)}
    md = grains_page(tmp_path, {"sphere": SPHERES, "dimer": [120.0, 121.0, 119.0]}, scatter, "seeds")
    line = first_statement(md)
    planned, _, added = line.partition("[seeds 4, 5 of the pressure study added after a look, all 5 seeds: ")
    assert added, line
    assert "**consistent, not established**" in planned and "dimer: consistent, not established" in planned
    assert added.startswith("reproduced: dimer: reproduced"), added
    assert "over its 3 planned seeds" in md and "That study's seeds 4, 5 were added after a look" in md


# ---------------------------------------------------------------------------------------------
# docs/operation.md (vppdem.report operation): effects on W by the equivalence rule


def operation_summary(W, f):
    air = {"W_machine": W, "peak_force_machine": 800.0, "underpressure_min": 60000.0, "underpressure_max": 60000.0,
           "gas_volume_min": 1e-5, "gas_volume_max": 1.6e-5}
    return {"cycles": [{"W": W}], "air": {"cycles": [air], "underpressure_set": 60000.0}, "inertial_number": 2.5e-4 * f,
            "quasi_static": f < 2, "dt": 1.8e-6, "run_seconds": 10.0,
            "inputs": {"damper.radius": 0.0255, "process.amplitude": 0.01, "process.pump_speed": 5.56e-4,
                       "grains.restitution": 0.5}}


def operation_page(tmp_path, pump, const):
    """pump, const: {frequency: [W_machine per seed]} of the triangle."""
    for study, table in (("pump", pump), ("constant", const)):
        for f, ws in table.items():
            for s, w in enumerate(ws, 1):
                write_json(tmp_path / "data" / study / f"process.waveform=triangle_process.frequency={f}_simulation.seed={s}"
                           / "summary.json", operation_summary(w, f))
    (tmp_path / "docs").mkdir()
    run_report(["operation", tmp_path / "data", tmp_path / "docs"])
    return (tmp_path / "docs" / "operation.md").read_text()


def frequency_line(md):
    return next(line for line in md.splitlines() if line.startswith("- W against the frequency"))


def test_operation_no_frequency_effect_within_the_margin_is_reproduced(tmp_path):
    md = operation_page(tmp_path, {1.0: [1000.0, 1100.0, 1200.0], 2.0: [1001.0, 1101.0, 1202.0]},
                        {1.0: [1000.0, 1101.0, 1199.0]})
    line = frequency_line(md)
    assert "That W does not depend on the frequency is **reproduced**" in line, line
    assert "within the +-10% margin at triangle 2 Hz" in line
    assert "| no change beyond the +-10% margin (the whole 95% interval within it:" in md
    # The pump against constant dp at 1 Hz within the margin: the constant model in W, reproduced.
    assert "is the constant model in W is therefore **reproduced**" in md
    assert "## Decision rules" in md and "**Equivalence margin**" in md


def test_operation_an_unresolved_frequency_effect_is_consistent_not_established(tmp_path):
    md = operation_page(tmp_path, {1.0: [1000.0, 1100.0, 1200.0], 2.0: [1050.0, 1000.0, 1300.0]},
                        {1.0: [1060.0, 1010.0, 1290.0]})
    line = frequency_line(md)
    assert "no change from 1 Hz resolved at any frequency" in line and "not excluded" in line, line
    assert "**consistent, not established**" in line
    assert "does not depend on the frequency beyond" not in md
    assert "is the constant model in W is therefore **consistent, not established**" in md


def test_operation_a_frequency_effect_beyond_the_margin_is_not_reproduced(tmp_path):
    md = operation_page(tmp_path, {1.0: [1000.0, 1100.0, 1200.0], 2.0: [1500.0, 1652.0, 1799.0]},
                        {1.0: [1000.0, 1100.0, 1200.0]})
    line = frequency_line(md)
    assert "a change from 1 Hz resolved at triangle 2 Hz" in line and "**not reproduced**" in line, line
    assert "| a change beyond the +-10% margin, resolved" in md


# ---------------------------------------------------------------------------------------------
# docs/devices.md (vppdem.report device trends): the table "Beside the published trends"


GRIPPER = ["dp0", "dp25", "dp50", "press1_dp50", "press4_dp50", "mu_membrane0_dp50", "mu_grains0_dp50"]


def device_root(tmp_path, hold, beam_work):
    """A source tree of hand-made device records: hold {case: [holding force per seed]} (the other
    gripper cases 0.05 N), beam_work {case: [work per cycle per seed]} at dp0, dp25, dp50."""
    root = tmp_path / "root"
    for study, n in (("gripper", 3), ("gripper_pour", 3), ("beam", 3)):
        os.makedirs(root / "studies" / "devices", exist_ok=True)
        (root / "studies" / "devices" / f"{study}.toml").write_text(f"seeds = {n}\n")
    for case in GRIPPER:
        for s, hf in enumerate(hold.get(case, [0.05, 0.05, 0.05]), 1):
            write_json(root / "docs" / "data" / "devices" / "gripper" / f"{case}_s{s}" / "summary.json",
                       {"stage": "done", "holding_force": hf, "membrane_z_min": 0.0001 * s,
                        "volume_change_vacuum": -0.09 - 0.001 * s, "grain_volume": 1.0, "volume_seal": 3.0})
    for s in (1, 2, 3):
        write_json(root / "docs" / "data" / "devices" / "gripper_pour" / f"pour_dp50_s{s}" / "summary.json",
                   {"stage": "done", "holding_force": 0.02, "membrane_z_min": 0.001, "volume_change_vacuum": -0.08 - 0.001 * s,
                    "grain_volume": 1.1, "volume_seal": 3.0})
    program = [{"kind": "cycle", "amplitude": -0.0005, "speed": 0.025, "cycles": 2}]
    for case, ws in beam_work.items():
        k = {"dp0": 100.0, "dp25": 1200.0, "dp50": 1700.0}[case]
        for s, w in enumerate(ws, 1):
            write_json(root / "docs" / "data" / "devices" / "beam" / f"{case}_s{s}" / "summary.json",
                       {"stage": "done", "stiffness": k + s, "work_per_cycle": w, "peak_force": 0.5 + 0.01 * s,
                        "inputs": {"tools.loader.program": program}})
    (root / "docs" / "devices.md").write_text("# Devices\n\n<!-- device_report:trends begin -->\n"
                                              "<!-- device_report:trends end -->\n\n<!-- device_report:rules begin -->\n"
                                              "<!-- device_report:rules end -->\n")
    run_report(["device", "trends"], env={"VPPDEM_SOURCE_DIR": str(root)})
    return (root / "docs" / "devices.md").read_text()


def trend(md, published):
    return [line for line in md.splitlines() if line.startswith(f"| {published}")]


def test_devices_beam_damping_resolved_up_at_every_step_is_reproduced(tmp_path):
    md = device_root(tmp_path, {"dp0": [0.0, 0.0, 0.0], "dp50": [0.10, 0.11, 0.12]},
                     {"dp0": [30e-6, 31e-6, 29e-6], "dp25": [40e-6, 41e-6, 39e-6], "dp50": [50e-6, 51e-6, 49e-6]})
    row = trend(md, "Bajkowski")[0]
    assert "damping as energy per cycle at a fixed displacement: reproduced" in row, row
    assert "stiffness: reproduced (every step resolved)" in row
    # The vacuum's grip resolved above dp = 0 in every seed: reproduced.
    assert trend(md, "Brown et al., PNAS")[0].split(" | ")[-1].startswith("reproduced"), trend(md, "Brown et al., PNAS")
    assert "## Decision rules" in md and "gripper: 3 (`seeds` of studies/devices/gripper.toml)" in md


def test_devices_beam_damping_one_step_unresolved_is_consistent_not_established(tmp_path):
    # 0 -> 25 kPa up, resolved; 25 -> 50 kPa down, not resolved (the published beam's case).
    md = device_root(tmp_path, {}, {"dp0": [30e-6, 31e-6, 29e-6], "dp25": [40e-6, 46e-6, 36e-6],
                                    "dp50": [38e-6, 39e-6, 37e-6]})
    row = trend(md, "Bajkowski")[0]
    assert "damping as energy per cycle at a fixed displacement: consistent, not established" in row, row
    assert "from 25 to 50 kPa not resolved" in row
    # The grip's steps all 0.05 N: nothing resolved, consistent, not established; suction not measured.
    brown = trend(md, "Brown et al. 2010")
    assert any("direction: consistent, not established" in r for r in brown)
    assert any("suction: not decidable (nothing measured): this study ran without it" in r for r in brown)


def test_devices_beam_damping_resolved_down_is_not_reproduced(tmp_path):
    md = device_root(tmp_path, {}, {"dp0": [30e-6, 31e-6, 29e-6], "dp25": [40e-6, 41e-6, 39e-6],
                                    "dp50": [20e-6, 21e-6, 19e-6]})
    row = trend(md, "Bajkowski")[0]
    assert "damping as energy per cycle at a fixed displacement: not reproduced" in row, row
    # Brown et al.'s 0.5%: the bags shrink 9% and 8%, resolved above it: not reproduced.
    assert any(r.split(" | ")[-1].startswith("not reproduced: the vacuum stage's shrinkage lies above 0.5%")
               for r in trend(md, "Brown et al. 2010"))


# docs/devices.md's jamming gripper (vppdem.report device gripper_jamming, report/device_jamming.py)

JAMMING = {"gripper_vacuum": ["both_dp0", "both_dp25", "both_dp50", "both_dp75"],
           "gripper_mechanisms": ["friction_dp50", "suction_dp50", "none_dp50"],
           "gripper_mechanisms_sphere": ["all_dp50", "shape_dp50"],
           "gripper_size": ["d8_dp50", "d16_dp50"]}


def jamming_root(tmp_path, hold, report=True, area=None):
    """Hand-made records of the four jamming studies (3 seeds each): hold {case: [holding force
    per seed]} (the other cases 0.1 N); holding_ratio F / (dp A) with A = area[case], else 1e-4 m^2."""
    root = tmp_path / "root"
    os.makedirs(root / "studies" / "devices", exist_ok=True)
    dps = {"both_dp0": 0, "both_dp25": 25e3, "both_dp75": 75e3}
    for study, cases in JAMMING.items():
        (root / "studies" / "devices" / f"{study}.toml").write_text("seeds = 3\n")
        for case in cases:
            dp = dps.get(case, 50e3)
            a = (area or {}).get(case, 1e-4)
            for s, hf in enumerate(hold.get(case, [0.1, 0.1, 0.1]), 1):
                write_json(root / "docs" / "data" / "devices" / study / f"{case}_s{s}" / "summary.json",
                           {"stage": "done", "holding_force": hf, "holding_ratio": hf / (dp * a) if dp else 0.0,
                            "object_area": a, "suction_force_max": 0.05, "seal_area": 1e-4,
                            "membrane_z_min": 0.001, "volume_change_vacuum": -0.03})
    if not report:
        return None
    (root / "docs" / "devices.md").write_text("# Devices\n\n<!-- device_report:gripper_jamming begin -->\n"
                                              "<!-- device_report:gripper_jamming end -->\n")
    run_report(["device", "gripper_jamming"], env={"VPPDEM_SOURCE_DIR": str(root)})
    return (root / "docs" / "devices.md").read_text()


def jamming_row(md, case):
    return [line for line in md.splitlines() if line.startswith(f"| `{case}` |")][0].split(" | ")


def test_devices_jamming_grip_growing_with_dp_at_every_step_is_reproduced_and_proportional(tmp_path):
    md = jamming_root(tmp_path, {"both_dp0": [0.0, 0.0, 0.0], "both_dp25": [0.249, 0.25, 0.251],
                                 "both_dp50": [0.499, 0.50, 0.501], "both_dp75": [0.749, 0.75, 0.751],
                                 "none_dp50": [0.0, 0.0, 0.0]})
    assert "**Against the vacuum** (each step up resolved upwards, Welch): reproduced." in md
    # F / (dp A) the same at every dp, the ratios' intervals within +-10%: proportional.
    assert "the ratio's 95% interval within +-10%): reproduced." in md
    # The holds column (7th: | case | object | mechanisms | dp | n | F | F/(dpA) | holds): an
    # interval above 0 holds, zeros do not.
    assert jamming_row(md, "both_dp50")[7] == "yes" and jamming_row(md, "none_dp50")[7] == "no"
    assert "33 of 33 runs" in md


def test_devices_jamming_a_step_resolved_down_is_not_reproduced_and_not_proportional(tmp_path):
    md = jamming_root(tmp_path, {"both_dp0": [0.0, 0.0, 0.0], "both_dp25": [0.24, 0.25, 0.26],
                                 "both_dp50": [0.49, 0.50, 0.51], "both_dp75": [0.30, 0.31, 0.32]})
    assert "**Against the vacuum** (each step up resolved upwards, Welch): not reproduced." in md
    # F / (dp A) at 75 kPa 0.41 times 50 kPa's, resolved beyond the margin: not proportional.
    assert "the ratio's 95% interval within +-10%): not reproduced." in md
    # A step not resolved (scatter as large as the step): consistent, not established.
    md = jamming_root(tmp_path, {"both_dp0": [0.0, 0.0, 0.0], "both_dp25": [0.1, 0.5, 0.2],
                                 "both_dp50": [0.49, 0.50, 0.51], "both_dp75": [0.74, 0.75, 0.76]})
    assert "resolved upwards, Welch): consistent, not established." in md
    # ... and F / (dp A) at 25 kPa scattered past the margin: proportionality not established.
    assert "the ratio's 95% interval within +-10%): consistent, not established." in md


def test_devices_jamming_size_steps_decide_the_force_up_and_the_ratio_down(tmp_path):
    # 8 -> 12 -> 16 mm: the force up at both steps, F / (dp A) (areas 0.5, 1, 1.8 cm^2) down at both.
    area = {"d8_dp50": 0.5e-4, "both_dp50": 1e-4, "d16_dp50": 1.8e-4}
    md = jamming_root(tmp_path, {"d8_dp50": [0.29, 0.30, 0.31], "both_dp50": [0.49, 0.50, 0.51],
                                 "d16_dp50": [0.69, 0.70, 0.71]}, area=area)
    assert "**Against the object's size** (each step 8 -> 12 -> 16 mm resolved upwards, Welch): reproduced." in md
    assert "8 -> 12 mm -0.020 ± " in md and "): reproduced." in md.split("**F / (dp A) against the size**")[1].splitlines()[0]
    assert jamming_row(md, "d16_dp50")[1] == "cylinder 16 mm"
    # The 16 mm cylinder held less than the 12 mm one, resolved: the force's trend not reproduced;
    # its ratio falls further, so the ratio's trend is.
    md = jamming_root(tmp_path, {"d8_dp50": [0.29, 0.30, 0.31], "both_dp50": [0.49, 0.50, 0.51],
                                 "d16_dp50": [0.39, 0.40, 0.41]}, area=area)
    assert "**Against the object's size** (each step 8 -> 12 -> 16 mm resolved upwards, Welch): not reproduced." in md
    assert md.split("**F / (dp A) against the size**")[1].splitlines()[0].endswith("): reproduced.")


def test_devices_jamming_trend_rows_decide_each_mechanism_by_its_difference_from_neither(tmp_path):
    # Friction alone resolved above neither: reproduced; suction alone no different: consistent,
    # not established; the sphere's shape alone holding nothing: interlocking not measured.
    jamming_root(tmp_path, {"both_dp0": [0.0, 0.0, 0.0], "friction_dp50": [0.8, 0.9, 0.85],
                            "suction_dp50": [0.001, 0.0, 0.002], "none_dp50": [0.001, 0.0, 0.001],
                            "shape_dp50": [0.0, 0.0, 0.0]}, report=False)
    md = device_root(tmp_path, {}, {"dp0": [30e-6, 31e-6, 29e-6], "dp25": [40e-6, 41e-6, 39e-6],
                                    "dp50": [50e-6, 51e-6, 49e-6]})
    row = trend(md, "Brown et al. 2010 (the gripper 25 grains across) | three mechanisms")[0]
    assert "friction: reproduced" in row and "suction: consistent, not established" in row, row
    assert "interlocking: not decidable (nothing measured): the sphere's shape alone holds 0.000 ± 0.000 N (0 of 3 seeds above 0)" in row
    # A study without records leaves its rows out: the small gripper's rows only.
    assert trend(md, "Brown et al. 2010 (the gripper 25 grains across) | the holding force of each mechanism")


# ---------------------------------------------------------------------------------------------
# docs/studies.md's velocity results (vppdem.report velocity_cycles --page)


HEAD = "underpressure,cycle,velocity,quantity,n,mean,sd,ref_velocity,diff_n,diff_mean,diff_ci95,rel_diff,within\n"


def velocity_csv(path, rows):
    """rows: (dp, cycle, v, n, mean, ref_v, diff_n, diff_mean, diff_ci95, ref_mean) for W."""
    with open(path, "w") as f:
        f.write(HEAD)
        for dp, k, v, n, m, rv, dn, dm, dh, ref in rows:
            f.write(f"{dp},{k},{v},W,{n},{m},1,{rv},{dn},{dm},{dh},{dm / ref},\n")


def velocity_page(tmp_path, quick, small):
    velocity_csv(tmp_path / "quick.csv", quick)
    velocity_csv(tmp_path / "small.csv", small)
    page = tmp_path / "studies.md"
    page.write_text("".join(f"<!-- velocity_cycles:{b} begin -->\n<!-- velocity_cycles:{b} end -->\n\n"
                            for b in ("quick", "small", "rules")))
    run_report(["velocity_cycles", "--page", page, tmp_path / "quick.csv", tmp_path / "small.csv"])
    return page.read_text()


def verdict_row(md, v):
    return next(line for line in md.splitlines() if line.startswith(f"| {v:g} m/s |"))


def test_velocity_within_unresolved_beyond_and_one_run(tmp_path):
    ref = 1000.0
    quick = [(60000, 1, 0.005, 2, ref, 0.005, 2, 0, 0, ref),
             (60000, 1, 0.01, 2, 1010.0, 0.005, 2, 10.0, 30.0, ref),     # within +-10%: reproduced
             (60000, 1, 0.02, 2, 1040.0, 0.005, 2, 40.0, 200.0, ref),    # 0 inside, past the margin
             (60000, 1, 0.05, 2, 1300.0, 0.005, 2, 300.0, 50.0, ref),    # beyond the margin
             (60000, 1, 0.000333, 1, 990.0, 0.005, 1, -10.0, "nan", ref)]  # one run
    small = [(60000, 1, 0.000333, 3, 300.0, 0.000333, 3, 0, 0, 300.0),
             (60000, 1, 0.01, 3, 306.0, 0.000333, 3, 6.0, 9.0, 300.0)]
    md = velocity_page(tmp_path, quick, small)
    assert verdict_row(md, 0.01).split(" | ")[1].startswith("**reproduced**"), verdict_row(md, 0.01)
    assert "**reproduced**" in verdict_row(md, 0.01).split(" | ")[2]
    assert "**consistent, not established** (1 unresolved; changes up to 24% not excluded)" in verdict_row(md, 0.02)
    assert "**not reproduced** (1 beyond" in verdict_row(md, 0.05)
    assert "**+30.0%**" in md and "+4.0%" in md and "**+4.0%**" not in md  # bold: resolved only
    assert "1 run: W 990 J/m2" in md and "**consistent, not established (one run)**" in md
    assert "### Decision rules of the velocity results" in md and "**Paired t**" in md
    assert "the paper's damper 2 (`seeds` of studies/velocity/quick.toml)" in md


# ---------------------------------------------------------------------------------------------
# docs/data/membrane_cylinder/report.md and docs/membrane.md (vppdem.report membrane_cylinder)


def membrane_page(tmp_path, lattice, mesh):
    """lattice, mesh: [W of cycles 3-5 per seed] (cycles 1-2 above them)."""
    data = tmp_path / "data"
    for foil, ws in (("lattice", lattice), ("mesh", mesh)):
        for s, w in enumerate(ws, 1):
            d = data / f"foil.builder={foil}_simulation.seed={s}"
            write_json(d / "summary.json", {"inputs": {"foil.builder": 1 if foil == "mesh" else 0, "simulation.seed": s},
                                            "foil_builder": foil, "foil_radius": 0.0176, "height": 0.0514, "grains": 238,
                                            "foil_particles": 1148 if foil == "lattice" else 1350, "foil_vacancies": 380,
                                            "W_settled": None})
            (d / "cycles.csv").write_text("cycle,W\n" + "".join(f"{k},{w + (200 if k < 3 else 0)}\n" for k in range(1, 6)))
    page = tmp_path / "membrane.md"
    page.write_text("text\n<!-- membrane_cylinder begin -->\n<!-- membrane_cylinder end -->\nmore\n")
    r = run_report(["membrane_cylinder", data, "--page", page])
    return r.stdout, page.read_text()


def test_membrane_within_the_margin_is_reproduced(tmp_path):
    report, page = membrane_page(tmp_path, [540.0, 545.0, 550.0, 535.0, 548.0], [542.0, 547.0, 549.0, 538.0, 546.0])
    assert "is therefore **reproduced**: the whole interval lies within the margin." in report
    assert "**Verdict.**" in page and "**reproduced**" in page and page.endswith("<!-- membrane_cylinder end -->\nmore\n")
    # The planned seeds: the study file beside DATA's tree, else the source tree's (5).
    assert "## Decision rules" in report and "per foil (`seeds` of studies/membrane/cylinder.toml)" in report
    assert "within the seed scatter** of" not in report


def test_membrane_zero_inside_an_interval_past_the_margin_is_consistent_not_established(tmp_path):
    report, _ = membrane_page(tmp_path, [500.0, 600.0, 520.0, 580.0, 540.0], [560.0, 510.0, 600.0, 530.0, 570.0])
    assert "is therefore **consistent, not established**: 0 lies inside the interval" in report
    assert "no change resolved; changes up to" in report


def test_membrane_a_difference_beyond_the_margin_is_not_reproduced(tmp_path):
    report, _ = membrane_page(tmp_path, [540.0, 545.0, 550.0, 535.0, 548.0], [800.0, 810.0, 805.0, 795.0, 802.0])
    assert "is therefore **not reproduced**: the interval lies wholly beyond the margin." in report


# ---------------------------------------------------------------------------------------------
# docs/paper_comparison.md's events and creep (vppdem.report.mechanisms; issue 60, item 3)


def mechanism_runs(tmp_path, share):
    """Hand-made records of the mechanisms study as the sweep publishes them (summary.csv, each case's
    cycles.csv): share(lam, seed) the events' share of every channel in cycles 2-3 (cycle 1 at 0: it
    must not count), seeds 1-3."""
    folder = tmp_path / "mechanisms"
    table = ["process.local_damping,simulation.seed,status,case"]
    for lam in (0.1, 0.2, 0.4):
        for seed in (1, 2, 3):
            x = share(lam, seed)
            d = folder / f"process.local-damping={lam:g}_simulation.seed={seed}"
            table.append(f"{lam:g},{seed},ok,{d.name}")
            os.makedirs(d, exist_ok=True)
            rows = ["cycle,friction_dissipation,damping_dissipation,viscous_dissipation,friction_in_events,"
                    "damping_in_events,viscous_in_events,event_fraction",
                    "1,1.0,1.0,0,0,0,0,0"]
            rows += [f"{c},2.0,1.0,0,{2.0 * x},{1.0 * x},0,0.1" for c in (2, 3)]
            (d / "cycles.csv").write_text("\n".join(rows) + "\n")
    (folder / "summary.csv").write_text("\n".join(table) + "\n")
    return str(folder)


def test_mechanisms_the_events_share_decides_c33_by_its_interval_against_one_half(tmp_path):
    from vppdem.report import mechanisms
    # Above 0.5 at every lambda, the share rising as 0.1 ln lambda: reproduced, slope +0.100.
    runs = mechanisms.load(mechanism_runs(tmp_path / "a", lambda lam, s: 0.8 + 0.1 * math.log(lam) + 0.001 * s))
    v, text, rows = mechanisms.analyse(runs, planned=3)
    assert v == "reproduced", text
    assert "events' share of the dissipation +0.100 ± 0.000" in text and "(9 of 9 runs)" in text
    assert rows[2].startswith("| 0.1 | 3 | 0.572 ± ")  # 0.8 + 0.1 ln 0.1 + 0.002
    # Below 0.5 at one lambda: contradicted.
    runs = mechanisms.load(mechanism_runs(tmp_path / "b", lambda lam, s: 0.3 if lam == 0.4 else 0.7 + 0.01 * s))
    assert mechanisms.analyse(runs, planned=3)[0] == "contradicted"
    # Scattered across 0.5 at one lambda: consistent, not established.
    runs = mechanisms.load(mechanism_runs(tmp_path / "c", lambda lam, s: [0.2, 0.9, 0.6][s - 1] if lam == 0.2 else 0.7))
    assert mechanisms.analyse(runs, planned=3)[0] == "consistent, not established"
    # A lambda with one run: open.
    runs = {k: v for k, v in runs.items() if not (k[0] == 0.1 and k[1] > 1)}
    assert mechanisms.analyse(runs, planned=3)[0] == "open (runs pending)"


def test_mechanisms_the_shares_against_the_loading_speed_take_lambda_02_as_001_m_s(tmp_path):
    from vppdem.report import mechanisms
    # The events' share 0.6 + 0.05 ln(v / 0.01): lambda 0.2's runs are the 0.01 m/s point.
    lam = mechanisms.load(mechanism_runs(tmp_path / "l", lambda lam, s: 0.6 + 0.001 * s))
    folder = tmp_path / "v"
    table = ["process.velocity,simulation.seed,status,case"]
    for v in (0.005, 0.02):
        for seed in (1, 2, 3):
            x = 0.6 + 0.05 * math.log(v / 0.01) + 0.001 * seed
            d = folder / f"process.velocity={v:g}_simulation.seed={seed}"
            table.append(f"{v:g},{seed},ok,{d.name}")
            os.makedirs(d, exist_ok=True)
            (d / "cycles.csv").write_text(
                "cycle,friction_dissipation,damping_dissipation,viscous_dissipation,friction_in_events,damping_in_events,"
                "viscous_in_events,event_fraction\n" + "".join(f"{c},2.0,1.0,0,{2 * x},{x},0,0.1\n" for c in (1, 2, 3)))
    (folder / "summary.csv").write_text("\n".join(table) + "\n")
    text, rows = mechanisms.velocity(lam, mechanisms.load(str(folder), "process.velocity"), planned=3)
    assert "events' share of the dissipation +0.050 ± 0.000" in text and "(6 of 6 runs" in text, text
    assert [r.split(" | ")[1] for r in rows[2:]] == ["3", "3", "3"]
