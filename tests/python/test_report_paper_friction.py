# vppdem.report paper's friction claims (C16, C17, C18, C2) from the friction study and its second
# leg (friction_8: the runs taken to 8 cycles; friction_8_seeds: C18's added seeds), on hand-made records.
import os

from synthetic_records import paper_report, row, write_file, write_run

B = {"0": 500, "0.1": 800, "0.2": 1000, "0.4": 1300, "0.6": 1500, "0.8": 1550, "1": 1600}


# C17 and C18 move to the friction study's second leg (friction_8: the runs at mu 0.1 ... 1.0
# taken to 8 cycles) once all of its 18 runs are there, and stay on the 5-cycle study until then.
# Hand-made records, every cycle of a run at one W but for mu 1.0's cycles 6-8: W = B(mu) + 10 s
# with B = 500, 800, 1000, 1300, 1500, 1550, 1600 for mu 0 ... 1; in the leg mu 1.0 falls to 1300
# + 10 s + 4 (s - 1) from cycle 6. 5 cycles: mu 0.6 -> 1.0 is +100 in every seed (+100 +- 0, 7% of
# mu 0.6's 1520: within 10%). The leg: -200, -196, -192, mean -196, sd 4, 95% half width 4.303 *
# 4 / sqrt(3) = 9.9 (-13% of 1520: beyond 10%, resolved); slope ratio (W(1) - W(0.6)) / 0.4 over
# (W(0.6) - W(0.1)) / 0.5 per seed -0.357, -0.350, -0.343. The leg's runs at mu 0.4, 0.6, 1.0
# continued a checkpoint (their summary.json's warning), the other 9 ran from their samples, one
# of which (mu 0.2, seed 3) differs in cycle 3 from the first leg: 8 of 9 repeat it. C18 plans 5
# seeds (the leg's added seeds 4-5, friction_8_seeds): over the leg's 3 it is provisional; with
# seeds 4-5 (the same pattern) it is -200 ... -184, mean -192, sd sqrt(40), half width 2.776 *
# sqrt(40) / sqrt(5) = 7.9, of mu 0.6's 1530: -13%, beyond 10% and final.
def test_paper_report_takes_the_friction_claims_from_the_complete_second_leg(tmp_path):
    d = tmp_path / "paper_report_leg"
    data = d / "data"

    def runs(study, cycles, first_seed=1, last_seed=3):
        for mu, b in B.items():
            for s in range(first_seed, last_seed + 1):
                if cycles == 8 and mu == "0":
                    continue  # the leg leaves mu 0 out
                if first_seed > 1 and mu not in ("0.6", "1"):
                    continue  # the added seeds: C18's two
                W = []
                for k in range(1, cycles + 1):
                    w = float(1300 + 10 * s + 4 * (s - 1) if mu == "1" and k > 5 else b + 10 * s)
                    if cycles == 8 and mu == "0.2" and s == 3 and k == 3:
                        w += 1e-6
                    W.append(w)
                continued = cycles == 8 and first_seed == 1 and mu in ("0.4", "0.6", "1")
                warning = "process.cycles raised on a checkpoint of an older vppdem: ..."
                write_run(data / study / f"grains.friction={mu}_simulation.seed={s}", W,
                          warnings=[warning] if continued else [])
        write_file(data / study / "COMMAND",
                   f"vppdem sweep (pinned build {'friction_8' if first_seed > 1 else study}-build)\n")

    runs("friction", 5)
    runs("friction_8", 8)
    held = d / "held"
    os.rename(data / "friction_8" / "grains.friction=0.4_simulation.seed=2", held)  # 17 of 18
    page = paper_report(data, d)
    c18 = row(page, "C18")
    assert "W_settled +100 +- 0 (+7%) J/m2, dissipated energy (cycle 5)" in c18, c18
    assert "second leg (8 cycles): 17 of 18 runs finished" in c18, c18
    assert "| reproduced: mu 1.0 against 0.6 +100 +- 0 (+7%) (+7% to +7%) |" in c18, c18
    assert "one pinned build for every run (friction-build;" in page
    assert "by a later build (friction_8-build;" in page
    assert "17 of 18 runs: `VPPDEM_LEG" in page
    assert "friction_8 17 of 18, friction_8_seeds 0 of 4, radius_packing 0 of 30." in page
    os.rename(held, data / "friction_8" / "grains.friction=0.4_simulation.seed=2")
    page = paper_report(data, d)
    c18 = row(page, "C18")
    assert "W_settled -196 +- 10 (-13%) (n 3 of 5) J/m2, dissipated energy (cycle 8)" in c18, c18
    assert "(8 cycles: the friction study's runs taken on, second leg)" in c18, c18
    # Decided over the leg's 3 planned seeds (beyond the +-10% margin); the added seeds not in yet.
    assert "| not reproduced: mu 1.0 against 0.6 -196 +- 10 (-13%) (-14% to -12%) |" in c18, c18
    assert "-0.35 +- 0.02 (3 seeds) (8 cycles" in row(page, "C17"), row(page, "C17")
    assert "9 continued from their cycle-5 checkpoint" in page
    assert "9 ran again from their samples (their checkpoints were gone), and 8 of those 9 repeat" in page
    # C16 and C2 stay on the 5-cycle runs: 21 runs (the leg's are the same runs longer).
    assert "1: 1620 +- 25" in row(page, "C16"), row(page, "C16")
    assert "21 of 21 finished 5-cycle runs are stationary" in page
    # C18's added seeds: over 5 seeds, final; C17 stays on the leg's 3 seeds, C2 on the 5-cycle runs.
    runs("friction_8_seeds", 8, 4, 5)
    page = paper_report(data, d)
    c18 = row(page, "C18")
    assert "W_settled -192 +- 8 (-13%) J/m2, dissipated energy (cycle 8)" in c18, c18
    assert ("| not reproduced: mu 1.0 against 0.6 -196 +- 10 (-13%) (-14% to -12%) [seeds 4-5 added after a "
            "look, all 5 seeds: not reproduced: mu 1.0 against 0.6 -192 +- 8 (-13%) (-13% to -12%)] |") in c18, c18
    assert "-0.35 +- 0.02 (3 seeds) (8 cycles" in row(page, "C17"), row(page, "C17")
    assert "21 of 21 finished 5-cycle runs are stationary" in page
    assert ("got seeds 4 and 5 (over three seeds not resolved), all 8 cycles from their seeds' samples by "
            "the same build, 4 of 4 runs") in page
    assert "by a later build (friction_8-build;" in page
