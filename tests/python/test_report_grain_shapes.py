# vppdem.report grain_shapes (docs/grains.md, after scripts/grain_shapes.sh) by hand.
import os

from synthetic_records import read, run_report, write_file


def summary(W, peak, dp):
    """A shape run's summary.json (numbers as a C++ stream writes them: 6 significant digits)."""
    return (f'{{"inputs": {{"process.velocity": 0.02, "process.underpressure": {dp:g}, "damper.radius": 0.0255}}, '
            f'"grains": 1100, "dt": 1.8e-06, "run_seconds": 3600, '
            f'"cycles": [{{"cycle": 1, "W": {W + 50:g}, "peak_force": {peak:g}, '
            f'"friction_dissipation": 3, "damping_dissipation": 1, "viscous_dissipation": 0}}, '
            f'{{"cycle": 2, "W": {W:g}, "peak_force": {peak:g}, '
            f'"friction_dissipation": 3, "damping_dissipation": 1, "viscous_dissipation": 0}}], '
            f'"W_settled": {W:g}, "first_settled_cycle": 2, "start_of_cycling": {{"packing_fraction": 0.6}}}}')


# Spheres W = 100, 110, 120 and dimers 210, 220, 230 J/m^2 (3 seeds, sd 10 each): the dimers'
# difference is +110 (+100% of 110) with Welch's interval t_{0.975,4} sqrt(100/3 + 100/3) = 2.7764 *
# 8.165 = 22.67 (20.6% of 110), printed "+100 +- 21"; the pressure study's W doubles from 0.02 to
# 0.08 MPa for every seed: 2.00 +- 0.00. Against a plan of spheres and dimers the page is final;
# against the repository's study (pellets too) it says 6 of 9 runs and names the pending ones.
def test_grain_shapes_report_by_hand(tmp_path):
    d = tmp_path / "shapes"
    for s in range(1, 4):
        write_file(d / "data" / f"grains.shape=sphere_simulation.seed={s}" / "summary.json",
                   summary(90.0 + 10.0 * s, 500, 60000))
        write_file(d / "data" / f"grains.shape=dimer_simulation.seed={s}" / "summary.json",
                   summary(200.0 + 10.0 * s, 900, 60000))
        for dp in (20000.0, 80000.0):
            write_file(d / "pressure" / f"damper.radius=0.0255_process.underpressure={int(dp)}_simulation.seed={s}"
                       / "summary.json", summary((2.0 if dp > 50000 else 1.0) * (100.0 + s), 500, dp))
    os.makedirs(d / "docs")
    write_file(d / "plan.toml", 'seeds = 3\n[grid]\n"grains.shape" = ["sphere", "dimer"]\n')

    def report(*args):
        return run_report("grain_shapes", d / "data", d / "docs", *args)

    with_plan = ("--pressure", d / "pressure", "--study", d / "plan.toml")
    status, output = report(*with_plan)
    assert status == 0, output
    md = read(d / "docs" / "grains.md")
    assert "Provisional" not in md
    assert "| sphere | 3 of 3 |" in md
    assert "| 110 +- 25 |" in md  # t_{0.975,2} 10 / sqrt(3) = 24.8
    # Dimers 210, 220, 230 against spheres 100, 110, 120: R = 2, var(ln R) = 100 / (3 110^2) + 100 /
    # (3 220^2) = 0.0034435 (se 0.058682), Welch dof 2.9412, t = 3.2188: R t se = 0.378, +100 +- 38%.
    assert "| +100 +- 38 |" in md
    assert "W 2.00 +- 0.38 times the spheres'" in md
    assert "W at 0.08 MPa is 2.00 +- 0.00 times W at 0.02 MPa" in md
    # Both effects ln 2; the pressure's without scatter: the difference's half width is the
    # dimers' t se = 0.189 at 2.94 dof, and 0 lies inside it.
    assert "dimer: consistent, not established, not resolved (+0.00 +- 0.19)" in md
    assert "+- 0.19)" in md
    # Peak forces 900 against 500 N in every run: 1.80 times, without scatter, resolved.
    assert "peak force over the stroke 1.80 +- 0.00 times (resolved)" in md
    assert "changes with the shape for dimer (resolved)." in md
    assert "friction share" in md
    assert os.path.exists(d / "docs" / "grains_shapes.png")
    # The pressure runs' stationarity by the paper report's re-analysis beside them: seed 1 at
    # 0.08 MPa not stationary there, so its W is the mean of its last two cycles, 202 + 25 = 227,
    # and its ratio 227 / 101 = 2.2475; with 2 and 2 the mean ratio is 2.08.
    write_file(d / "report" / "pressure" / "summary.csv",
               "case,W_settled\ndamper.radius=0.0255_process.underpressure=80000_simulation.seed=1,\n")
    status, output = report(*with_plan)
    assert status == 0, output
    rmd = read(d / "docs" / "grains.md")
    assert "W at 0.08 MPa is 2.08 +- " in rmd
    assert "1 of these 6 runs not stationary" in rmd
    # The repository's plan: pellets too, none run.
    status, output = report()
    assert status == 0, output
    pmd = read(d / "docs" / "grains.md")
    assert "Provisional: 6 of the study's 9 runs" in pmd
    assert "pellet seed 1, pellet seed 2, pellet seed 3" in pmd
    assert "| pellet | 0 of 3 | pending" in pmd
    # A folder without runs is refused naming it.
    os.makedirs(d / "empty")
    status, output = run_report("grain_shapes", d / "empty", d / "docs")
    assert status != 0
    assert "no finished runs" in output
