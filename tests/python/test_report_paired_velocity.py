# vppdem.report paired_velocity by hand (scripts/trust_studies.sh's velocity convergence; docs/studies.md,
# "Velocity convergence"): paired differences against the slowest velocity on a sweep with seeds.
import math
import os

import pytest

from synthetic_records import rows_of, num, run_report, write_file


# Three seeds whose packings differ by +-10 J/m^2 (far more than the velocity effect): the
# unpaired intervals overlap everywhere, the paired differences do not. W(v, s) = base_s +
# offset(v, s) with offsets 0 (0.005 m/s), 1, 2, 0 (0.05 m/s), 10, 11, 9 (0.1 m/s): at 0.05 m/s the
# differences 1, 2, 0 have mean 1, sd 1 and the interval 1 +- t_{0.975,2} / sqrt(3) = 1 +- 2.484,
# which holds 0; at 0.1 m/s 10 +- 2.484, which does not. The converged velocity is 0.05 m/s.
def test_paired_velocity_intervals_by_hand(tmp_path):
    d = tmp_path / "paired"
    csv = ("process.underpressure,process.velocity,simulation.seed,W,dissipated_energy,peak_force,run_seconds,"
           "status,case,W_settled,settled_cycles,first_settled_cycle,friction_share,damping_share,grains,"
           "packing_fraction,warnings\n")
    base = [100, 110, 90]
    offset = {"0.005": [0, 0, 0], "0.05": [1, 2, 0], "0.1": [10, 11, 9]}
    for v, off in offset.items():
        for s in range(3):
            csv += (f"60000,{v},{s + 1},{num(float(base[s] + off[s]))},1,500,1,ok,c{v}_{s},,0,,,,60,0.6,\n")
    write_file(d / "summary.csv", csv)
    status, output = run_report("paired_velocity", d)
    assert status == 0, output
    assert ("W: fastest velocity within the paired 95% interval of 0.005 m/s (and every slower one): "
            "0.05 m/s") in output
    t2 = 0.95 / math.sqrt(2 * 0.975 * 0.025)  # t_{0.975,2}, closed form
    seen = 0
    for row in rows_of(d / "paired_velocity.csv"):
        if row["quantity"] != "W":
            continue
        v = row["velocity"]
        assert row["n"] == "3"
        assert row["diff_n"] == "3"
        if v == "0.05":
            seen += 1
            assert float(row["diff_mean"]) == pytest.approx(1.0, abs=1e-9)
            assert float(row["diff_sd"]) == pytest.approx(1.0, abs=1e-9)
            assert float(row["diff_ci95"]) == pytest.approx(t2 / math.sqrt(3.0), abs=1e-8)
            assert row["within"] == "1"
            assert row["converged"] == "1"
            # Unpaired: 101, 112, 90: mean 101, sd 11, half width t2 * 11 / sqrt(3).
            assert float(row["mean"]) == pytest.approx(101.0, abs=1e-9)
            assert float(row["ci95"]) == pytest.approx(t2 * 11.0 / math.sqrt(3.0), abs=1e-7)
        elif v == "0.1":
            seen += 1
            assert float(row["diff_mean"]) == pytest.approx(10.0, abs=1e-9)
            assert row["within"] == "0"
            assert row["converged"] == "0"
    assert seen == 2
    assert os.path.exists(d / "paired_velocity.png")
    # A sweep without seeds cannot be paired: said so, nonzero exit.
    write_file(d / "noseed" / "summary.csv", "process.velocity,W,status\n0.1,5,ok\n")
    status, output = run_report("paired_velocity", d / "noseed")
    assert status != 0
    assert "simulation.seed" in output
