# The operation study's files (examples/operation/pump.toml and constant.toml, run by
# examples/operation/run.sh; docs/operation.md): both load; the constant-model twin branches from the
# pump study's samples (samples_from = "pump", matched by geometry) and is the pump study but for the
# pressure model, or its cases would not find the samples, or would not pair with the pump's; the
# published records (docs/data/operation/, made at simulation.dt_safety 0.45 before the files could
# say so) are still the files' cases, so that `--publish` takes them as finished; a real branch on the
# small damper prepares nothing and starts from the pump study's sample; and the report's --runs
# keeps the last cycle of forces.csv as the script's awk did, byte for byte.
import json
import os
import re
import shutil
import subprocess

import vppdem
from conftest import MASS_SCALED, SOURCE_DIR, read_study

FOLDER = os.path.join(SOURCE_DIR, "examples", "operation")
DATA = os.path.join(SOURCE_DIR, "docs", "data", "operation")
PYTHON = "/usr/bin/python3" if os.path.exists("/usr/bin/python3") else "python3"
# The awk of examples/operation/run.sh before the extraction moved into vppdem.report operation.
AWK = r'''NR == 1 { for (i = 1; i <= NF; i++) if ($i == "cycle") k = i; print; next }
{ last[NR] = $0; cyc[NR] = $k; if ($k > m) m = $k }
END { for (i = 2; i <= NR; i++) if (cyc[i] == m) print last[i] }'''
# The tests' small damper, one cycle (the studies keep their 10 mm amplitude otherwise).
SMALL = ["damper.radius=0.012", "damper.height=0.03", "grains.volume_fraction=0.45", "process.amplitude=0.002",
         "process.cycles=1"] + MASS_SCALED
CASE = "process.waveform=triangle_process.frequency=20_simulation.seed=1"


def path(name):
    return os.path.join(FOLDER, name + ".toml")


def study(name):
    return read_study(path(name))


def source_python(args, **kw):
    """python3 ARGS with the package of the source tree (the report needs no compiled module)."""
    env = dict(os.environ, PYTHONPATH=os.path.join(SOURCE_DIR, "src", "python"))
    return subprocess.run([PYTHON, *map(str, args)], env=env, capture_output=True, text=True, **kw)


def test_both_studies_load_and_the_twin_branches_from_the_pump_studys_samples(tmp_path):
    p, p_set, p_grid = study("pump")
    c, c_set, c_grid = study("constant")
    for name in ("pump", "constant"):
        assert vppdem.Study(path(name), out=tmp_path / name).cases(), name
    assert c.get("samples_from") == "pump" and c.get("samples_match") == "geometry"
    assert "samples_from" not in p  # the pump study prepares the samples
    assert c["seeds"] == p["seeds"]  # a sample for each of the twin's seeds
    assert c_grid["process.waveform"] == p_grid["process.waveform"]
    assert set(c_grid["process.frequency"]) <= set(p_grid["process.frequency"])  # paired case by case
    # The twin is the pump study but for the pressure model (and the pump's speed; the air record,
    # which the pump model writes anyway).
    assert {k for k in c_set.keys() & p_set.keys() if c_set[k] != p_set[k]} == {"process.pressure_model"}
    assert (c_set["process.pressure_model"], p_set["process.pressure_model"]) == ("constant", "pump")
    assert set(c_set) ^ set(p_set) <= {"process.pump_speed", "output.air"}
    # Every key that makes a sample as in the pump study, and none swept.
    makes_sample = {r["key"] for r in vppdem.settings() if not r["shares_preparation"]}
    for key in sorted(makes_sample):
        assert key not in p_grid and key not in c_grid, key
        assert c_set.get(key) == p_set.get(key), (key, c_set.get(key), p_set.get(key))
    # No step: the published runs' case.toml has none (run.sh's header), and an extra key is another case.
    assert "simulation.dt_safety" not in p_set and "simulation.dt_safety" not in c_set


