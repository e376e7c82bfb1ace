# The trust studies' files (studies/trust/, run by scripts/trust_studies.sh; docs/studies.md,
# "Regenerating the studies"): every part of the script has its study file, every file loads and
# keeps the published results' time step; paper_velocity (samples_from the velocity study, matched
# by geometry) sets every key that makes a sample as the velocity study does, or its case would not
# find the sample and would prepare its own; the calibration's synthetic experiment runs at the
# friction study's conditions, at a friction between its grid values, from a seed it does not run;
# vppdem.report paper_velocity_cycle1 writes the table the script's Python heredoc wrote; and the
# paper-velocity case really branches from the velocity study's seed-1 sample.
import csv
import json
import os
import re
import subprocess

import vppdem
from conftest import MASS_SCALED, SOURCE_DIR, read_study

FOLDER = os.path.join(SOURCE_DIR, "studies", "trust")
SCRIPT = os.path.join(SOURCE_DIR, "scripts", "trust_studies.sh")
PYTHON = "/usr/bin/python3" if os.path.exists("/usr/bin/python3") else "python3"
# Keys that act neither on a run's dynamics nor on its sample: a run may differ from the study it is
# compared with in these.
BOOKKEEPING = {"output.energy", "simulation.threads"}


def path(name):
    return os.path.join(FOLDER, name + ".toml")


def study(name):
    return read_study(path(name))


def script_parts():
    m = re.search(r"^all=\(([^)]*)\)$", open(SCRIPT).read(), flags=re.M)
    assert m, "scripts/trust_studies.sh no longer lists its parts as all=(...)"
    return m.group(1).split()


def report(args):
    env = dict(os.environ, PYTHONPATH=os.path.join(SOURCE_DIR, "src", "python"))
    return subprocess.run([PYTHON, "-m", "vppdem.report", "paper_velocity_cycle1", *map(str, args)], env=env,
                          capture_output=True, text=True)


def test_every_part_of_the_script_has_a_study_file_that_loads_and_keeps_the_published_step(tmp_path):
    parts = script_parts()
    assert parts == ["underpressure", "friction", "young", "radius", "damping", "velocity", "paper_velocity",
                     "calibration"]
    names = [p if p != "calibration" else "calibration_truth" for p in parts]
    assert sorted(n + ".toml" for n in names) == sorted(os.listdir(FOLDER))
    for name in names:
        s, fixed, grid = study(name)
        # The published results ran when 0.45 was the default (0.3 now): without it no run is theirs.
        assert fixed.get("simulation.dt_safety") == 0.45, name
        assert "simulation.dt_safety" not in grid, name
        assert vppdem.Study(path(name), out=tmp_path / name).cases(), name
        if name not in ("paper_velocity", "calibration_truth"):
            # The script's defaults (SEEDS 3, CYCLES 5, VELOCITY 0.01 but for the velocity study).
            assert s.get("seeds") == 3 and fixed.get("process.cycles") == 5, name
            assert fixed.get("process.velocity") == (None if name == "velocity" else 0.01), name


def test_paper_velocity_sets_what_makes_the_velocity_studys_samples():
    b, b_set, b_grid = study("paper_velocity")
    a, a_set, a_grid = study("velocity")
    assert b.get("samples_from") == "velocity" and b.get("samples_match") == "geometry"
    assert b.get("seeds") == 1 and not b_grid  # one case: seed 1
    assert b_set["process.velocity"] == 3.33e-4 and b_set["process.cycles"] == 1
    assert b_set["process.underpressure"] in a_grid["process.underpressure"]  # paired with the study's runs
    makes_sample = {r["key"] for r in vppdem.settings() if not r["shares_preparation"]}
    for key in sorted(makes_sample):
        assert key not in a_grid, key
        assert b_set.get(key) == a_set.get(key), (key, b_set.get(key), a_set.get(key))


