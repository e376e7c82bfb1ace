# Issue 48 ("Nothing silently wrong III"), the Python findings: a value the module accepts does
# what it says, a bad one is refused with a message naming it, and a Damper cannot be broken
# from a second thread or by Ctrl-C. Each test failed on main 78169b8 (a segfault or double
# free, a partial cycle recorded as a cycle, AttributeError, a silent override, empty records,
# cycle(-5) running every cycle, sweep(jobs=-3) running).
import json
import os
import signal
import threading

import numpy as np
import pytest

import vppdem
from conftest import SMALL
from test_studies import TINY


def test_a_second_thread_is_refused_while_a_stage_runs():
    # A stage runs without the interpreter lock; a call on the same Damper from another thread
    # used to race it (a second cycle() crashed with a segfault or "double free or corruption").
    # Now it is refused with a RuntimeError saying why, and the running stage is not disturbed.
    d = vppdem.Damper(settings=SMALL)
    started, checked = threading.Event(), threading.Event()
    errors, from_callback = [], []

    def progress(stage, done, total, time):
        if not started.is_set():
            # The progress callback runs on the running thread, between steps: a read is allowed
            # there, a stage is not (it would run inside the one running).
            from_callback.append(d.stage)
            try:
                d.cycle(1)
            except RuntimeError as e:
                from_callback.append(str(e))
            started.set()
            checked.wait(60)  # the run holds here (the lock released) until the calls below are made

    def run():
        try:
            d.prepare(progress=progress)
        except BaseException as e:  # noqa: B036 (reported below)
            errors.append(e)

    t = threading.Thread(target=run)
    t.start()
    try:
        assert started.wait(60)
        for call in (lambda: d.stage, lambda: d.W, lambda: d.summary(), lambda: d.save("never.ckpt"),
                     lambda: d.cycle(1), lambda: d.prepare()):
            with pytest.raises(RuntimeError, match=r"running prepare\(\) in another thread; one call at a time"):
                call()
    finally:
        checked.set()
        t.join()
    assert not errors, errors
    assert from_callback[0] in ("fill", "compress")
    assert "called from within prepare() (its progress callback)" in from_callback[1]
    assert d.stage == "prepared"  # the run went on undisturbed, and the object is free again
    assert not os.path.exists("never.ckpt")


def test_an_interrupted_cycle_is_kept_out_of_W_and_the_records(vacuumed, finished, tmp_path):
    # Ctrl-C about a third into cycle 1: the partial loop (a third of the samples) used to be
    # reported by d.W and written to cycles.csv and summary.json as cycle 1, with a W far from
    # the cycle's. Now only finished cycles count; the partial one is named in the warnings, its
    # samples stay in forces.csv, and cycle() continues it to the same bits as a run never
    # interrupted.
    d = vppdem.Damper.load(vacuumed, settings=SMALL)

    def progress(stage, done, total, time):
        if stage == "cycle" and done > 0.3 * total:
            os.kill(os.getpid(), signal.SIGINT)  # as Ctrl-C would

    with pytest.raises(KeyboardInterrupt):
        d.cycle(progress=progress)
    spc = SMALL["process.samples_per_cycle"]
    assert 0 < d.displacement.shape[0] < spc  # the cycle had started
    assert d.cycles_done == 0
    assert d.W.shape == (0,)
    assert all(v.shape == (0,) for v in d.cycles().values())
    s = d.summary()
    assert s["cycles"] == []
    assert d.incomplete_cycle == 1
    assert any(w.startswith("cycle 1 incomplete") for w in s["warnings"]), s["warnings"]
    d.write(tmp_path)
    assert len((tmp_path / "cycles.csv").read_text().splitlines()) == 1  # the header only
    assert json.loads((tmp_path / "summary.json").read_text())["cycles"] == []
    assert len((tmp_path / "forces.csv").read_text().splitlines()) == 1 + d.displacement.shape[0]
    # Cycle 1 done, cycle 2 interrupted the same way: cycle 1 alone is recorded.
    d.cycle(1)
    with pytest.raises(KeyboardInterrupt):
        d.cycle(progress=progress)
    assert d.cycles_done == 1 and d.incomplete_cycle == 2
    np.testing.assert_array_equal(d.W, finished.W[:1])
    assert [c["cycle"] for c in d.summary()["cycles"]] == [1]
    assert any(w.startswith("cycle 2 incomplete") for w in d.summary()["warnings"])
    d.cycle()
    np.testing.assert_array_equal(d.force_total, finished.force_total)
    np.testing.assert_array_equal(d.W, finished.W)
    assert d.incomplete_cycle is None and finished.incomplete_cycle is None
    assert not any("incomplete" in w for w in d.summary()["warnings"])


@pytest.mark.parametrize("bad", [[("process.cycles", 2)], ["process.cycles=2"], "process.cycles=2"])
def test_settings_must_be_a_dict(bad, tmp_path):
    # A list (of pairs, or of "key=value" as sweep's `sets`) used to fail with AttributeError:
    # 'list' object has no attribute 'items'.
    for call in (lambda: vppdem.Damper(settings=bad), lambda: vppdem.load_config(settings=bad),
                 lambda: vppdem.sweep(tmp_path / "never.toml", tmp_path / "out", settings=bad)):
        with pytest.raises(TypeError, match=r"settings: a dict of dotted keys.*not (list|str)"):
            call()


