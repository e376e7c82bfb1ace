# tools/synthetic_experiment.py (docs/studies.md, "Calibration that could fail"): a damper run's
# forces.csv written as a test rig writes its record.
import importlib.util
import os
import sys

from conftest import SOURCE_DIR
from synthetic_records import read, write_file


def synthetic_experiment(monkeypatch, *args):
    """tools/synthetic_experiment.py ARGS in this process (its main() reads sys.argv; the tool puts
    src/python on sys.path, restored afterwards)."""
    monkeypatch.setattr(sys, "path", sys.path[:])
    monkeypatch.setattr(sys, "argv", ["synthetic_experiment.py", *map(str, args)])
    path = os.path.join(SOURCE_DIR, "tools", "synthetic_experiment.py")
    spec = importlib.util.spec_from_file_location("synthetic_experiment", path)
    tool = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(tool)
    tool.main()


# The synthetic rig record: mm, kN, compression negative, from an offset origin; without noise
# it is the run's force_zeroed and displacement exactly (to the 9 digits written).
def test_synthetic_experiment_is_the_run_as_a_rig_writes_it(tmp_path, monkeypatch):
    d = tmp_path / "synthetic"
    write_file(d / "forces.csv", "time,displacement,force_total,force_grains,force_foil,force_zeroed,cycle\n"
                                 "0,0,5,6,-1,0,1\n0.1,0.002,85,80,5,80,1\n0.2,0,7,8,-1,2,1\n")
    synthetic_experiment(monkeypatch, d / "forces.csv", d / "exp.csv", "--disp-noise", "0", "--force-noise", "0")
    lines = read(d / "exp.csv").splitlines()
    assert lines[0].startswith("# synthetic record"), lines[0]
    assert lines[1] == "t_s,stroke_mm,load_kN"
    assert lines[2] == "0,-12.5,-0"
    assert lines[3] == "0.1,-14.5,-0.08"
    assert not os.path.exists(d / "exp.csv.part")
