# The velocity convergence's study files (studies/velocity/, run by scripts/velocity_convergence.sh;
# docs/studies.md, "Velocity convergence"): every one loads and keeps the published runs' time step;
# each branch study (samples_from its base study, matched by geometry) sets every key that makes a
# sample as its base does, or its cases would not find the base's samples and would prepare their
# own; and the small damper's branch really runs from the small study's samples and is paired with
# its runs by vppdem.report velocity_cycles.
import csv
import json
import os
import re
import subprocess

import vppdem
from conftest import MASS_SCALED, SOURCE_DIR, read_study

FOLDER = os.path.join(SOURCE_DIR, "studies", "velocity")
BRANCHES = {"small_paper": "small", "quick_slow": "quick", "quick_paper": "quick"}
PYTHON = "/usr/bin/python3" if os.path.exists("/usr/bin/python3") else "python3"


def path(name):
    return os.path.join(FOLDER, name + ".toml")


def study(name):
    return read_study(path(name))


def test_every_velocity_study_loads_and_keeps_the_published_step(tmp_path):
    for name in ["quick", "small", *BRANCHES]:
        s, fixed, _ = study(name)
        # The published runs ran when 0.45 was the default (0.3 now): without it no run is theirs.
        assert fixed.get("simulation.dt_safety") == 0.45, name
        assert s.get("seeds", 0) >= 1, name
        assert vppdem.Study(path(name), out=tmp_path / name).cases(), name


def test_each_branch_study_sets_what_makes_its_base_studys_samples():
    makes_sample = {r["key"] for r in vppdem.settings() if not r["shares_preparation"]}
    for branch, base in BRANCHES.items():
        b, b_set, b_grid = study(branch)
        a, a_set, a_grid = study(base)
        assert b.get("samples_from") == base and b.get("samples_match") == "geometry", branch
        assert 1 <= b["seeds"] <= a["seeds"], branch  # a sample for each of its seeds
        for key in sorted(makes_sample):
            assert key not in a_grid and key not in b_grid, (branch, key)
            assert b_set.get(key) == a_set.get(key), (branch, base, key, b_set.get(key), a_set.get(key))


def test_the_small_damper_at_the_papers_velocity_branches_from_the_small_studys_samples(tmp_path):
    # The small study cut to one velocity, one dp and one cycle, one seed (its [set] as it is, and
    # mass-scaled: conftest.MASS_SCALED), into
    # tmp/small; then small_paper.toml into the sibling tmp/small_paper, at 0.02 m/s instead of the
    # paper's velocity (seconds, not minutes): both its cases branch from the one sample and prepare
    # nothing, and the report pairs them with the small study's run by seed.
    text = open(path("small")).read()
    text, n_v = re.subn(r'^"process\.velocity" = \[.*\]$', '"process.velocity" = [0.1]', text, flags=re.M)
    text, n_dp = re.subn(r'^"process\.underpressure" = \[.*\]$', '"process.underpressure" = [0.02e6]', text, flags=re.M)
    assert n_v == 1 and n_dp == 1, "small.toml's grid is no longer a velocity list and an underpressure list"
    (tmp_path / "small.toml").write_text(text)
    assert vppdem.sweep(tmp_path / "small.toml", tmp_path / "small", seeds=1, sets=["process.cycles=1"] + MASS_SCALED,
                        jobs=1) == 0
    sample = tmp_path / "small" / "process.underpressure=20000_process.velocity=0.1_simulation.seed=1" / "prepared.ckpt"
    assert sample.exists()

    branch = vppdem.Study(path("small_paper"), out=tmp_path / "small_paper", seeds=1,
                          sets=["process.velocity=0.02"] + MASS_SCALED)
    assert branch.run(jobs=1) == 0
    cases = sorted(p for p in (tmp_path / "small_paper").iterdir() if p.is_dir())
    assert [c.name for c in cases] == ["process.underpressure=20000_simulation.seed=1",
                                       "process.underpressure=60000_simulation.seed=1"]
    for c in cases:
        assert not (c / "prepared.ckpt").exists(), c  # it prepared nothing
        summary = json.loads((c / "summary.json").read_text())
        assert summary["from"] == str(sample), c
        assert summary["inputs"]["simulation.dt_safety"] == 0.45

    env = dict(os.environ, PYTHONPATH=os.path.join(SOURCE_DIR, "src", "python"))
    r = subprocess.run([PYTHON, "-m", "vppdem.report", "velocity_cycles", str(tmp_path / "small"), "--extra",
                        str(tmp_path / "small_paper"), "--out", str(tmp_path / "vc")], env=env, capture_output=True,
                       text=True)
    assert r.returncode == 0, r.stderr
    with open(tmp_path / "vc.csv") as f:
        rows = {(r["underpressure"], r["velocity"], r["quantity"]): r for r in csv.DictReader(f) if r["cycle"] == "1"}
    # dp 0.02 MPa: 0.1 m/s (the small study) paired with 0.02 m/s (the branch) on seed 1.
    assert rows[("20000", "0.1", "W")]["ref_velocity"] == "0.02"
    assert rows[("20000", "0.1", "W")]["diff_n"] == "1"
    assert rows[("60000", "0.02", "W")]["n"] == "1"  # the branch alone at 0.06 MPa
