# vppdem.plot (the PNGs of `vppdem plot DIR`) from the source tree, as the command runs it:
# Debian's interpreter with PYTHONPATH=src/python, where no compiled module is.
import os
import subprocess

import pytest

import vppdem
import vppdem.plot
from conftest import BINARY, SMALL, SOURCE_DIR

PYTHON = "/usr/bin/python3" if os.path.exists("/usr/bin/python3") else "python3"
SOURCE_PACKAGE = os.path.join(SOURCE_DIR, "src", "python")
DAMPER_PNGS = ["loops_total.png", "loops_foil.png", "loops_grains.png", "loops.png", "energy_split.png"]


def without_core(args, **kwargs):
    """`python3 ARGS` seeing only the source tree's package (no _core)."""
    env = dict(os.environ, PYTHONPATH=SOURCE_PACKAGE)
    return subprocess.run([PYTHON] + args, env=env, capture_output=True, text=True, **kwargs)


@pytest.fixture(scope="module")
def damper_dir(tmp_path_factory):
    """The small damper, one cycle, by the command, not plotted."""
    if not BINARY:
        pytest.skip("VPPDEM_BINARY not set (ctest sets it)")
    d = tmp_path_factory.mktemp("plot") / "run"
    sets = [a for k, v in dict(SMALL, **{"process.cycles": 1}).items() for a in ("--set", f"{k}={v}")]
    subprocess.run([BINARY, "damper", "--out", str(d), "--no-plot", "--quiet"] + sets, check=True)
    assert not os.path.exists(d / "loops.png")
    return d


def test_import_without_the_compiled_module():
    code = ("import vppdem\n"
            "assert issubclass(vppdem.ConfigError, ValueError)\n"
            "for call in (vppdem.Damper, vppdem.World, vppdem.settings, vppdem.load_config):\n"
            "    try:\n"
            "        call()\n"
            "    except ImportError as e:\n"
            "        assert '_core' in str(e) and 'VPPDEM_PYTHON' in str(e), e\n"
            "    else:\n"
            "        raise AssertionError(f'{call} ran without _core')\n"
            "print(vppdem.plot.__name__)\n")
    r = without_core(["-c", code])
    assert r.returncode == 0, r.stderr
    assert r.stdout.strip() == "vppdem.plot"


def test_module_plots_a_damper_folder(damper_dir):
    r = without_core(["-m", "vppdem.plot", str(damper_dir)])
    assert r.returncode == 0, r.stderr
    assert r.stdout.split() == [str(damper_dir / n) for n in DAMPER_PNGS]
    for n in DAMPER_PNGS:
        assert os.path.getsize(damper_dir / n) > 0, n


def test_a_folder_without_forces_csv_is_refused(tmp_path):
    r = without_core(["-m", "vppdem.plot", str(tmp_path)])
    assert r.returncode == 1
    assert r.stderr.startswith("vppdem.plot: ")
    assert str(tmp_path / "forces.csv") + " not found" in r.stderr
    with pytest.raises(vppdem.plot.PlotError, match="forces.csv not found"):
        vppdem.plot.damper(tmp_path)


def test_a_missing_column_is_named(tmp_path):
    (tmp_path / "forces.csv").write_text("time,displacement,cycle\n0,0,1\n")
    with pytest.raises(ValueError, match="missing column.*force_total"):
        vppdem.plot.damper(tmp_path)


def test_sweep_folder_with_a_prefix_and_a_caption(damper_dir, tmp_path):
    # A one-case sweep folder made by hand around the damper run: its loop in NAME_loops.png.
    study = tmp_path / "study"
    study.mkdir()
    os.symlink(damper_dir, study / "grains.friction=0.3")
    (study / "summary.csv").write_text("grains.friction,W,status,case\n0.3,100,ok,grains.friction=0.3\n")
    r = without_core(["-m", "vppdem.plot", str(study), "--prefix", "fig", "--caption", "made by hand"])
    assert r.returncode == 0, r.stderr
    assert r.stdout.split() == [str(study / "fig_W.png"), str(study / "fig_loops.png")]
    assert all(os.path.getsize(p) > 0 for p in r.stdout.split())


def test_the_command_plots_through_the_package(damper_dir, tmp_path):
    # `vppdem plot DIR`: 0 when drawn, 2 when plotting failed (here: no forces.csv).
    for n in DAMPER_PNGS:
        (damper_dir / n).unlink(missing_ok=True)
    r = subprocess.run([BINARY, "plot", str(damper_dir)], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert all(os.path.getsize(damper_dir / n) > 0 for n in DAMPER_PNGS)
    bad = subprocess.run([BINARY, "plot", str(tmp_path)], capture_output=True, text=True)
    assert bad.returncode == 2
    assert "forces.csv not found" in bad.stderr
