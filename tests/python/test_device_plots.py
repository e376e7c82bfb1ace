# The plots and the report of device runs and device studies (issue 61, item 2): `vppdem plot DIR`
# on a `vppdem device` folder (vppdem.plot.device) and on a device study's folder
# (vppdem.plot.device_study), and `python3 -m vppdem.report device FOLDER` on any device study's
# folder (vppdem.report.device.study_report), on synthetic records with known answers, in this
# process (numpy and matplotlib only).
import gzip
import math
import os

import numpy as np
import pytest

import vppdem.plot as vplot
from synthetic_records import read, run_report, write_file

T2 = 4.302652729749464   # Student's t_{0.975, 2}
T4 = 2.7764451051977987  # t_{0.975, 4}


def plot_command(capsys, *args):
    """`python3 -m vppdem.plot ARGS` in this process: (exit status, stdout, stderr). (The command's
    own path, `vppdem plot` through src/python without the compiled module: test_device.py,
    test_plot.py.)"""
    try:
        vplot.main([str(a) for a in args])
        status = 0
    except SystemExit as e:
        status = e.code
    out = capsys.readouterr()
    return status, out.out, out.err


@pytest.fixture
def figures(monkeypatch):
    """The figures the plots save, {file name: Figure} (the files are written as well)."""
    saved = {}
    save = vplot._save

    def keep(fig, path, dpi):
        saved[os.path.basename(path)] = fig
        return save(fig, path, dpi)
    monkeypatch.setattr(vplot, "_save", keep)
    return saved


# ---- a device run ------------------------------------------------------------------------------
# Two tools: the holder moves (down in the press, holds in the vacuum, up in the load), the object
# is fixed; stages 0-4 at rows 0-1, 2, 3-4, 5-6, 7-9.
STAGE = [0, 0, 1, 2, 2, 3, 3, 4, 4, 4]
TIME = [0.001 * (k + 1) for k in range(10)]
HOLDER_Z = [0, 0, 0, -0.001, -0.002, -0.002, -0.002, -0.001, 0.0, 0.001]
HOLDER_FZ = [0, 0, 0, -0.5, -1.0, -1.0, -1.1, -0.2, 0.1, 0.0]
OBJECT_FZ = [0, 0, 0, -0.4, -0.9, -1.0, -1.0, 0.2, 0.3, 0.0]
DP = [0, 0, 0, 0, 0, 25000, 50000, 50000, 50000, 50000]
VOLUME = [1e-6, 1e-6, 1e-6, 0.99e-6, 0.98e-6, 0.95e-6, 0.9e-6, 0.9e-6, 0.9e-6, 0.9e-6]


def tools_text(rows=range(10)):
    lines = ["time,stage,holder_z,holder_fx,holder_fy,holder_fz,object_z,object_fx,object_fy,object_fz"]
    for k in rows:
        lines.append(f"{TIME[k]},{STAGE[k]},{HOLDER_Z[k]},0,0,{HOLDER_FZ[k]},0,0,0,{OBJECT_FZ[k]}")
    return "\n".join(lines) + "\n"


def device_run(d):
    write_file(d / "tools.csv", tools_text())
    write_file(d / "air.csv", "time,stage,enclosed_volume,gas_volume,dp\n" + "".join(
        f"{TIME[k]},{STAGE[k]},{VOLUME[k]},{VOLUME[k] - 0.5e-6},{DP[k]}\n" for k in range(10)))
    write_file(d / "summary.json", '{"stage": "done", "object": "object", "holding_force": 0.3, '
                                   '"underpressure": 50000, "stiffness": 0}\n')
    return d


def axes_titled(fig, title):
    return [ax for ax in fig.axes if ax.get_title() == title]


def points(ax):
    """Every (x, y) the axes' labelled lines draw, and {label: the first point of its line}."""
    pts, first = set(), {}
    for line in ax.get_lines():
        if line.get_label().startswith("_"):
            continue
        xs, ys = line.get_xdata(), line.get_ydata()
        pts |= {(round(float(x), 12), round(float(y), 12)) for x, y in zip(xs, ys)}
        first[line.get_label()] = (float(xs[0]), float(ys[0]))
    return pts, first


def test_stage_spans_are_the_runs_of_equal_stage_numbers():
    assert vplot.stage_spans(TIME, STAGE) == [(0, 0.001, 0.002), (1, 0.003, 0.003), (2, 0.004, 0.005),
                                              (3, 0.006, 0.007), (4, 0.008, 0.01)]


