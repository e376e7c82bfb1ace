# vppdem.device(): the `vppdem device` command from Python (issue 47, docs/devices.md), on the
# tiny gripper of the C++ device tests (tests/data/devices/tiny_gripper.toml, ~7 s of CPU).
import csv
import json
import math
import os
import signal
import subprocess
import threading
import time

import pytest

import vppdem
from conftest import BINARY, SOURCE_DIR
from synthetic_records import run_report

TINY = os.path.join(SOURCE_DIR, "tests", "data", "devices", "tiny_gripper.toml")


@pytest.fixture(scope="module")
def gripper(tmp_path_factory):
    """The tiny gripper run once for the module (without VTK frames): its folder and result."""
    out = tmp_path_factory.mktemp("device") / "gripper"
    return out, vppdem.device(TINY, out, sets=["output.vtk=false"])


def test_a_device_runs_from_python_and_its_result_is_its_summary(gripper):
    out, r = gripper
    assert r["stage"] == "done"
    # The vacuum holds the object (the C++ test: 0.032 N with 50 kPa, 0 without).
    assert r["holding_force"] > 0.0
    assert r["volume_change"] < 0.0
    for k in ("holding_force", "press_force", "volume_seal", "volume_vacuum", "dt"):
        assert math.isfinite(r[k]), k
    # The lattice fill (the default): every grain placed stays, none struck off at the seal.
    assert r["fill_mode"] == "lattice"
    assert r["grains_placed"] == r["grains"] and r["grains_removed_at_seal"] == 0
    assert 0.0 < r["packing_seal"] < 1.0
    # The returned numbers are summary.json's, to the digit written there.
    with open(out / "summary.json") as f:
        summary = json.load(f)
    assert _find(summary, "holding_force") == pytest.approx(r["holding_force"], rel=1e-9)
    # Called again, the finished run is not run again: its result comes back the same.
    again = vppdem.device(TINY, out, sets=["output.vtk=false"])
    assert again["holding_force"] == r["holding_force"]


def _find(d, key):
    if isinstance(d, dict):
        for k, v in d.items():
            if k == key:
                return v
            found = _find(v, key)
            if found is not None:
                return found
    return None


def test_bad_device_keys_raise_config_error_and_write_nothing(tmp_path):
    out = tmp_path / "bad"
    with pytest.raises(vppdem.ConfigError, match="stages.underpressure"):
        vppdem.device(TINY, out, settings={"stages.underpressure": -1.0})
    assert not out.exists()
    with pytest.raises(ValueError, match="checkpoint_every"):
        vppdem.device(TINY, out, checkpoint_every=float("nan"))


def test_a_device_study_runs_through_vppdem_study(tmp_path, gripper):
    # A device study file (docs/devices.md, "Studies") through vppdem.Study: its runs listed with
    # their overrides, run by vppdem sweep, its summary.csv read back; the run is the one
    # vppdem.device() makes with the same keys.
    study = tmp_path / "study.toml"
    study.write_text(f"device = {json.dumps(TINY)}\n[set]\n\"output.vtk\" = false\n"
                     "[cases.dp50]\n\"stages.underpressure\" = 50000\n")
    s = vppdem.Study(study, tmp_path / "out")
    cases = s.cases()
    assert [(c["name"], c["case"], c["seed"]) for c in cases] == [("dp50", "dp50", 0)]
    assert cases[0]["overrides"] == ["output.vtk=false", "stages.underpressure=50000"]
    assert s.run() == 0
    rows = s.summary()
    assert len(rows) == 1 and rows[0]["status"] == "ok" and rows[0]["case"] == "dp50"
    # The module's run by hand has the same keys: the file's underpressure is 5e4 Pa.
    by_hand = gripper[1]
    assert rows[0]["holding_force"] == pytest.approx(by_hand["holding_force"], rel=1e-12)
    with pytest.raises(vppdem.ConfigError, match="device study"):
        vppdem.Study(study, tmp_path / "out").run(jobs=2)
    # summary_cases.csv: the case over its one run (no seeds: no interval).
    (case,) = s.cases_summary()
    assert (case["case"], case["seeds"], case["ok"], case["folders"]) == ("dp50", 1, 1, "dp50")
    assert case["holding_force_n"] == 1 and case["holding_force_mean"] == rows[0]["holding_force"]
    assert case["holding_force_ci95"] is None
    # `vppdem plot` on the run's folder and on the study's (issue 61, item 2); the report of the folder.
    out = tmp_path / "out"
    for folder, pngs in ((out / "dp50", ["device_tools.png", "device_air.png"]), (out, ["sweep_numbers.png"])):
        r = subprocess.run([BINARY, "plot", str(folder)], capture_output=True, text=True)
        assert r.returncode == 0, r.stdout + r.stderr
        assert r.stdout.split() == [str(folder / p) for p in pngs]
    status, printed = run_report("device", out)
    assert status == 0, printed
    assert "| `dp50` | 1 | " in (out / "device_report.md").read_text()