def test_the_calibrations_experiment_is_a_run_the_friction_study_could_have_made_but_did_not():
    t, t_set, t_grid = study("calibration_truth")
    f, f_set, f_grid = study("friction")
    assert not t_grid and "seeds" not in t  # one run, one packing
    # Everything the friction study fixes, the experiment has (but what only writes files).
    for key, value in f_set.items():
        if key not in BOOKKEEPING:
            assert t_set.get(key) == value, (key, t_set.get(key), value)
    assert set(t_set) - set(f_set) <= {"grains.friction", "simulation.seed"} | BOOKKEEPING, set(t_set) - set(f_set)
    # A friction between two grid values ("0:1:0.1" as the sweep expands it) and a seed outside 1..seeds.
    start, stop, step = (float(x) for x in f_grid["grains.friction"].split(":"))
    grid = [round(start + k * step, 12) for k in range(int(round((stop - start) / step)) + 1)]
    mu = t_set["grains.friction"]
    assert grid[0] < mu < grid[-1] and all(abs(mu - g) > 1e-9 for g in grid), (mu, grid)
    assert t_set["simulation.seed"] > f["seeds"]


def write_run(d, cycles, inputs=None, sample=None):
    """A finished run's records: cycles.csv (W, peak_force of each cycle as text) and summary.json."""
    d.mkdir(parents=True)
    (d / "cycles.csv").write_text("cycle,W,peak_force,dissipated_energy\n" +
                                  "".join(f"{k + 1},{w},{p},0.5\n" for k, (w, p) in enumerate(cycles)))
    summary = {"W": 1.0}
    if inputs is not None:
        summary["inputs"] = inputs
    if sample is not None:
        summary["from"] = sample
    (d / "summary.json").write_text(json.dumps(summary))


def test_the_cycle1_table_holds_the_seeds_first_cycles_at_every_velocity_sorted(tmp_path):
    # A velocity study: 2 dp x 3 velocities x 2 seeds, one failed run; cycle 1 differs from cycle 2,
    # and the W text is kept as cycles.csv wrote it (no reformatting).
    v = tmp_path / "velocity"
    v.mkdir()
    rows = ["process.underpressure,process.velocity,simulation.seed,W,dissipated_energy,peak_force,run_seconds,status,case"]
    for dp in ("20000", "60000"):
        for i, vel in enumerate(("0.1", "0.05", "0.005")):
            for s in ("1", "2"):
                case = f"process.underpressure={dp}_process.velocity={vel}_simulation.seed={s}"
                status = "failed: x" if (dp, vel, s) == ("60000", "0.05", "1") else "ok"
                rows.append(f"{dp},{vel},{s},9,9,9,1,{status},{case}")
                # cycle 1: W "<dp digit><velocity index><seed>.50", peak force "7<index><seed>.0"
                write_run(v / case, [(f"{dp[0]}{i}{s}.50", f"7{i}{s}.0"), ("1", "1")])
    (v / "summary.csv").write_text("\n".join(rows) + "\n")
    # The paper-velocity sweep: seeds 1 and 2 at 0.06 MPa (summary.json's inputs give v, dp, seed).
    p = tmp_path / "paper_velocity"
    for s in (1, 2):
        write_run(p / f"simulation.seed={s}", [(f"55{s}.25", "1035.5"), ("1", "1")],
                  {"process.velocity": 3.33e-4, "process.underpressure": 60000, "simulation.seed": s})
    out = tmp_path / "cycle1.csv"
    r = report([v, p, "--out", out])
    assert r.returncode == 0, r.stderr
    assert out.read_text() == (
        "velocity,W_cycle1,peak_force_cycle1,run\n"
        "0.000333,551.25,1035.5,simulation.seed=1\n"
        "0.005,621.50,721.0,process.underpressure=60000_process.velocity=0.005_simulation.seed=1\n"
        "0.1,601.50,701.0,process.underpressure=60000_process.velocity=0.1_simulation.seed=1\n")
    assert not os.path.exists(str(out) + ".part")
    # --seed 2: that seed's case, paired with the study's seed-2 runs (0.05 m/s is there).
    r = report([v, p, "--seed", 2, "--out", out])
    assert r.returncode == 0, r.stderr
    assert [l.split(",")[0] for l in out.read_text().splitlines()[1:]] == ["0.000333", "0.005", "0.05", "0.1"]
    assert out.read_text().splitlines()[1] == "0.000333,552.25,1035.5,simulation.seed=2"
    # A damper run's folder from before summary.json held the seed: the seed of its --from sample.
    old = tmp_path / "old_run"
    write_run(old, [("2588.5", "1035")], {"process.velocity": 3.33e-4, "process.underpressure": 60000},
              sample=str(v / "process.underpressure=20000_process.velocity=0.1_simulation.seed=2" / "prepared.ckpt"))
    r = report([v, old, "--out", out])
    assert r.returncode == 0, r.stderr
    assert out.read_text().splitlines()[1:] == [
        "0.000333,2588.5,1035,old_run",
        "0.005,622.50,722.0,process.underpressure=60000_process.velocity=0.005_simulation.seed=2",
        "0.05,612.50,712.0,process.underpressure=60000_process.velocity=0.05_simulation.seed=2",
        "0.1,602.50,702.0,process.underpressure=60000_process.velocity=0.1_simulation.seed=2"]
    # No case of the seed: named, nothing written.
    os.remove(out)
    r = report([v, p, "--seed", 3, "--out", out])
    assert r.returncode != 0 and "no finished case of seed 3" in r.stderr, r.stderr
    assert not out.exists()