def test_a_device_run_is_drawn_from_its_records(tmp_path, figures):
    d = device_run(tmp_path / "run")
    assert vplot.kind_of(str(d)) == "device"
    written = vplot.device(d)
    assert written == [str(d / "device_tools.png"), str(d / "device_air.png")]
    assert all(os.path.getsize(p) > 0 for p in written)
    fig = figures["device_tools.png"]
    # The holder's force against its displacement: the records' points, one line per stage, each
    # starting at its stage's first row.
    (ax,) = axes_titled(fig, "holder: force against displacement")
    pts, first = points(ax)
    assert pts == {(round(1e3 * z, 12), round(f, 12)) for z, f in zip(HOLDER_Z, HOLDER_FZ)}
    assert first == {"fill": (0.0, 0.0), "seal": (0.0, 0.0), "press": (-1.0, -0.5), "vacuum": (-2.0, -1.0),
                     "load": (-1.0, -0.2)}
    # Against time, with a marker at each stage's start.
    (ax,) = axes_titled(fig, "holder: force against time")
    pts, _ = points(ax)
    assert pts == {(round(t, 12), round(f, 12)) for t, f in zip(TIME, HOLDER_FZ)}
    starts = sorted(float(line.get_xdata()[0]) for line in ax.get_lines() if line.get_label().startswith("_")
                    and line.get_linestyle() == ":")
    assert starts == [0.001, 0.003, 0.004, 0.006, 0.008]
    assert [t.get_text().strip() for t in ax.texts] == ["fill", "seal", "press", "vacuum", "load"]
    # The fixed object: its force against time only.
    (ax,) = axes_titled(fig, "object: force against time")
    assert points(ax)[0] == {(round(t, 12), round(f, 12)) for t, f in zip(TIME, OBJECT_FZ)}
    assert not axes_titled(fig, "object: force against displacement")
    assert any("object does not move" in t.get_text() for a in fig.axes for t in a.texts)
    # The title: dp and the holding force; no stiffness without result.cycle_tool.
    assert fig._suptitle.get_text().startswith("device run: dp 50 kPa, holding force 0.3 N (object) (F_z")
    # dp [kPa] and the enclosed volume [cm^3] against time.
    air = figures["device_air.png"]
    (ax,) = axes_titled(air, "underpressure")
    assert points(ax)[0] == {(round(t, 12), round(p * 1e-3, 12)) for t, p in zip(TIME, DP)}
    (ax,) = axes_titled(air, "enclosed volume (through the membrane particles' centres)")
    pts, _ = points(ax)
    assert {(round(t, 12), round(v * 1e6, 12)) for t, v in zip(TIME, VOLUME)} <= pts


def test_a_published_device_run_is_drawn_from_tools_csv_gz(tmp_path, figures):
    # A published run: tools.csv.gz (the rows from the press on), no air.csv.
    d = tmp_path / "dp50_s1"
    d.mkdir()
    with gzip.open(d / "tools.csv.gz", "wt") as f:
        f.write(tools_text(range(3, 10)))
    assert vplot.kind_of(str(d)) == "device"
    assert vplot.device(d) == [str(d / "device_tools.png")]
    (ax,) = axes_titled(figures["device_tools.png"], "holder: force against time")
    assert points(ax)[0] == {(round(TIME[k], 12), round(HOLDER_FZ[k], 12)) for k in range(3, 10)}


def test_the_command_draws_a_device_run_and_names_a_bad_record(tmp_path, capsys):
    d = device_run(tmp_path / "run")
    status, out, err = plot_command(capsys, d)
    assert status == 0, err
    assert out.split() == [str(d / "device_tools.png"), str(d / "device_air.png")]
    write_file(d / "tools.csv", "time,stage,holder_z,holder_fz\n0,0,0,0\n")
    status, out, err = plot_command(capsys, d)
    assert status == 1
    assert "tools.csv: not a device's tools.csv" in err and "NAME_z,NAME_fx,NAME_fy,NAME_fz" in err
    with pytest.raises(vplot.PlotError, match="tools.csv not found"):
        vplot.device(tmp_path)


# ---- a device study ----------------------------------------------------------------------------
NUMBERS = ["holding_force", "press_force", "underpressure", "volume_change", "volume_change_vacuum", "packing_seal",
           "packing_vacuum", "grains", "stiffness", "work_per_cycle", "peak_force", "energy_residual", "energy_scale",
           "holding_ratio", "object_area", "suction_force_max", "seal_area"]
# Case a: holding force 1, 2, 3 N over seeds 1-3 (mean 2, sd 1, half width t_2 / sqrt 3); case b:
# 2, 3, 4 N (b - a: +1 in every seed); case c: seed 1 only, seed 2 failed. grains 570 in every run.
RUNS = [("a", 1, 1.0, -0.10), ("b", 1, 2.0, -0.20), ("c", 1, 5.0, -0.3), ("a", 2, 2.0, -0.12), ("b", 2, 3.0, -0.22),
        ("a", 3, 3.0, -0.14), ("b", 3, 4.0, -0.24)]