def test_a_keyword_and_settings_may_not_disagree():
    # process__cycles=1 used to beat {"process.cycles": 2} in settings without a word.
    with pytest.raises(ValueError, match=r"'process.cycles' given twice with different values: 2 \(settings\) "
                                         r"and 1 \(keyword process__cycles\)"):
        vppdem.load_config(settings={"process.cycles": 2}, process__cycles=1)
    with pytest.raises(ValueError, match=r"'process.cycles' given twice.*3 \(keyword process__cycles\) and 4 "
                                         r"\(keyword process.cycles\)"):
        vppdem.load_config(process__cycles=3, **{"process.cycles": 4})
    with pytest.raises(ValueError, match="'process.cycles' given twice"):  # a nested table and a dotted key
        vppdem.load_config(settings={"process": {"cycles": 2}, "process.cycles": 5})
    with pytest.raises(ValueError, match="'grains.friction' given both in sets and in settings"):
        vppdem.sweep("never.toml", "never", settings={"grains.friction": 0.3}, sets=["grains.friction=0.5"])
    # The same value twice says one thing: accepted (2 and 2.0 are one number).
    assert vppdem.Damper(settings={**SMALL, "process.cycles": 3}, process__cycles=3.0).summary()["inputs"][
        "process.cycles"] == 3
    with pytest.raises(ValueError, match="given twice"):  # a bool is not the number 1
        vppdem.load_config(settings={"output.energy": True}, output__energy=1)


def test_write_before_prepare_is_refused(tmp_path):
    # write() before prepare() used to write records of nothing (forces.csv with a header only,
    # summary.json without a preparation) that look like a run's.
    d = vppdem.Damper(settings=SMALL)
    with pytest.raises(RuntimeError, match=r"write\(\): nothing to write: the damper is at stage 'fill'"):
        d.write(tmp_path / "out")
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("n,error,text", [
    (-5, ValueError, r"cycle\(\): n = -5: a whole number >= 1"),
    (0, ValueError, r"cycle\(\): n = 0: a whole number >= 1 .*or None for all that remain"),
    (1.5, ValueError, r"cycle\(\): n = 1.5: a whole number"),
    (True, TypeError, r"cycle\(\): n = True: .* not a bool"),
    ("2", TypeError, r"cycle\(\): n = '2'"),
])
def test_cycle_counts_below_one_are_refused(finished, n, error, text):
    # cycle(-5) used to run all the cycles that remain (the C++'s n < 0), cycle(1.5) one.
    with pytest.raises(error, match=text):
        finished.cycle(n)
    with pytest.raises(ValueError, match=r"cycle\(\): n = -5"):  # the compiled module's own check
        finished._d.cycle(-5)


def test_sweep_jobs_below_zero_are_refused(tmp_path):
    # sweep(jobs=-3) used to run; --jobs takes 0 (the free cores) or more.
    study = tmp_path / "tiny.toml"
    study.write_text(TINY)
    for jobs, error in ((-3, ValueError), (1.5, ValueError), ("2", TypeError)):
        with pytest.raises(error, match=f"jobs = {jobs!r}: a whole number >= 0"):
            vppdem.sweep(study, tmp_path / "out", jobs=jobs)
        with pytest.raises(error, match=f"jobs = {jobs!r}: a whole number >= 0"):
            vppdem.calibrate(study, tmp_path / "exp.csv", tmp_path / "cal", jobs=jobs)
    assert not (tmp_path / "out").exists() and not (tmp_path / "cal").exists()


# Issue 62: an empty or blank output folder is refused before anything runs (it would be the
# current folder), and write() does not replace another run's records without overwrite=True.
@pytest.mark.parametrize("out", ["", "   "])
def test_an_empty_or_blank_out_is_refused(out, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    study = tmp_path / "s.toml"
    study.write_text(TINY)
    calls = [lambda: vppdem.Damper(settings=SMALL, out=out),
             lambda: vppdem.sweep(study, out),
             lambda: vppdem.calibrate(study, study, out),
             lambda: vppdem.device(os.path.join(os.environ.get("VPPDEM_SOURCE_DIR", "."),
                                                "tests/data/devices/tiny_gripper.toml"), out)]
    for call in calls:
        with pytest.raises(ValueError, match="empty or blank output folder is refused"):
            call()
    assert sorted(os.listdir(tmp_path)) == ["s.toml"]


def test_write_does_not_replace_another_runs_records(finished, tmp_path):
    with pytest.raises(ValueError, match="empty or blank"):
        finished.write("")
    finished.write(tmp_path / "a")  # a new folder: written
    first = (tmp_path / "a" / "forces.csv").read_bytes()
    (tmp_path / "a" / "forces.csv").write_text("someone's record\n")
    with pytest.raises(FileExistsError, match="overwrite=True"):
        finished.write(tmp_path / "a")
    assert (tmp_path / "a" / "forces.csv").read_text() == "someone's record\n"  # untouched
    finished.write(tmp_path / "a", overwrite=True)
    assert (tmp_path / "a" / "forces.csv").read_bytes() == first
