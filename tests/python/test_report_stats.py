# vppdem.report.stats, the one statistics module of the reports (issue 46), against table values,
# closed forms, hand-computed samples and the C++ (src/vpp/analysis/stats.cpp) through the tables
# `vppdem sweep --report-only` published into docs/data/paper/report/; and every report's command
# line (`python3 -m vppdem.report NAME`), from the source tree as the scripts run it.
import csv
import glob
import math
import os
import subprocess

import pytest

from conftest import SOURCE_DIR

PYTHON = "/usr/bin/python3" if os.path.exists("/usr/bin/python3") else "python3"
SOURCE_PACKAGE = os.path.join(SOURCE_DIR, "src", "python")


def source_report():
    """vppdem.report.stats: the copy beside the compiled module (build/python, as ctest runs it), or
    the source tree's when the package in use has none."""
    import vppdem
    try:
        from vppdem.report import stats
    except ImportError:
        vppdem.__path__.append(os.path.join(SOURCE_PACKAGE, "vppdem"))
        from vppdem.report import stats
    return stats


stats = source_report()


def report(args, **kwargs):
    """`python3 -m vppdem.report ARGS` with PYTHONPATH=src/python (no compiled module)."""
    env = dict(os.environ, PYTHONPATH=SOURCE_PACKAGE)
    return subprocess.run([PYTHON, "-m", "vppdem.report"] + args, env=env, capture_output=True, text=True,
                          cwd=SOURCE_DIR, **kwargs)


# ---- the Student t quantile

# t_{p, dof} from the standard tables (Abramowitz & Stegun 26.10; R's qt), more digits than a
# printed table's three.
TABLE = [
    (0.975, 1, 12.706204736), (0.975, 2, 4.302652730), (0.975, 3, 3.182446305), (0.975, 4, 2.776445105),
    (0.975, 5, 2.570581836), (0.975, 9, 2.262157163), (0.975, 10, 2.228138852), (0.975, 30, 2.042272456),
    (0.975, 100, 1.983971519), (0.95, 1, 6.313751515), (0.95, 5, 2.015048373), (0.995, 4, 4.604094871),
]


@pytest.mark.parametrize("p,dof,t", TABLE)
def test_t_quantile_matches_the_table(p, dof, t):
    assert stats.t_quantile(p, dof) == pytest.approx(t, abs=1e-8)


def test_t_quantile_the_three_digit_table():
    assert round(stats.t_quantile(0.975, 1), 3) == 12.706
    assert round(stats.t_quantile(0.975, 4), 3) == 2.776
    assert round(stats.t_quantile(0.975, 9), 3) == 2.262


def test_t_quantile_closed_forms():
    # dof 1 (Cauchy): tan(pi (p - 1/2)); dof 2: (2p - 1) / sqrt(2 p (1 - p)).
    for p in (0.6, 0.9, 0.975, 0.999):
        assert stats.t_quantile(p, 1) == pytest.approx(math.tan(math.pi * (p - 0.5)), rel=1e-12)
        assert stats.t_quantile(p, 2) == pytest.approx((2 * p - 1) / math.sqrt(2 * p * (1 - p)), rel=1e-12)


def test_t_quantile_real_dof_symmetry_and_domain():
    # Welch's degrees of freedom are real: t lies between its integer neighbours'.
    t = stats.t_quantile(0.975, 98 / 19)
    assert stats.t_quantile(0.975, 6) < t < stats.t_quantile(0.975, 5)
    assert stats.t_quantile(0.025, 4) == -stats.t_quantile(0.975, 4)
    assert stats.t_quantile(0.5, 7) == 0.0
    assert stats.t_quantile(0.975, 1e6) == pytest.approx(1.959963985, abs=1e-5)  # the normal's
    for p, dof in ((0.0, 3), (1.0, 3), (0.975, 0.5), (0.975, math.inf), (0.975, math.nan)):
        with pytest.raises(ValueError):
            stats.t_quantile(p, dof)


