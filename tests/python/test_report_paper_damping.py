# vppdem.report paper's C30 (how friction and the local damping share the dissipation) and C19, from
# the damping study beside the friction study's lambda 0.2, on hand-made records.
import shutil

from synthetic_records import paper_report, row, write_cycles, write_run

BASE = {"0": 500.0, "0.6": 1600.0, "1": 1650.0}
SHARE = {"0": {"0.1": 0.0, "0.2": 0.0, "0.4": 0.0},
         "0.6": {"0.1": 0.95, "0.2": 0.9, "0.4": 0.8},
         "1": {"0.1": 0.75, "0.2": 0.7, "0.4": 0.6}}


# The damping study (lambda 0.1 / 0.4) beside the friction study's lambda 0.2, at mu 0 / 0.6 / 1, 3
# seeds, 5 flat cycles. W = base(mu) + 10 s + offset(lambda, mu, s): mu 0's offsets 30, -30, 0
# (lambda 0.1: W 540, 490, 530, 520 +- 4.303 * 26.5 / sqrt(3) = 65.7) and 20, -20, 0 (lambda 0.4)
# leave 0 +- 4.303 * 30 / sqrt(3) = 74.5 (and 49.7): not resolved; at mu 0.6 lambda 0.4 is
# -200 - 10 s lower (W 1400 in every seed; -220 +- 24.8: resolved). Friction
# shares (friction / (friction + damping) in the last cycle): 0.95 / 0.9 / 0.8 at mu 0.6 and
# 0.75 / 0.7 / 0.6 at mu 1 for lambda 0.1 / 0.2 / 0.4. Open while a run is missing; the mu-0
# sentence goes when its difference is resolved.
def test_paper_report_shares_the_dissipation_by_the_local_damping(tmp_path):
    d = tmp_path / "paper_report_damping"
    data = d / "data"

    def case(lam, mu, s):
        if lam == "0.2":
            return data / "friction" / f"grains.friction={mu}_simulation.seed={s}"
        return data / "damping" / f"simulation.local-damping={lam}_grains.friction={mu}_simulation.seed={s}"

    def run(lam, mu, s, mu0_lam01):
        pm = float((s == 1) - (s == 2))  # +1, -1, 0 over the seeds
        W = BASE[mu] + 10 * s
        if mu == "0":
            W += mu0_lam01 * pm if lam == "0.1" else 20 * pm if lam == "0.4" else 0
        if mu == "0.6" and lam == "0.4":
            W -= 200 + 10 * s
        f = SHARE[mu][lam]
        write_run(case(lam, mu, s), [W] * 5, extra=[(f, 1 - f, 0, 0)] * 5)

    def all_runs(mu0_lam01):
        for lam in ("0.1", "0.2", "0.4"):
            for mu in ("0", "0.6", "1"):
                for s in range(1, 4):
                    run(lam, mu, s, mu0_lam01)

    def rows():
        page = paper_report(data, d)
        return row(page, "C19"), row(page, "C30")

    all_runs(30.0)
    shutil.rmtree(case("0.4", "1", 3))
    c19, c30 = rows()
    assert "| open (runs pending) |" in c30, c30
    assert ("W_settled [J/m2] and the friction share of the dissipation (energy ledger, cycle 5): mu 0: W 520 +- 66 / "
            "520 +- 25 / 520 +- 43") in c30, c30
    all_runs(30.0)
    c19, c30 = rows()
    assert ("mu 0.6: W 1620 +- 25 / 1620 +- 25 / 1400 +- 0, friction share 0.95 +- 0.00 / "
            "0.90 +- 0.00 / 0.80 +- 0.00, W against lambda 0.2: lambda 0.1 +0 +- 23 (+0%) (Welch), lambda "
            "0.4 -220 +- 25 (-14%) (Welch)") in c30, c30
    # Not resolved at mu 0, but Welch's intervals (lambda 0.1: 57 / 520 = 11%; 0.4: 35 / 520 = 7%) reach
    # past 10%: nothing shown either way.
    answered = ("| - (an open question; answered in the model: with friction (mu 0.6-1.0) friction takes 0.60-0.95 of "
                "the dissipation for lambda 0.1-0.4, the local damping the rest; W moves beyond the seed scatter at mu "
                "0.6, lambda 0.4, not at the other 5; ")
    assert (answered + "at mu 0 (the damping takes all of it) W is not resolved from lambda 0.2's, lambda 0.1 "
                       "-11% to +11%, lambda 0.4 -7% to +7%: whether it follows the coefficient is not shown); "
                       "the paper's own answer is C33 |") in c30, c30
    assert "and W at mu 0 is not resolved from lambda 0.2's at lambda 0.1 or 0.4 (C30) |" in c19, c19
    # mu 0, lambda 0.1's offsets 3, -3, 0: Welch 0 +- 22, and lambda 0.4's 0 +- 35, both within 10% of 520.
    all_runs(3.0)
    c19, c30 = rows()
    assert (answered + "at mu 0 the damping takes all of it, yet W stays within 10% of lambda 0.2's when "
                       "lambda is halved or doubled") in c30, c30
    # mu 0, lambda 0.1 moved: 412, 424, 436 against 510, 520, 530 (-96 +- 5, resolved).
    for s in range(1, 4):
        write_cycles(case("0.1", "0", s), [400 + 12 * s] * 5, extra=[(0, 1, 0, 0)] * 5)
    c19, c30 = rows()
    assert "W moves beyond the seed scatter at mu 0, lambda 0.1, mu 0.6, lambda 0.4, not at the other 4); " in c30, c30
    assert "changes with the damping coefficient (C30) |" in c19, c19
