# vppdem.sweep and vppdem.calibrate run the command's C++ (vpp/study/study.h, vpp/calibration/calibrate.h).
import csv
import os
import signal

import pytest

import vppdem
from conftest import SOURCE_DIR, TINY_STUDY as TINY


def test_sweep_on_a_tiny_study(tmp_path):
    study = tmp_path / "tiny.toml"
    study.write_text(TINY)
    failed = vppdem.sweep(study, tmp_path / "out", jobs=2)
    assert failed == 0
    with open(tmp_path / "out" / "summary.csv") as f:
        rows = list(csv.DictReader(f))
    assert [float(r["grains.friction"]) for r in rows] == [0.3, 0.6]
    assert all(r["status"] == "ok" for r in rows)
    assert all(float(r["W"]) > 0 for r in rows)


def test_sweep_backend_batch_gives_the_cpu_backends_loops(tmp_path):
    # vppdem.sweep(..., backend="batch"): the two cases' cycling in lockstep through one batch of the
    # batch engine (docs/gpu.md), the same forces.csv as each case stepping its own World.
    study = tmp_path / "tiny.toml"
    study.write_text(TINY)
    assert vppdem.sweep(study, tmp_path / "cpu", jobs=1) == 0
    assert vppdem.sweep(study, tmp_path / "batch", jobs=2, backend="batch") == 0
    for case in ("grains.friction=0.3", "grains.friction=0.6"):
        assert (tmp_path / "cpu" / case / "forces.csv").read_bytes() == (tmp_path / "batch" / case / "forces.csv").read_bytes()
    with pytest.raises(vppdem.ConfigError, match="--backend cuda"):
        vppdem.sweep(study, tmp_path / "cuda", backend="cuda")
    assert not (tmp_path / "cuda").exists()


def test_a_sweep_refuses_another_builds_cases_unless_mix_builds(tmp_path):
    # Every run records its build (build.json); a study in a folder another build ran refuses,
    # naming it and --mix-builds, before anything runs (docs/studies.md, "One build per study").
    b = vppdem.build()
    assert set(b) == {"commit", "id"}
    assert len(b["id"]) == 16 and all(c in "0123456789abcdef" for c in b["id"])
    study = tmp_path / "tiny.toml"
    study.write_text(TINY)
    case = tmp_path / "out" / "grains.friction=0.3"
    case.mkdir(parents=True)
    (case / "build.json").write_text('{"commit": "0123abcd", "id": "00000000000000aa"}\n')
    with pytest.raises(vppdem.ConfigError, match="--mix-builds") as e:
        vppdem.sweep(study, tmp_path / "out", jobs=1)
    assert "00000000000000aa" in str(e.value) and b["id"] in str(e.value)
    assert sorted(os.listdir(case)) == ["build.json"]
    assert not (tmp_path / "out" / "grains.friction=0.6").exists()


def test_sweep_errors_carry_the_command_message(tmp_path):
    study = tmp_path / "bad.toml"
    study.write_text('[grid]\n"grains.fricton" = [0.3]\n')
    with pytest.raises(vppdem.ConfigError, match="grains.fricton"):
        vppdem.sweep(study, tmp_path / "out")


def test_calibrate_against_a_simulated_record(finished, tmp_path):
    # The "experiment" is the small damper's own loop at friction 0.6 (2 cycles): the grid
    # point with the same settings reproduces it (misfit 0) and is the best.
    finished.write(tmp_path / "exp")
    study = tmp_path / "cal.toml"
    study.write_text(TINY.replace('"process.cycles" = 1', '"process.cycles" = 2')
                     .replace('"process.samples_per_cycle" = 40', '"process.samples_per_cycle" = 80')
                     .replace('"grains.friction" = [0.3, 0.6]', '"grains.friction" = [0.6]'))
    cal = vppdem.calibrate(study, tmp_path / "exp" / "forces.csv", tmp_path / "cal", force_column="force_zeroed")
    assert cal["best"]["grains.friction"] == 0.6
    assert cal["misfit"] == 0  # the sweep's branch from its prepared sample is this very run
    assert (tmp_path / "cal" / "misfit.csv").exists()


def test_sweep_progress_sees_every_case(tmp_path):
    study = tmp_path / "tiny.toml"
    study.write_text(TINY)
    seen = []
    failed = vppdem.sweep(study, tmp_path / "out", jobs=1, progress=lambda d, t, c: seen.append((d, t, c)))
    assert failed == 0
    assert [d for d, _, _ in seen] == [1, 2]
    assert all(t == 2 for _, t, _ in seen)
    assert len({c for _, _, c in seen}) == 2
    assert all((tmp_path / "out" / c / "summary.json").exists() for _, _, c in seen)


def test_interrupted_sweep_resumes(tmp_path):
    # KeyboardInterrupt from the callback after the first case (as Ctrl-C would raise it): the
    # sweep stops, keeps the finished case and writes no summary.csv; the same call resumes it.
    study = tmp_path / "tiny.toml"
    study.write_text(TINY)
    out = tmp_path / "out"

    def interrupt(done, total, case):
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        vppdem.sweep(study, out, jobs=1, progress=interrupt)
    finished = [c for c in os.listdir(out) if (out / c / "summary.json").exists()]
    assert len(finished) == 1
    assert not (out / "summary.csv").exists()
    assert not any((out / c / "FAILED").exists() for c in os.listdir(out) if (out / c).is_dir())

    seen = []
    assert vppdem.sweep(study, out, jobs=1, progress=lambda d, t, c: seen.append(c)) == 0
    assert len(seen) == 2  # the earlier case counts as done
    with open(out / "summary.csv") as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == 2 and all(r["status"] == "ok" for r in rows)


def test_sigint_stops_a_sweep_that_resumes(tmp_path):
    # A real SIGINT (Ctrl-C) after the first case, while the second may be running: the sweep
    # raises KeyboardInterrupt, leaves no FAILED marker, and the same call finishes it.
    study = tmp_path / "tiny.toml"
    study.write_text(TINY)
    out = tmp_path / "out"
    with pytest.raises(KeyboardInterrupt):
        vppdem.sweep(study, out, jobs=1, progress=lambda d, t, c: os.kill(os.getpid(), signal.SIGINT))
    assert not any((out / c / "FAILED").exists() for c in os.listdir(out) if (out / c).is_dir())
    assert vppdem.sweep(study, out, jobs=1) == 0
    with open(out / "summary.csv") as f:
        assert [r["status"] for r in csv.DictReader(f)] == ["ok", "ok"]