def test_incomplete_beta_closed_forms():
    # I_x(1, 1) = x; I_x(a, 1) = x^a; I_x(1, b) = 1 - (1 - x)^b; I_x(a, b) = 1 - I_{1-x}(b, a).
    for x in (0.1, 0.5, 0.77):
        assert stats.incomplete_beta(x, 1, 1) == pytest.approx(x, rel=1e-13)
        assert stats.incomplete_beta(x, 3.5, 1) == pytest.approx(x ** 3.5, rel=1e-12)
        assert stats.incomplete_beta(x, 1, 2.5) == pytest.approx(1 - (1 - x) ** 2.5, rel=1e-12)
        assert stats.incomplete_beta(x, 2, 5) == pytest.approx(1 - stats.incomplete_beta(1 - x, 5, 2), abs=1e-14)
    assert stats.incomplete_beta(0.0, 2, 3) == 0.0 and stats.incomplete_beta(1.0, 2, 3) == 1.0


# ---- one sample

def test_interval_of_a_known_sample():
    # 1..5: mean 3, sd sqrt(2.5), half width t_{0.975,4} sqrt(2.5) / sqrt(5) = 2.776445105 / sqrt(2).
    n, m, s, h = stats.interval([1, 2, 3, 4, 5])
    assert (n, m) == (5, 3.0)
    assert s == pytest.approx(math.sqrt(2.5), rel=1e-15)
    assert h == pytest.approx(2.776445105 / math.sqrt(2), rel=1e-9)
    assert stats.mean([1, 2, 3, 4, 5]) == 3.0 and stats.sd([1, 2, 3, 4, 5]) == s
    # Failed runs (None, NaN, inf) are left out, as vpp::mean_interval leaves out non-finite values.
    assert stats.interval([1, None, 2, math.nan, 3, 4, math.inf, 5]) == (n, m, s, h)
    one = stats.interval([7.0])
    assert one[:2] == (1, 7.0) and math.isnan(one[2]) and math.isnan(one[3])
    none = stats.interval([])
    assert none[0] == 0 and all(math.isnan(v) for v in none[1:])
    assert math.isnan(stats.mean([])) and math.isnan(stats.sd([1.0]))


# ---- two samples

def test_paired_difference_by_hand():
    # Differences 1, 2, 3 (seed 4 only in a: left out): mean 2, sd 1, half width t_{0.975,2} / sqrt(3).
    d = stats.paired({1: 10, 2: 20, 3: 30, 4: 40}, {1: 11, 2: 22, 3: 33})
    assert (d.test, d.n, d.dof) == ("paired", 3, 2)
    assert d.d == pytest.approx(2.0, rel=1e-15)
    assert d.h == pytest.approx(4.302652730 / math.sqrt(3), rel=1e-9)
    assert d.ref == 20.0 and d.ok and not d.resolved  # 2 < 2.484
    assert d.text() == "+2 +- 2 (+10%)"
    assert stats.paired({1: 10}, {1: 12}).h is None  # one pair: no interval


def test_welch_difference_by_hand():
    # {1, 2, 3} against {2, 4, 6, 8, 10}: sds 1 and sqrt(10), v = 1/3 and 2, d = 6 - 2 = 4,
    # dof = (7/3)^2 / ((1/3)^2 / 2 + 2^2 / 4) = 98/19, half width t_{0.975, 98/19} sqrt(7/3).
    d = stats.welch([1, 2, 3], [2, 4, 6, 8, 10])
    assert (d.test, d.n) == ("Welch", (3, 5))
    assert d.d == pytest.approx(4.0, rel=1e-15)
    assert d.dof == pytest.approx(98 / 19, rel=1e-13)
    assert d.h == pytest.approx(stats.t_quantile(0.975, 98 / 19) * math.sqrt(7 / 3), rel=1e-13)
    assert 2.4469 * math.sqrt(7 / 3) < d.h < 2.5706 * math.sqrt(7 / 3)
    assert d.resolved and d.ref == 2.0
    assert stats.welch_dof(2, 3, 4, 5) == pytest.approx(4624 / 776, rel=1e-13)
    assert stats.welch_dof(0, 3, 0, 5) == 6.0  # no scatter: n1 + n2 - 2
    # The same as a contrast (-1, a), (+1, b); dicts as lists of their values.
    c = stats.contrast([(-1, {1: 1, 2: 2, 3: 3}), (1, [2, 4, 6, 8, 10])], ref=2.0)
    assert (c.d, c.dof) == pytest.approx((d.d, d.dof), rel=1e-13) and c.h == pytest.approx(d.h, rel=1e-13)
    assert stats.welch([1], [2, 3]).h is None