# Ctrl-C (issue 61): a device run, alone or as a study's case, stops at its next step with a
# checkpoint and raises KeyboardInterrupt; the same call resumes it. A fill that cannot end
# before 100 s of simulated time (hours of CPU) is interrupted by SIGINT after 1 s of wall clock.
ENDLESS = ["output.vtk=false", "stages.fill_time=100", "stages.fill_min_time=100"]


def _interrupted(call):
    """call() with SIGINT sent to this process 1 s in: the KeyboardInterrupt it raises, and the
    seconds it took (generous bounds below: without the stop it would take hours)."""
    timer = threading.Timer(1.0, os.kill, (os.getpid(), signal.SIGINT))
    start = time.monotonic()
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt) as e:
            call()
    finally:
        timer.cancel()
    return e, time.monotonic() - start


def _simulated_time(folder):
    with open(folder / "summary.json") as f:
        return json.load(f)["time"]


def test_ctrl_c_stops_a_device_run_with_a_checkpoint_that_the_same_call_resumes(tmp_path):
    out = tmp_path / "run"
    _, seconds = _interrupted(lambda: vppdem.device(TINY, out, sets=ENDLESS))
    assert seconds < 60
    assert (out / "run.ckpt").exists()
    with open(out / "summary.json") as f:
        first = json.load(f)
    assert first["stage"] == "fill" and first["time"] > 0.0
    # The same call resumes from the checkpoint (its simulated time goes on from there).
    _, seconds = _interrupted(lambda: vppdem.device(TINY, out, sets=ENDLESS))
    assert seconds < 60
    assert _simulated_time(out) > first["time"]


def test_ctrl_c_stops_a_device_study_leaving_its_run_resumable(tmp_path):
    study = tmp_path / "study.toml"
    sets = "".join(f'"{k}" = {v}\n' for k, v in (s.split("=") for s in ENDLESS))
    study.write_text(f"device = {json.dumps(TINY)}\n[set]\n{sets}[cases.a]\n[cases.b]\n")
    s = vppdem.Study(study, tmp_path / "out")
    _, seconds = _interrupted(s.run)
    assert seconds < 60
    a = tmp_path / "out" / "a"
    assert (a / "run.ckpt").exists() and not (a / "FAILED").exists()  # stopped, not failed
    with open(tmp_path / "out" / "summary.csv") as f:
        rows = {r["case"]: r for r in csv.DictReader(f)}
    assert rows["a"]["status"] == "not run" and "run.ckpt resumes it" in rows["a"]["message"]
    assert rows["b"]["status"] == "not run" and not (tmp_path / "out" / "b").exists()
    # Run again, the study resumes the stopped run from its checkpoint.
    first = _simulated_time(a)
    _interrupted(s.run)
    assert _simulated_time(a) > first
