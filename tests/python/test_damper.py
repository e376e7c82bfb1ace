# vppdem.Damper: stages, records as numpy arrays, checkpoints, errors with the command's messages,
# progress and Ctrl-C.
import os
import signal
import subprocess

import numpy as np
import pytest

import vppdem
from conftest import BINARY, SMALL


def test_stages_in_order():
    d = vppdem.Damper(settings=SMALL)
    assert d.stage == "fill"
    d.prepare()
    assert d.stage == "prepared"
    assert d.cycles_done == 0
    assert d.displacement.shape == (0,)
    d.vacuum()
    assert d.stage == "cycle"  # ready to cycle
    # A prepared sample of this damper: grains after the re-fills, foil 494 particles.
    s = d.summary()
    assert s["foil_particles"] == 494
    assert s["grains"] >= 56
    assert s["preparation"]["packing_fraction"] > 0.3


def test_records_and_shapes(finished):
    d = finished
    assert d.stage == "done"
    assert d.cycles_done == 2
    n = 2 * SMALL["process.samples_per_cycle"]
    for a in (d.displacement, d.force_total, d.force_grains, d.force_foil, d.sample_time):
        assert isinstance(a, np.ndarray) and a.shape == (n,)
    assert np.all(np.diff(d.sample_time) > 0)
    # A triangle of 2 mm: the cap goes down (compression positive) and back.
    assert d.displacement.max() == pytest.approx(SMALL["process.amplitude"], rel=0.05)
    assert abs(d.displacement[0]) < 1e-4
    c = d.cycles()
    assert c["W"].shape == (2,) and np.all(np.isfinite(c["W"]))
    # W against the loop's area computed here, independently of the C++ analysis: the shoelace
    # formula over each cycle's samples as a closed polygon (a constant offset of the force, such
    # as the zeroing, leaves a closed loop's area unchanged), over the lid's area. Dissipative:
    # positive, the compression branch above the release branch.
    spc = SMALL["process.samples_per_cycle"]
    for k in range(2):
        u = d.displacement[k * spc:(k + 1) * spc]
        f = d.force_total[k * spc:(k + 1) * spc]
        area = 0.5 * np.sum(u * np.roll(f, -1) - np.roll(u, -1) * f)
        w = -area / (np.pi * SMALL["damper.radius"] ** 2)
        assert w > 0
        assert c["W"][k] == pytest.approx(w, rel=1e-9)
    assert list(c["cycle"]) == [1.0, 2.0]
    # The ledger's split: dissipations are non-negative, the boundary work feeds them.
    for k in ("friction_dissipation", "damping_dissipation", "viscous_dissipation"):
        assert np.all(c[k] >= 0)
    assert np.all(c["boundary_work"] > 0)
    e = d.energy()
    assert list(e) == vppdem._core.Damper.energy_columns()
    assert all(v.shape == (n,) for v in e.values())
    s = d.summary()
    assert [x["W"] for x in s["cycles"]] == list(c["W"])
    assert s["inputs"]["process.cycles"] == 2


def test_cycles_split_into_calls_are_bitwise_the_same(vacuumed, finished):
    d = vppdem.Damper.load(vacuumed, settings=SMALL)
    assert d.stage == "cycle" and d.cycles_done == 0
    assert d.cycle(1) == 1
    assert d.stage == "cycle"
    assert d.displacement.shape == (80,)
    assert d.cycle(1) == 2
    assert d.stage == "done"
    np.testing.assert_array_equal(d.force_total, finished.force_total)
    np.testing.assert_array_equal(d.displacement, finished.displacement)
    np.testing.assert_array_equal(d.energy()["friction_dissipation"], finished.energy()["friction_dissipation"])


def test_save_mid_cycling_and_load(vacuumed, finished, tmp_path):
    d = vppdem.Damper.load(vacuumed, settings=SMALL)
    d.cycle(1)
    d.save(tmp_path / "one.ckpt")
    e = vppdem.Damper.load(tmp_path / "one.ckpt")  # its settings come from the checkpoint
    assert e.cycles_done == 1
    e.cycle()
    np.testing.assert_array_equal(e.force_total, finished.force_total)


def test_cycle_beyond_process_cycles(finished):
    with pytest.raises(RuntimeError, match=r"0 of process.cycles = 2 cycle\(s\) remain"):
        finished.cycle(1)