def test_ratio_and_satterthwaite_by_hand():
    # Dimers 210, 220, 230 against spheres 100, 110, 120 (test_report_grain_shapes.py): R = 2,
    # var(ln R) = 100 / (3 110^2) + 100 / (3 220^2), Welch dof 2.9412: R t se = 0.378.
    lr, se, dof = stats.log_ratio([100, 110, 120], [210, 220, 230])
    assert lr == pytest.approx(math.log(2), rel=1e-14)
    assert se * se == pytest.approx(100 / (3 * 110 ** 2) + 100 / (3 * 220 ** 2), rel=1e-13)
    assert dof == pytest.approx(2.9412, abs=1e-4)
    R, h, na, nb = stats.ratio([100, 110, 120], [210, 220, 230])
    assert (R, na, nb) == (2.0, 3, 3) and h == pytest.approx(0.378, abs=5e-4)
    assert stats.satterthwaite([(1 / 3, 2), (2.0, 4)]) == pytest.approx(98 / 19, rel=1e-13)
    assert stats.satterthwaite([(1.0, 4), (1.0, math.inf)]) == pytest.approx(16.0, rel=1e-15)


def test_ols_recovers_a_line():
    b, se, dof, s = stats.ols([[1.0, x] for x in (0, 1, 2, 3)], [1.0, 3.0, 5.0, 7.0])
    assert b == pytest.approx([1.0, 2.0], abs=1e-12) and dof == 2 and s == pytest.approx(0.0, abs=1e-12)


# ---- against the C++ (vpp::mean_interval, the paired differences of `vppdem sweep`)

def published_tables(name):
    return sorted(glob.glob(os.path.join(SOURCE_DIR, "docs", "data", "paper", "report", "*", name)))


def rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def test_the_cpp_tables_use_the_same_t():
    # Every interval the C++ wrote into the published tables (summary_cases.csv: a quantity's mean
    # over the seeds; summary_paired.csv: the paired differences) has half width t sd / sqrt(n):
    # the t it used, ci95 sqrt(n) / sd, is this module's t_{0.975, n-1}.
    checked = 0
    for path in published_tables("summary_cases.csv"):
        for r in rows(path):
            for q in [k[:-2] for k in r if k.endswith("_n")]:
                n, sd, h = r[q + "_n"], r.get(q + "_sd", ""), r.get(q + "_ci95", "")
                if n and int(n) >= 2 and sd and h and float(sd) > 0:
                    t = float(h) * math.sqrt(int(n)) / float(sd)
                    assert t == pytest.approx(stats.t_quantile(0.975, int(n) - 1), rel=1e-12), (path, q, r)
                    checked += 1
    for path in published_tables("summary_paired.csv"):
        for r in rows(path):
            if r["n"] and int(r["n"]) >= 2 and r["diff_sd"] and float(r["diff_sd"]) > 0:
                t = float(r["diff_ci95"]) * math.sqrt(int(r["n"])) / float(r["diff_sd"])
                assert t == pytest.approx(stats.t_quantile(0.975, int(r["n"]) - 1), rel=1e-12), (path, r)
                checked += 1
    if not checked:
        pytest.skip("no published tables with intervals in docs/data/paper/report")
    assert checked > 100