def summary_csv(d, with_failed=True):
    lines = ["case,seed,folder," + ",".join(NUMBERS) + ",status,message"]
    for case, seed, hf, dv in RUNS:
        values = {"holding_force": hf, "volume_change": dv, "grains": 570, "underpressure": 50000}
        lines.append(f"{case},{seed},{case}_s{seed}," + ",".join(str(values.get(q, "")) for q in NUMBERS) + ",ok,")
    if with_failed:
        lines.append(f"c,2,c_s2," + "," * (len(NUMBERS) - 1) + ",failed,\"the run stopped, badly\"")
    write_file(d / "summary.csv", "\n".join(lines) + "\n")


def cases_csv(d):
    """summary_cases.csv as `vppdem sweep` writes it (test DeviceStudy.CasesTableHoldsTheMean...)."""
    head = "case,seeds,ok," + ",".join(f"{q}_n,{q}_mean,{q}_sd,{q}_ci95" for q in NUMBERS) + ",folders"
    rows = [head]
    for case, n, hf, dv in (("a", 3, (2.0, 1.0, T2 / math.sqrt(3)), (-0.12, 0.02, T2 * 0.02 / math.sqrt(3))),
                            ("b", 3, (3.0, 1.0, T2 / math.sqrt(3)), (-0.22, 0.02, T2 * 0.02 / math.sqrt(3))),
                            ("c", 1, (5.0, None, None), (-0.3, None, None))):
        cells = []
        for q in NUMBERS:
            st = {"holding_force": hf, "volume_change": dv, "grains": (570, 0, 0) if n > 1 else (570, None, None),
                  "underpressure": (50000, 0, 0) if n > 1 else (50000, None, None)}.get(q)
            cells += [str(n if st else 0)] + (["" if x is None else repr(x) for x in st] if st else ["", "", ""])
        seeds = 3 if case != "c" else 2
        rows.append(f"{case},{seeds},{n}," + ",".join(cells) + "," + ";".join(f"{case}_s{s}" for s in range(1, seeds + 1)))
    write_file(d / "summary_cases.csv", "\n".join(rows) + "\n")


def test_a_device_study_draws_each_number_against_the_case_with_its_interval(tmp_path, figures):
    d = tmp_path / "study"
    summary_csv(d)
    cases_csv(d)
    assert vplot.kind_of(str(d)) == "device_study"
    cases, stats, intervals = vplot.device_study_cases(d)
    assert cases == ["a", "b", "c"] and intervals
    assert stats["holding_force"]["a"] == (2.0, pytest.approx(T2 / math.sqrt(3)), [1.0, 2.0, 3.0])
    assert stats["holding_force"]["c"] == (5.0, None, [5.0])  # one run: no interval; the failed run left out
    assert set(stats) == {"holding_force", "volume_change", "grains", "underpressure"}  # numbers the runs have
    assert vplot.device_study(d) == [str(d / "sweep_numbers.png")]
    fig = figures["sweep_numbers.png"]
    # A panel per number that differs between runs: the means with their intervals, each run a dot.
    assert [ax.get_title() for ax in fig.axes if ax.axison] == ["holding_force", "volume_change"]
    (ax,) = axes_titled(fig, "holding_force")
    bars = ax.containers[0]
    assert list(bars.lines[0].get_xdata()) == [0, 1, 2]
    assert list(bars.lines[0].get_ydata()) == [2.0, 3.0, 5.0]
    spans = [seg[:, 1] for seg in bars.lines[2][0].get_segments()]
    assert [tuple(np.round(s, 9)) for s in spans] == [
        (round(2 - T2 / math.sqrt(3), 9), round(2 + T2 / math.sqrt(3), 9)),
        (round(3 - T2 / math.sqrt(3), 9), round(3 + T2 / math.sqrt(3), 9)), (5.0, 5.0)]
    dots = sorted((float(x), float(y)) for line in ax.get_lines() if line.get_marker() == "."
                  for x, y in zip(line.get_xdata(), line.get_ydata()))
    assert dots == [(0, 1.0), (0, 2.0), (0, 3.0), (1, 2.0), (1, 3.0), (1, 4.0), (2, 5.0)]
    (ax,) = axes_titled(fig, "volume_change")
    assert ax.get_ylabel() == "volume change, seal to end of vacuum [%]"
    assert [round(float(y), 9) for y in ax.containers[0].lines[0].get_ydata()] == [-12.0, -22.0, -30.0]
    # The numbers the same in every run, named under the figure.
    assert any(t.get_text() == "the same in every run: underpressure 50 kPa, grains 570" for t in fig.texts)