def test_write_gives_the_command_files(finished, tmp_path):
    finished.write(tmp_path)
    for f in ("forces.csv", "energy.csv", "cycles.csv", "summary.json"):
        assert (tmp_path / f).exists(), f
    rows = (tmp_path / "forces.csv").read_text().splitlines()
    assert rows[0] == "time,displacement,force_total,force_grains,force_foil,force_zeroed,cycle"
    assert len(rows) == 1 + 160
    # The arrays are the files' columns, from one description of the records (vpp/analysis/records.h):
    # forces() holds forces.csv, cycles() cycles.csv (and summary.json's cycles), same names,
    # same numbers.
    header = rows[0].split(",")
    table = np.loadtxt(tmp_path / "forces.csv", delimiter=",", skiprows=1)
    f = finished.forces()
    assert list(f) == header
    for j, name in enumerate(header):
        np.testing.assert_array_equal(f[name], table[:, j], err_msg=name)
    assert finished.time[0] == 0.0  # counted from the start of cycling, as the file
    np.testing.assert_array_equal(finished.cycle_index, table[:, header.index("cycle")].astype(int))
    cyc_lines = (tmp_path / "cycles.csv").read_text().splitlines()
    cheader = cyc_lines[0].split(",")
    ctable = np.loadtxt(tmp_path / "cycles.csv", delimiter=",", skiprows=1, ndmin=2)
    c = finished.cycles()
    assert set(cheader) == set(c)  # with the ledger on, every column of the record
    for j, name in enumerate(cheader):
        np.testing.assert_array_equal(c[name], ctable[:, j], err_msg=name)
    names = {(r["record"], r["name"]) for r in vppdem.record_columns()}
    assert {("forces", h) for h in header} <= names and {("cycles", h) for h in cheader} <= names


def test_air_of_a_sealed_damper(tmp_path):
    # The pump model, sealed (no pump, no bleed): p V is constant over the samples, the arrays
    # are forces.csv's air columns, and the constant model records none.
    d = vppdem.Damper(settings={**SMALL, "process.pressure_model": "pump", "process.pump_speed": 0,
                                "process.bleed_rate": 0})
    d.cycle()
    a = d.air()
    n = 2 * SMALL["process.samples_per_cycle"]
    assert all(v.shape == (n,) for v in a.values())
    pv = a["pressure_inside"] * a["gas_volume"]
    np.testing.assert_allclose(pv, pv[0], rtol=1e-12)
    assert a["pressure_inside"].max() > 1.02 * a["pressure_inside"][0]
    np.testing.assert_allclose(a["underpressure"], 101325.0 - a["pressure_inside"], rtol=0, atol=1e-9)
    d.write(tmp_path)
    cols = np.genfromtxt(tmp_path / "forces.csv", delimiter=",", names=True)
    for k in ("enclosed_volume", "gas_volume", "pressure_inside", "underpressure", "force_lid"):
        np.testing.assert_allclose(cols[k], a[k], rtol=1e-15, atol=0)
    assert "gas_work" in (tmp_path / "energy.csv").read_text().splitlines()[0].split(",")


def test_constant_model_records_no_air(finished):
    assert all(v.shape == (0,) for v in finished.air().values())


def cli_error(args):
    r = subprocess.run(f"{BINARY} damper {args}", shell=True, capture_output=True, text=True)
    assert r.returncode != 0
    line = [l for l in r.stderr.splitlines() if l.startswith("vppdem: error: ")]
    assert line, r.stderr
    return line[0][len("vppdem: error: "):]


@pytest.mark.skipif(not BINARY, reason="VPPDEM_BINARY not set")
@pytest.mark.parametrize("key,value,text", [
    ("process.underpresure", "0.06e6", "0.06e6"),   # unknown key (a typo)
    ("process.underpressure", -5.0, "-5.0"),        # value out of range
    ("process.cycles", "many", "many"),             # wrong type
])
def test_config_errors_carry_the_command_message(key, value, text, tmp_path):
    with pytest.raises(vppdem.ConfigError) as err:
        vppdem.Damper(settings={key: value})
    assert isinstance(err.value, ValueError)
    assert str(err.value) == cli_error(f"--out {tmp_path}/x --set {key}={text}")


def test_config_from_file_and_keywords(tmp_path):
    cfg = tmp_path / "c.toml"
    cfg.write_text('[process]\nunderpressure = 0.05e6\ncycles = 3\n')
    d = vppdem.Damper(cfg, settings=SMALL)
    s = d.summary()["inputs"]
    assert s["process.underpressure"] == 0.05e6   # from the file
    assert s["process.cycles"] == 2               # settings override the file
    rest = {k: v for k, v in SMALL.items() if k != "process.cycles"}
    s = vppdem.Damper(cfg, settings=rest, process__cycles=1).summary()["inputs"]
    assert s["process.cycles"] == 1               # and so does a keyword (one that settings do
    # not give: the two disagreeing is refused, tests/python/test_safety.py)
    d2 = vppdem.Damper({"process": {"underpressure": 0.04e6}}, **{"damper.radius": 0.012, "damper.height": 0.03})
    assert d2.summary()["inputs"]["process.underpressure"] == 0.04e6
    with pytest.raises(FileNotFoundError if False else vppdem.ConfigError):
        vppdem.Damper(tmp_path / "missing.toml")


def test_progress_callback_and_interrupt():
    calls = []

    def progress(stage, done, total, time):
        calls.append((stage, done, total, time))
        if len(calls) == 3:
            os.kill(os.getpid(), signal.SIGINT)  # as Ctrl-C would

    d = vppdem.Damper(settings=SMALL)
    with pytest.raises(KeyboardInterrupt):
        d.prepare(progress=progress)
    assert 3 <= len(calls) <= 4
    assert calls[0][0] == "prepare: fill"
    assert calls[1][1] > calls[0][1] and calls[1][3] > calls[0][3]