def test_the_published_records_are_still_the_study_files_cases(tmp_path):
    # The records of docs/data/operation as a run folder: every one is a finished case of its study
    # file (its case.toml the case's), so that `--publish docs/data/operation/STUDY` puts them back
    # as finished and runs nothing. A key added to a file's [set] (simulation.dt_safety = 0.45, the
    # step they ran at) would make every one a run of other settings.
    for name, runs in (("pump", 30), ("constant", 24)):
        shutil.copytree(os.path.join(DATA, name), tmp_path / name)
        s = vppdem.Study(path(name), out=tmp_path / name)
        rows = s.report()
        assert len(rows) == runs, name
        bad = [(r["case"], r["status"]) for r in rows if r["status"] != "ok"]
        assert not bad, (name, bad[:3])


def test_last_cycle_is_the_awks_bytes(tmp_path):
    # A forces.csv by hand: the cycle column in the middle, the last cycle's rows not all at the end,
    # a cycle written as 3.0 (the same number), no newline after the last row.
    text = ("time,cycle,force\n0,0,1.5\n0.1,1,2\n0.2,3,4.25\n0.3,2,5\n0.4,3.0,-1e-3\n0.5,3,7")
    forces = tmp_path / "forces.csv"
    forces.write_text(text)
    r = source_python(["-c", "import sys; from vppdem.report.operation import last_cycle; "
                             "sys.stdout.write(last_cycle(sys.argv[1]))", forces])
    assert r.returncode == 0, r.stderr
    assert r.stdout == "time,cycle,force\n0.2,3,4.25\n0.4,3.0,-1e-3\n0.5,3,7\n"
    if shutil.which("awk"):
        a = subprocess.run(["awk", "-F,", AWK, str(forces)], capture_output=True, text=True)
        assert a.returncode == 0 and a.stdout == r.stdout, a.stdout


def test_the_twin_branches_from_the_pump_sample_and_the_report_keeps_its_last_cycle(tmp_path):
    # Both study files cut to the triangle at 20 Hz (their [set] and samples_from as they are), one
    # seed, on the small damper (mass-scaled), into tmp/out/pump and the sibling tmp/out/constant, each published
    # into tmp/data as run.sh does: the twin's case branches from the pump study's sample and prepares
    # nothing; the report's --runs keeps both runs' last cycle as the awk did, and again changes nothing.
    for name in ("pump", "constant"):
        text = open(path(name)).read()
        text, n_w = re.subn(r'^"process\.waveform" = \[.*\]$', '"process.waveform" = ["triangle"]', text, flags=re.M)
        text, n_f = re.subn(r'^"process\.frequency" = \[.*\]$', '"process.frequency" = [20.0]', text, flags=re.M)
        assert n_w == 1 and n_f == 1, f"{name}.toml's grid is no longer a waveform list and a frequency list"
        (tmp_path / f"{name}.toml").write_text(text)
        assert vppdem.sweep(tmp_path / f"{name}.toml", tmp_path / "out" / name, seeds=1, sets=SMALL, jobs=1,
                            publish=tmp_path / "data" / name) == 0, name
    sample = tmp_path / "out" / "pump" / CASE / "prepared.ckpt"
    assert sample.exists()
    twin = tmp_path / "out" / "constant" / CASE
    assert not (twin / "prepared.ckpt").exists()  # it prepared nothing
    assert json.loads((twin / "summary.json").read_text())["from"] == str(sample)

    docs = tmp_path / "docs"
    docs.mkdir()
    r = source_python(["-m", "vppdem.report", "operation", tmp_path / "data", docs, "--runs", tmp_path / "out"])
    assert r.returncode == 0, r.stderr
    assert "2 written, 0 unchanged" in r.stdout, r.stdout
    assert (docs / "operation.md").exists()
    for name in ("pump", "constant"):
        kept = (tmp_path / "data" / name / CASE / "forces_last_cycle.csv").read_text()
        forces = tmp_path / "out" / name / CASE / "forces.csv"
        lines = forces.read_text().splitlines()
        k = lines[0].split(",").index("cycle")
        assert kept.splitlines() == [lines[0]] + [l for l in lines[1:] if l.split(",")[k] == "1"], name
        if shutil.which("awk"):
            a = subprocess.run(["awk", "-F,", AWK, str(forces)], capture_output=True, text=True)
            assert a.returncode == 0 and a.stdout == kept, name
    r = source_python(["-m", "vppdem.report", "operation", tmp_path / "data", docs, "--runs", tmp_path / "out"])
    assert r.returncode == 0 and "0 written, 2 unchanged" in r.stdout, (r.stdout, r.stderr)