def test_without_summary_cases_csv_the_means_are_drawn_without_intervals(tmp_path, figures, capsys):
    d = tmp_path / "old"
    summary_csv(d)
    cases, stats, intervals = vplot.device_study_cases(d)
    assert not intervals and stats["holding_force"]["b"] == (3.0, None, [2.0, 3.0, 4.0])
    vplot.device_study(d, caption="by hand", prefix="fig")
    assert "summary_cases.csv not found" in capsys.readouterr().err
    (ax,) = axes_titled(figures["fig_numbers.png"], "holding_force")
    assert not ax.containers[0].has_yerr


def test_the_command_draws_a_device_study_and_refuses_a_folder_without_finished_runs(tmp_path, capsys):
    d = tmp_path / "study"
    summary_csv(d)
    cases_csv(d)
    status, out, err = plot_command(capsys, d, "--prefix", "fig")
    assert status == 0, err
    assert out.split() == [str(d / "fig_numbers.png")]
    write_file(d / "summary.csv", "case,seed,folder,holding_force,status,message\na,1,a_s1,,not run,\n")
    status, out, err = plot_command(capsys, d)
    assert status == 1 and "no finished run (status ok)" in err


# ---- the report of any device study's folder ------------------------------------------------------

def table_row(page, case):
    line = next(x for x in page.splitlines() if x.startswith(f"| `{case}` |"))
    return [c.strip() for c in line.strip("|").split("|")]


def test_the_report_of_a_study_folder_has_the_means_intervals_and_differences(tmp_path):
    d = tmp_path / "study"
    summary_csv(d)
    status, out = run_report("device", d)
    assert status == 0, out
    page = read(d / "device_report.md")
    assert out.strip() == str(d / "device_report.md")
    assert os.path.getsize(d / "device_report.png") > 0
    head = next(x for x in page.splitlines() if x.startswith("| case |"))
    assert head == "| case | n | holding force [N] | volume change, seal to end of vacuum [%] |"
    # mean ± the 95% Student-t half width: a 2 ± 2.5 N, volume -12 ± 5.0%; c one run, no interval
    assert table_row(page, "a") == ["`a`", "3", f"2 ± {T2 / math.sqrt(3):.2g}", f"-12 ± {T2 * 2 / math.sqrt(3):.2g}"]
    assert table_row(page, "c") == ["`c`", "1", "5", "-30"]
    assert "The same in every run: underpressure 50 kPa, grains 570." in page
    # b - a by Welch: +1 N, se sqrt(2/3), 4 degrees of freedom
    row = next(x for x in page.splitlines() if x.startswith("| `b` - `a` |"))
    assert f"+1 ± {T4 * math.sqrt(2 / 3):.3g}, not resolved" in row
    # paired by seed: +1 N in every seed, resolved
    status, out = run_report("device", d, "--test", "paired", "--out", tmp_path / "paired")
    assert status == 0, out
    row = next(x for x in read(tmp_path / "paired" / "device_report.md").splitlines() if x.startswith("| `b` - `a` |"))
    assert "+1 ± 0, resolved" in row


def test_the_report_reads_run_folders_without_summary_csv(tmp_path):
    # A published folder from before the studies wrote summary.csv: <case>_s<seed>/summary.json.
    d = tmp_path / "published"
    for case, seed, hf, dv in RUNS:
        write_file(d / f"{case}_s{seed}" / "summary.json",
                   f'{{"stage": "done", "holding_force": {hf}, "volume_change": {dv}, "grains": 570}}\n')
    write_file(d / "c_s2" / "summary.json", '{"stage": "load", "holding_force": 9}\n')  # unfinished: left out
    status, out = run_report("device", d)
    assert status == 0, out
    page = read(d / "device_report.md")
    assert "from the run folders' summary.json" in page
    assert table_row(page, "a")[:3] == ["`a`", "3", f"2 ± {T2 / math.sqrt(3):.2g}"]
    assert table_row(page, "c")[:3] == ["`c`", "1", "5"]


def test_the_report_keeps_the_shipped_studies_and_refuses_what_is_neither(tmp_path, monkeypatch):
    from vppdem.report import device
    called = []
    monkeypatch.setattr(device, "load", lambda study: {"study": study})
    monkeypatch.setattr(device, "beam", lambda runs: called.append(runs) or {})
    monkeypatch.setattr(device, "trends", lambda: True)
    assert run_report("device", "beam")[0] == 0
    assert called == [{"study": "beam"}]
    status, out = run_report("device", tmp_path / "missing")
    assert status == 2 and "is neither a shipped study (gripper, gripper_pour, beam, trends, gripper_jamming) nor a folder" in out
    status, out = run_report("device", tmp_path)
    assert status == 2 and "no finished run" in out
    status, out = run_report("device", "beam", "--out", tmp_path)
    assert status == 2 and "--out and --test are for a study's folder" in out