def test_the_cpp_intervals_of_W_recomputed():
    # W over each case's seeds, from summary.csv's runs, is the interval summary_cases.csv has.
    checked = 0
    for path in published_tables("summary_cases.csv"):
        runs = {r["case"]: r for r in rows(os.path.join(os.path.dirname(path), "summary.csv"))}
        for r in rows(path):
            cases = [c for c in r["cases"].split(";") if c in runs and runs[c]["status"] == "ok"]
            ws = [float(runs[c]["W"]) for c in cases if runs[c]["W"]]
            if len(ws) < 2 or int(r["W_n"]) != len(ws):
                continue
            n, m, s, h = stats.interval(ws)
            assert m == pytest.approx(float(r["W_mean"]), rel=1e-13), (path, r["cases"])
            assert s == pytest.approx(float(r["W_sd"]), rel=1e-11), (path, r["cases"])
            assert h == pytest.approx(float(r["W_ci95"]), rel=1e-11), (path, r["cases"])
            checked += 1
    if not checked:
        pytest.skip("no published tables with W intervals in docs/data/paper/report")


# ---- the reports' command lines

def test_every_report_imports_and_prints_its_usage():
    import importlib
    import vppdem.report as rep
    assert set(rep.REPORTS) == {"paper", "operation", "grain_shapes", "robustness", "paired_velocity",
                                "velocity_cycles", "paper_velocity_cycle1", "friction_split", "foil", "device",
                                "device_slices", "membrane_cylinder"}
    for name, (module, _) in rep.REPORTS.items():
        m = importlib.import_module(f"vppdem.report.{module}")
        assert callable(m.main), name
        r = report([name, "--help"])
        assert r.returncode == 0, (name, r.stderr)
        assert "usage:" in r.stdout and name in r.stdout, (name, r.stdout)


def test_the_reports_use_the_one_student_t():
    # No report keeps a t quantile or an incomplete beta function of its own.
    folder = os.path.join(SOURCE_PACKAGE, "vppdem", "report")
    for f in sorted(os.listdir(folder)):
        if f.endswith(".py") and f != "stats.py":
            text = open(os.path.join(folder, f)).read()
            assert "def t_quantile" not in text and "def incomplete_beta" not in text and "def _betacf" not in text, f
            assert "scipy" not in text, f


def test_the_entry_point_lists_the_reports_and_refuses_an_unknown_one():
    r = report([])
    assert r.returncode == 2 and "paired_velocity" in r.stdout and "paper" in r.stdout
    r = report(["papper"])
    assert r.returncode == 2 and "unknown report 'papper'" in r.stderr


def test_paired_velocity_by_hand(tmp_path):
    # Three seeds whose packings differ by +-10 J/m^2; the offsets against 0.005 m/s are 1, 2, 0 at
    # 0.05 m/s (interval 1 +- t_{0.975,2} / sqrt(3) = 1 +- 2.484: within) and 10, 11, 9 at 0.1 m/s
    # (not): the converged velocity is 0.05 m/s (test_report_paired_velocity.py, the same data).
    lines = ["process.velocity,simulation.seed,W,status,case"]
    for v, off in (("0.1", (10, 11, 9)), ("0.05", (1, 2, 0)), ("0.005", (0, 0, 0))):
        for s, (base, o) in enumerate(zip((100, 110, 90), off), 1):
            lines.append(f"{v},{s},{base + o},ok,c{v}_{s}")
    (tmp_path / "summary.csv").write_text("\n".join(lines) + "\n")
    r = report(["paired_velocity", str(tmp_path), "--quantities", "W"])
    assert r.returncode == 0, r.stderr
    assert "W: fastest velocity within the paired 95% interval of 0.005 m/s (and every slower one): 0.05 m/s" in r.stdout
    got = {row["velocity"]: row for row in rows(tmp_path / "paired_velocity.csv")}
    assert float(got["0.05"]["diff_ci95"]) == pytest.approx(4.302652730 / math.sqrt(3), rel=1e-9)
    assert (got["0.05"]["within"], got["0.1"]["within"]) == ("1", "0")
    bad = report(["paired_velocity", str(tmp_path / "missing")])
    assert bad.returncode != 0 and "vppdem.report paired_velocity:" in bad.stderr
