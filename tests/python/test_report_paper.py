# vppdem.report paper (docs/paper_comparison.md: the paper's claims decided from the studies' runs,
# scripts/paper_report.sh) on hand-made records of the underpressure, modulus, radius and time step
# studies: the claims C1, C9, C26, C28 and C5 from paired and Welch intervals.
import math
import os

import pytest

from synthetic_records import paper_report, row, rows_of, section, write_run


# The report on hand-made records of the underpressure study (25.5 mm, four dp x 3 seeds, 5 flat
# cycles each: every run stationary): W(dp, s) = 500 + 10 s + k (dp - 0.02 MPa) + e(dp, s), with
# e = 0 at 0.02 MPa and 0, 6, 12 over the seeds above it. The paired difference of 0.06 MPa from
# 0.02 MPa is then 1000 + {0, 6, 12}: mean 1006, sd 6, 95% half width t_{0.975,2} 6 / sqrt(3) =
# 4.3027 * 3.4641 = 14.9 J/m^2 (the seeds' +-10 J/m^2 offsets cancel). Every dp is higher than
# 0.02 MPa beyond its interval: C1 is reproduced, provisionally (the repository's radius study plans
# 5 seeds; its means say '(n 3 of 5)'). The page, its figure and the published tables are written
# (the first time by scripts/paper_report.sh itself); the study without runs stays open.
def test_paper_report_decides_a_claim_from_paired_intervals(tmp_path):
    d = tmp_path / "paper_report"
    data = d / "data"

    def underpressure_rows(first, last):
        """The 25.5 mm rows of seeds first..last (the formula above)."""
        for dp in (20000, 40000, 60000, 80000):
            for s in range(first, last + 1):
                W = 500 + 10 * s + 0.025 * (dp - 20000) + (6 * (s - 1) if dp > 20000 else 0)
                write_run(data / "radius_underpressure" /
                          f"damper.radius=0.0255_process.underpressure={dp}_simulation.seed={s}", [W] * 5)

    underpressure_rows(1, 3)
    page = paper_report(data, d, script=True)
    assert "0.06: +1006 +- 15 (+193%)" in page
    assert "0.02 MPa: 520 +- 25 (n 3 of 5)" in page  # 510, 520, 530: t 10 / sqrt(3) = 24.8
    # The repository's modulus and radius studies run 5 seeds, 3 planned (seeds 4-5 added after a
    # look): the verdicts are decided over the planned 3 (PLANNED in vppdem.report.paper).
    # C1 by the rules: paired, over the 3 seeds the study planned (no added seeds yet: nothing beside).
    assert ("| reproduced: 0.04 MPa +506 +- 15 (+97%); 0.06 MPa +1006 +- 15 (+193%); 0.08 MPa +1506 +- 15 "
            "(+290%) |") in page
    assert "12 of 12 finished 5-cycle runs are stationary" in page
    # The rules at the head; the claims issue 44 added; the stationary-W, packing and friction-share sections.
    for s in ("## Decision rules", "**Welch t** (95%, two-sided; Welch-Satterthwaite degrees of freedom)",
              "+-10% of the reference's mean", "| C31 |", "| C32 |", "| C33 |", "## Stationary W",
              "## W and the packing", "## Friction share: local damping and loading speed"):
        assert s in page, s
    assert "| C16 |" in page
    assert "open (runs pending)" in page  # friction: no runs
    # The studies whose reference cases are another study's runs take them from it: the
    # modulus study's 2.3 GPa is the underpressure study's 0.06 MPa (1510, 1526, 1542: t 16 /
    # sqrt(3) = 39.7), the preparation study's re-fill its 0.02 MPa. (They stayed pending while
    # the assembly's loop variable was shadowed.)
    assert "2300 MPa: 1526 +- 40" in page
    assert "0.02 MPa: re-fill 520 +- 25" in page
    assert os.path.exists(d / "paper_underpressure_radius.png")
    found = False
    for p in rows_of(data / "report" / "radius_underpressure" / "summary_paired.csv"):
        if (p["key"] == "process.underpressure" and p["value"] == "60000" and p["quantity"] == "W_settled"
                and p["group"] == "damper.radius=0.0255"):
            found = True
            assert float(p["diff_mean"]) == pytest.approx(1006.0, abs=1e-9)
            assert float(p["diff_ci95"]) == pytest.approx(4.302652729911275 * 6.0 / math.sqrt(3.0), abs=1e-6)
    assert found

    # C9 (insensitive to E_k) is decided, provisionally (the study plans 5), once every modulus has
    # 3 seeds (a paired difference over fewer is shown, marked with its n, and decides nothing). Against the 2.3 GPa
    # runs above (1510, 1526, 1542): 23 MPa 800 + s (resolved, lower), 230 MPa 20 lower in every
    # seed (-20 +- 0: within 10% of 1526), 23 GPa -100, +100, 0 (sd 100, half width 4.303 * 100 /
    # sqrt(3) = 248 > 153: unresolved, reaching past 10%).
    ref, off23g = [1510, 1526, 1542], [-100, 100, 0]

    def young(e, s, W):
        write_run(data / "young" / f"grains.young={e}_simulation.seed={s}", [float(W)] * 5)

    for s in range(1, 4):
        young("2.3e+07", s, 800 + s)
        young("2.3e+08", s, ref[s - 1] - 20)
        if s < 3:
            young("2.3e+10", s, ref[s - 1] + off23g[s - 1])

    def c9():
        return row(paper_report(data, d), "C9")

    v = c9()
    assert "23000 MPa: 1518 +- 1372 (n 2 of 5)" in v, v  # 1410, 1626: 12.71 * 152.7 / sqrt(2)
    assert "| open (runs pending) |" in v, v  # 23 GPa: 2 of 3 seeds
    # Welch (each modulus its own samples) over the seeds in, shown; 23 GPa short of its 3 planned seeds:
    # not decided. 230 MPa: sds 16 and 16 over 3, se 13.06, dof 4: 2.776 * 13.06 = 36.
    assert ("against 2.3 GPa (Welch, all seeds): 23 MPa -724 +- 40 (-47%); 230 MPa -20 +- 36 (-1%); "
            "23000 MPa -8 +- 1331 (-1%)") in v, v
    young("2.3e+10", 3, ref[2] + off23g[2])
    v = c9()
    # 230 MPa within 10% of 1526 (-20 +- 36), 23 GPa not resolved, reaching past 10% (+0 +- 263, Welch dof 2.09).
    assert ("| consistent, not established: 23 MPa -724 +- 40 (-47%); 230 MPa -20 +- 36 (-1%); 23000 MPa +0 +- "
            "263 (+0%) |") in v, v

    # C28 (a wider damper has lower W) per radius against 25.5 mm, at each dp: 30.5 mm is
    # W_25.5 - 300 - 10 s (-320 +- 24.8: below, resolved, the paper's direction at 4 of 4 dp);
    # 20.5 mm is W_25.5 - 20 + {50, -50, 0} (-20 +- 4.303 * 50 / sqrt(3) = 124: not resolved).
    # Both below in the mean: W peaks at 25.5 mm, and the page says its samples are the densest
    # only where their packing fraction is the largest. C26 (the loop energy grows with the
    # radius) on energies of W / 1000 J: 30.5 mm lower, resolved (against the paper), 20.5 mm not
    # resolved.
    def radius(pack20):
        for dp in (20000, 40000, 60000, 80000):
            for s in range(1, 4):
                for r in ("0.0205", "0.0255", "0.0305"):
                    W25 = 500 + 10 * s + 0.025 * (dp - 20000) + (6 * (s - 1) if dp > 20000 else 0)
                    W = W25 if r == "0.0255" else W25 - 300 - 10 * s if r == "0.0305" else \
                        W25 - 20 + 50 * ((s == 1) - (s == 2))
                    pack = 0.62 if r == "0.0255" else 0.60 if r == "0.0305" else pack20
                    write_run(data / "radius_underpressure" /
                              f"damper.radius={r}_process.underpressure={dp}_simulation.seed={s}",
                              [W] * 5, energy=W / 1000, packing=pack)
        return section(paper_report(data, d), "| C26 |", end="| C29 |")

    # By the rules: Welch (each radius its own samples). 30.5 mm at 0.06 MPa: 1200, 1206, 1212 against
    # 1510, 1526, 1542: -320, se sqrt((36 + 256) / 3) = 9.87, Welch dof 2.55, +- 35: below, resolved (the
    # paper's direction); 20.5 mm: 1540, 1456, 1522 (sd 44.2): -20, se 27.2, dof 2.51, +- 97: not
    # resolved. C28 is consistent, not established (nothing against it resolved); C26 (the energy grows
    # with the radius) not reproduced: 30.5 mm's energy lower, resolved, at every dp.
    c28v = ("| consistent, not established: 0.02 MPa 30.5 mm -320 +- 25 (-62%) [yes]; 0.02 MPa 20.5 mm -20 +- 107 "
            "(-4%) [unresolved]; 0.04 MPa 30.5 mm -320 +- 35 (-31%) [yes];")
    peak = ". The mean W peaks at 25.5 mm at every dp. Confound: the radii's samples differ in packing"
    v = radius(0.61)
    assert "0.06 MPa, 30.5 mm: -320 +- 35 (" in v, v
    assert "0.06 MPa, 20.5 mm: -20 +- 97 (" in v, v
    assert ("20.5 / 25.5 / 30.5 mm: 0.610 +- 0.000 (n 3 of 5) / 0.620 +- 0.000 (n 3 of 5) / 0.600 +- 0.000 "
            "(n 3 of 5)") in v, v
    assert c28v in v, v
    assert peak in v, v
    assert "summary.json 'preparation'), and W peaks with it (section" in v, v
    assert ("| not reproduced: 0.02 MPa 30.5 mm -0.32 +- 0.02 (-62%) [against]; 0.02 MPa 20.5 mm -0.02 +- 0.11 "
            "(-4%) [unresolved];") in v, v
    v = radius(0.63)  # the 20.5 mm samples the densest: W does not follow the packing here
    assert c28v in v, v
    assert "summary.json 'preparation') (section" in v, v

    # Seeds 4 and 5 of the 25.5 mm rows: C1 is decided over all 5 (0.06 MPa from 0.02 MPa: 1000 +
    # 6 (s - 1), mean 1012, sd 9.49, t_{0.975,4} 2.776 * 9.49 / sqrt(5) = 11.8; 0.02 MPa's mean 530),
    # no longer provisional, while C26 and C28 (20.5 and 30.5 mm over 3) still are. The time step's
    # seeds 1-5 against the radius study's 25.5 mm, 0.06 MPa runs (the friction study's mu 0.6,
    # its first reference, has none here): W 1494 + 16 s - 20 - s, paired -21 ... -25, mean -23,
    # sd 1.58, 2.776 * 1.58 / sqrt(5) = 2.0, within 5% of 1542: C5 reproduced over all 5.
    underpressure_rows(4, 5)
    for s in range(1, 6):
        write_run(data / "timestep" / f"simulation.dt-safety=0.25_simulation.seed={s}",
                  [float(1494 + 16 * s - 20 - s)] * 2)
    pg = paper_report(data, d)
    c1 = row(pg, "C1")
    assert "0.06: +1012 +- 12 (+191%);" in c1, c1
    assert "0.02 MPa: 530 +- 20;" in c1, c1  # 510 ... 550: 2.776 * 15.8 / sqrt(5)
    # C1 decided over the 3 planned seeds, all 5 beside it; C28 still over 3 (20.5 and 30.5 mm have 3).
    assert ("| reproduced: 0.04 MPa +506 +- 15 (+97%); 0.06 MPa +1006 +- 15 (+193%); 0.08 MPa +1506 +- 15 "
            "(+290%) [seeds 4-5 added after a look, all 5 seeds: reproduced: 0.04 MPa +512 +- 12 (+97%);") in c1, c1
    assert c28v in pg
    # C5: the first grid's paired difference over all 5 seeds (-23 +- 2) in vppdem's column; the row is the
    # paper's protocol (issue 60: no bias claimed), its step decided by the plan (no runs here: 0 of 10).
    assert ("0.25 against 0.45 -23 +- 2 (-1%); converged W: pending (section 'Time step converged') | the numerical "
            "level's rule: stationary W, paired against dt_safety 0.15, margin +-5%; 10 planned seeds | "
            "protocol: vppdem's step at the studies' dt_safety 0.45 is 1.84e-6 s, about the paper's; whether it "
            "is fine enough: the time step decided by intervals: 0 of 10 planned seeds so far |") in pg