def test_progress_counts_up_within_each_stage_and_tells_the_time_left(capsys):
    # Each stage's steps never go back (a re-fill is a stage of its own name, counted from its
    # start); the line printed with progress=True gives the rate and the time left ("at most"
    # for the stages that end when the sample is at rest).
    calls = []
    d = vppdem.Damper(settings=SMALL)
    d.prepare(progress=lambda stage, done, total, time: calls.append((stage, done, total)))
    stages = list(dict.fromkeys(c[0] for c in calls))
    assert stages[0] == "prepare: fill" and stages[-1] == "prepare: compress", stages
    assert "prepare: re-fill 1" in stages, stages  # the small damper is re-filled once at least
    for stage in stages:
        done = [c[1] for c in calls if c[0] == stage]
        assert done == sorted(done), stage
        assert all(c[1] <= c[2] for c in calls if c[0] == stage), stage
    d.vacuum(progress=True)
    err = capsys.readouterr().err
    lines = [line for line in err.splitlines() if line.startswith("[vacuum]")]
    assert lines and all(" left" in line and "at most" in line for line in lines), err


def test_ctrl_c_stops_a_run_without_a_callback():
    # SIGINT from outside while the C++ steps without the interpreter lock (as Ctrl-C in a
    # terminal): the run stops within 256 steps with KeyboardInterrupt.
    import threading
    import time

    d = vppdem.Damper(settings=SMALL)
    threading.Timer(0.5, os.kill, (os.getpid(), signal.SIGINT)).start()
    t0 = time.monotonic()
    with pytest.raises(KeyboardInterrupt):
        d.prepare()  # about 4 s to the end of the preparation
    assert time.monotonic() - t0 < 2.0
    assert d.stage in ("fill", "compress")


def test_settings_tables_are_what_the_readers_apply():
    # vppdem.settings(): the damper's table; its defaults are what a Damper without settings runs
    # with (summary()["inputs"]), key by key.
    rows = {r["key"]: r for r in vppdem.settings()}
    inputs = vppdem.Damper().summary()["inputs"]
    compared = 0
    for key, value in inputs.items():
        r = rows[key]  # every recorded input is a row of the table
        if key == "simulation.threads" or isinstance(r["default"], str):
            continue  # 0 means the free cores; a word default ("grains.radius/3") is derived
        assert value == r["default"], key
        compared += 1
    assert compared >= 20
    assert rows["process.underpressure"]["unit"] == "Pa"
    assert rows["grains.friction"]["shares_preparation"] is True
    # The scene runner's table: required keys have no default.
    scene = {r["key"]: r for r in vppdem.settings("scene")}
    assert scene["simulation.duration"]["default"] == 1e-3
    assert scene["spheres[].radius"]["required"] and scene["spheres[].radius"]["default"] is None
    assert scene["simulation.gravity"]["default"] == (0.0, 0.0, -9.81)
    with pytest.raises(ValueError):
        vppdem.settings("tension")


def test_counting_columns_are_integers(finished, tmp_path):
    # The cycle index and the settled flag are counts, not measurements: integer arrays, as the
    # CSV records hold them (read back by vppdem.records the same way).
    d = finished
    c, f = d.cycles(), d.forces()
    for name, a in (("cycles cycle", c["cycle"]), ("cycles settled", c["settled"]), ("forces cycle", f["cycle"]),
                    ("cycle_index", d.cycle_index)):
        assert a.dtype.kind == "i", (name, a.dtype)
    assert list(c["cycle"]) == [1, 2]
    d.write(tmp_path / "w")
    from vppdem import records
    back = records.read_csv(tmp_path / "w" / "cycles.csv")
    assert back["cycle"].dtype.kind == "i" and back["W"].dtype.kind == "f"
    assert np.array_equal(back["cycle"], c["cycle"])


def test_help_is_a_users_page():
    # help(vppdem): what is there and where to look, not every class in full (547 lines before);
    # no docstring tells the module's history ("used to", "before", "issue N").
    import inspect
    import pydoc
    import re

    page = pydoc.render_doc(vppdem, renderer=pydoc.plaintext)
    assert len(page.splitlines()) < 120, len(page.splitlines())
    for name in ("Damper(", "sweep(", "calibrate(", "Study(", "device(", "World()", "ConfigError"):
        assert name in page, name
    history = re.compile(r"\bused to\b|\bissue \d+|\bbefore (this|the fix|issue)|\bno longer\b", re.I)
    seen = []
    for owner in (vppdem, vppdem.Damper, vppdem.Study, vppdem.World):
        for name, obj in [("", owner)] + inspect.getmembers(owner):
            doc = inspect.getdoc(obj) if not name.startswith("_") or not name else None
            if doc and history.search(doc):
                seen.append(f"{getattr(owner, '__name__', owner)}.{name}: {history.search(doc).group(0)}")
    assert not seen, seen
