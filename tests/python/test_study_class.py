# vppdem.Study: a study file and its folder as one object, over vppdem.sweep / vppdem.calibrate and
# the command's `sweep --list` / `--report-only` (src/python/vppdem/study.py). One tiny study of two
# frictions (one shared preparation, one cycle each), run once for the module, --jobs 1.
import csv
import os

import pytest

import vppdem
from conftest import TINY_STUDY as TINY

NAMES = ["grains.friction=0.3", "grains.friction=0.6"]


@pytest.fixture(scope="module")
def study_file(tmp_path_factory):
    path = tmp_path_factory.mktemp("study") / "tiny.toml"
    path.write_text(TINY)
    return path


@pytest.fixture(scope="module")
def ran(study_file):
    """The tiny study run to the end through Study.run() (the returned failed count kept)."""
    s = vppdem.Study(study_file, out=study_file.parent / "out")
    seen = []
    failed = s.run(jobs=1, progress=lambda done, total, case: seen.append((done, total, case)))
    return s, failed, seen


def csv_text(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def test_cases_lists_two_cases_sharing_one_preparation(study_file, tmp_path):
    s = vppdem.Study(study_file, out=tmp_path / "never")
    cases = s.cases()
    assert [c["name"] for c in cases] == NAMES
    assert [c["index"] for c in cases] == [1, 2]
    assert [c["group"] for c in cases] == [1, 1]  # one preparation
    assert [c["prepares"] for c in cases] == [True, False]
    assert cases[1]["branches_from"] == NAMES[0] and cases[0]["branches_from"] is None
    assert cases[0]["folder"] == os.path.join(os.fspath(tmp_path / "never"), NAMES[0])
    assert not (tmp_path / "never").exists()  # --list runs and creates nothing


def test_run_and_summary_read_the_tables_back(ran):
    s, failed, seen = ran
    assert failed == 0
    assert [d for d, _, _ in seen] == [1, 2]
    rows = s.summary()
    text = csv_text(os.path.join(s.out, "summary.csv"))
    assert len(rows) == 2 and len(text) == 2
    assert [r["grains.friction"] for r in rows] == [0.3, 0.6]
    assert [r["status"] for r in rows] == ["ok", "ok"]
    assert [r["case"] for r in rows] == NAMES == [c["name"] for c in s.cases()]
    for r, t in zip(rows, text):
        assert isinstance(r["W"], float) and r["W"] > 0
        assert r["W"] == float(t["W"]) and r["peak_force"] == float(t["peak_force"])
        assert list(r) == list(t)  # the same columns, in order
        for k, v in t.items():  # empty cells None, numbers floats
            if v == "":
                assert r[k] is None
            elif k not in ("status", "case", "warnings"):
                assert r[k] == float(v)
    cases = s.cases_summary()
    assert [c["grains.friction"] for c in cases] == [0.3, 0.6]
    assert all(c["W_n"] == 1.0 and c["W_sd"] is None for c in cases)  # one seed: no spread
    assert [c["W_mean"] for c in cases] == [r["W"] for r in rows]
    assert s.paired() == []  # no seeds: no summary_paired.csv


def test_report_rewrites_the_same_tables(ran):
    s, _, _ = ran
    before = {n: open(os.path.join(s.out, n), "rb").read() for n in ("summary.csv", "summary_cases.csv")}
    os.remove(os.path.join(s.out, "summary.csv"))
    rows = s.report()
    for n, b in before.items():
        assert open(os.path.join(s.out, n), "rb").read() == b, n
    assert rows == s.summary() and [r["status"] for r in rows] == ["ok", "ok"]


def test_report_of_an_empty_folder_marks_the_cases_not_run(study_file, tmp_path):
    s = vppdem.Study(study_file, out=tmp_path / "empty")
    with pytest.raises(FileNotFoundError, match="empty"):
        s.report()  # no folder: nothing to tabulate
    with pytest.raises(FileNotFoundError, match="summary.csv"):
        s.summary()
    (tmp_path / "empty").mkdir()
    rows = s.report()
    assert [r["status"] for r in rows] == ["not run", "not run"]
    assert all(r["W"] is None for r in rows)
    assert sorted(os.listdir(tmp_path / "empty")) == ["summary.csv", "summary_cases.csv"]  # no case folders


def test_bad_arguments_are_refused(study_file, tmp_path):
    missing = tmp_path / "no_such_study.toml"
    with pytest.raises(FileNotFoundError, match="no_such_study.toml"):
        vppdem.Study(missing, out=tmp_path / "out")
    with pytest.raises(ValueError, match="seeds"):
        vppdem.Study(study_file, out=tmp_path / "out", seeds=-1)
    with pytest.raises(ValueError, match="out"):
        vppdem.Study(study_file, out=None)
    with pytest.raises(ValueError, match="grains.friction"):
        vppdem.Study(study_file, out=tmp_path / "out", sets=["grains.friction=0.1"],
                     settings={"grains.friction": 0.2})
    with pytest.raises(TypeError, match="sets"):
        vppdem.Study(study_file, out=tmp_path / "out", sets="grains.friction=0.1")
    s = vppdem.Study(study_file, out=tmp_path / "out", settings={"grains.fricton": 0.2})
    with pytest.raises(vppdem.ConfigError, match="grains.fricton"):
        s.cases()
    with pytest.raises(ValueError, match="seeds"):
        vppdem.Study(study_file, out=tmp_path / "out").calibrate(tmp_path / "exp.csv", seeds=2)
    assert not (tmp_path / "out").exists()


def test_calibrate_compares_the_finished_cases(ran):
    # The "experiment" is the friction-0.6 case's own loop: the calibration (which resumes the
    # finished study, running nothing) finds it with misfit 0.
    s, _, _ = ran
    exp = os.path.join(s.out, NAMES[1], "forces.csv")
    cal = s.calibrate(exp, jobs=1, force_column="force_zeroed")
    assert cal["best"]["grains.friction"] == 0.6
    assert cal["misfit"] == 0
    assert os.path.exists(os.path.join(s.out, "calibration.json"))