def test_the_paper_velocity_case_branches_from_the_velocity_studys_seed1_sample(tmp_path):
    # The velocity study cut to one velocity and one dp (its [set] as it is), seed 1, on the small
    # damper (mass-scaled: conftest.MASS_SCALED), into tmp/velocity; then paper_velocity.toml into the sibling tmp/paper_velocity with the
    # same geometry, at 0.05 m/s instead of the paper's velocity (seconds, not minutes): its case
    # branches from the one sample and prepares nothing, and the report pairs it with the study's run.
    small = ["damper.radius=0.012", "damper.height=0.03", "grains.volume_fraction=0.45",
             "process.amplitude=0.0005", "process.samples_per_cycle=40", "simulation.threads=1"] + MASS_SCALED
    text = open(path("velocity")).read()
    text, n_v = re.subn(r'^"process\.velocity" = \[.*\]$', '"process.velocity" = [0.1]', text, flags=re.M)
    text, n_dp = re.subn(r'^"process\.underpressure" = \[.*\]$', '"process.underpressure" = [0.06e6]', text, flags=re.M)
    assert n_v == 1 and n_dp == 1, "velocity.toml's grid is no longer an underpressure list and a velocity list"
    (tmp_path / "velocity.toml").write_text(text)
    assert vppdem.sweep(tmp_path / "velocity.toml", tmp_path / "velocity", seeds=1,
                        sets=small + ["process.cycles=1"], jobs=1) == 0
    case = tmp_path / "velocity" / "process.underpressure=60000_process.velocity=0.1_simulation.seed=1"
    assert (case / "prepared.ckpt").exists()

    branch = vppdem.Study(path("paper_velocity"), out=tmp_path / "paper_velocity", sets=small + ["process.velocity=0.05"])
    assert branch.run(jobs=1) == 0
    cases = sorted(p for p in (tmp_path / "paper_velocity").iterdir() if p.is_dir())
    assert [c.name for c in cases] == ["simulation.seed=1"]
    assert not (cases[0] / "prepared.ckpt").exists()  # it prepared nothing
    summary = json.loads((cases[0] / "summary.json").read_text())
    assert summary["from"] == str(case / "prepared.ckpt")
    assert summary["inputs"]["simulation.dt_safety"] == 0.45

    r = report([tmp_path / "velocity", tmp_path / "paper_velocity", "--out", tmp_path / "c1.csv"])
    assert r.returncode == 0, r.stderr
    with open(tmp_path / "c1.csv") as f:
        got = list(csv.DictReader(f))
    first = lambda d: next(csv.DictReader(open(d / "cycles.csv")))  # noqa: E731
    assert [(r["velocity"], r["W_cycle1"], r["peak_force_cycle1"], r["run"]) for r in got] == [
        ("0.05", first(cases[0])["W"], first(cases[0])["peak_force"], "simulation.seed=1"),
        ("0.1", first(case)["W"], first(case)["peak_force"], case.name)]
