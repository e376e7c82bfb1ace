"""The decision rules of docs/paper_comparison.md (issue 44), written once and applied to every claim
alike by vppdem.report.paper: one function per rule, on per-run values (one number per run, from
the runs' cycles.csv), with no claim-specific arithmetic.

Rules (the page's head states them in words, from RULES below):
The statistics they use (Student t, intervals, the paired and Welch differences, least squares)
are vppdem.report.stats'.

  difference   paired(): Student t on the per-seed differences where the cases of a seed branch from
               one prepared sample (underpressure, friction, time step, loading velocity);
               welch(): Welch's t with the Welch-Satterthwaite degrees of freedom where each case
               prepares its own sample (radius, grain modulus, local damping, preparation, foil
               resolution). 95% two-sided.
  equivalence  band(): a difference whose whole 95% interval lies within +-MARGIN of the reference's
               mean is "no effect" ("within"); one whose interval lies wholly beyond it, "beyond";
               0 outside the interval, reaching inside the margin: "resolved"; 0 inside, reaching
               past the margin: "unresolved".
  saturation   saturation(): per seed, the later step's change as a fraction of the earlier step's
               (per unit of the varied key where the steps differ in length); saturating where the
               95% interval of the ratio lies below SATURATION, not saturating where above it.
  W            which W a run gives: the last cycle's (a study's W_settled where all its runs are
               stationary by the settle criterion); stationary(): a run's stationary W, its
               W_settled where it settled, else extrapolated from its cycles (geometric decay with
               a rate pooled over the 8-cycle runs), with an uncertainty.
  seeds        the seeds fixed before a study ran decide (PLANNED in vppdem.report.paper); seeds added
               after a look are reported beside the verdict, never in it.
  convergence  richardson(): W(s) = W0_i + a_i s^p per seed i in a numerical parameter s (the time
               step's safety factor), the order p shared by the seeds, by profile least squares over
               P_GRID, its 95% range by the profile F test (as pooled_rate's q); the converged W the
               mean of the W0_i with its Student-t interval over the seeds; level_bias(): each
               level's relative bias (W_i(s) - W0_i) / W0_i paired over the seeds; converged_level():
               the largest level whose mean bias lies within CONVERGED.
"""
import math

from .stats import LEVEL, interval, ols, paired, profile_range, t_quantile, welch

MARGIN = 0.10       # equivalence margin: a fraction of the reference's mean
SATURATION = 0.5    # a later step's change under half the earlier one's: saturating
CONVERGED = 0.02    # a numerical level whose mean bias lies within 2% of the converged W
P_GRID = [0.5 + i / 100 for i in range(251)]  # the orders p a convergence fit tries: 0.5 ... 3.0

VERDICTS = [
    ("reproduced", "the claim's test passes at 95%: a difference in the paper's direction resolved from 0, "
                   "or, for a claim of no effect, the whole 95% interval within the margin"),
    ("consistent, not established", "vppdem's runs point the paper's way or are compatible with it, but "
                                    "the 95% interval does not decide (0 inside it, or reaching past the margin), "
                                    "or the evidence is a single run"),
    ("not reproduced", "the claim's test fails at 95%: a difference the claim excludes is resolved (a trend "
                       "reversed or a peak where the paper has a monotone trend), or an effect the claim says "
                       "is absent lies beyond the margin"),
    ("contradicted", "a statement about the mechanism that vppdem's energy ledger reverses, resolved at 95%"),
    ("not decidable", "the repository lacks what would decide it: the experiment's measured loops, or a run "
                      "or a measure vppdem has not made (the claim's row names it)"),
    ("open", "runs pending"),
]


def difference(test, a, b):
    """The rule's test for a claim: 'paired' (shared samples) or 'Welch' (independent samples)."""
    return paired(a, b) if test == "paired" else welch(a, b)


def band(diff, margin=MARGIN):
    """The equivalence rule: 'within' (the 95% interval inside +-margin of the reference's mean),
    'beyond' (wholly outside it), 'resolved' (0 outside the interval, which reaches inside the
    margin), 'unresolved' (0 inside, the interval reaching past the margin); None: pending."""
    if diff is None or not diff.ok or not diff.ref:
        return None
    t = margin * abs(diff.ref)
    if abs(diff.d) + diff.h <= t:
        return "within"
    if abs(diff.d) - diff.h > t:
        return "beyond"
    return "resolved" if abs(diff.d) > diff.h else "unresolved"


def direction(diff, want):
    """A difference against the direction a claim gives it (want: +1 higher, -1 lower):
    'yes' (resolved that way), 'against' (resolved the other way), 'unresolved', None (pending)."""
    if diff is None or not diff.ok:
        return None
    if not diff.resolved:
        return "unresolved"
    return "yes" if (diff.d > 0) == (want > 0) else "against"


def saturation(later, earlier, threshold=SATURATION):
    """The saturation rule: per seed the later step's change over the earlier step's (lists of
    equal length, per unit of the varied key where the steps' lengths differ), the 95% interval of
    the ratio over the seeds: (n, mean, half width, 'saturating' | 'not saturating' | 'undecided'
    | None)."""
    x = [lt / er for lt, er in zip(later, earlier) if er]
    n, m, _, h = interval(x)
    if n < 2:
        return n, m, h, None
    return n, m, h, ("saturating" if m + h < threshold else "not saturating" if m - h > threshold
                     else "undecided")


# ---------------------------------------------------------------------------------------------
# Stationary W


def geometric_fit(w, q, first=2):
    """Least squares of W_n = W_inf + a q^n over the cycles n >= first (w[0] is cycle 1), q given:
    (W_inf, its standard error from the residuals or None, residual sum of squares, points)."""
    pts = [(n, v) for n, v in enumerate(w, 1) if n >= first and v is not None]
    k = len(pts)
    if k < 2:
        return None, None, 0.0, k
    xs = [q ** n for n, _ in pts]
    ys = [v for _, v in pts]
    mx, my = sum(xs) / k, sum(ys) / k
    sxx = sum((x - mx) ** 2 for x in xs)
    if sxx <= 0:
        return my, None, sum((y - my) ** 2 for y in ys), k
    a = sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sxx
    w_inf = my - a * mx
    rss = sum((y - w_inf - a * x) ** 2 for x, y in zip(xs, ys))
    se = math.sqrt(rss / (k - 2) * (1.0 / k + mx * mx / sxx)) if k > 2 else None
    return w_inf, se, rss, k


def pooled_rate(runs, first=2, grid=None):
    """The decay ratio q of W_n = W_inf + a q^n shared by the runs (lists of W per cycle): the q that
    minimises the summed relative residuals over all runs, and its 95% range by the profile F test
    (the q whose summed residuals exceed the least by less than F_{1, dof} times the residual
    variance). (q, q_lo, q_hi, residual relative sd)."""
    grid = grid or [i / 100 for i in range(5, 96)]
    runs = [[v / w[-1] for v in w] for w in runs if len(w) >= first + 3 and w[-1]]  # relative to the last W

    def total(q):
        return sum(geometric_fit(w, q, first)[2] for w in runs)
    if not runs:
        return None, None, None, None
    ss = {q: total(q) for q in grid}
    dof = sum(len(w) - first + 1 - 2 for w in runs) - 1
    qb, lo, hi, var = profile_range(ss, dof)
    return qb, lo, hi, math.sqrt(var)


def stationary(w, q, settled_mean=None, rel_sd=None, first=2):
    """A run's stationary W: (value, standard uncertainty, 'settled' | 'extrapolated'). Settled runs
    (W_settled given): their W_settled, its uncertainty rel_sd / sqrt(cycles) not counted (0).
    Otherwise W_inf of the fit with the pooled q over cycles >= first; its uncertainty from the pooled
    residual scatter (rel_sd, relative) through the fit's leverage."""
    if settled_mean is not None:
        return settled_mean, 0.0, "settled"
    w_inf, _, _, k = geometric_fit(w, q, first)
    if w_inf is None:
        return None, None, "extrapolated"
    pts = [q ** n for n in range(first, len(w) + 1)]
    mx = sum(pts) / len(pts)
    sxx = sum((x - mx) ** 2 for x in pts)
    lev = math.sqrt(1.0 / len(pts) + (mx * mx / sxx if sxx > 0 else 0.0))
    u = abs(w[-1]) * rel_sd * lev if rel_sd is not None else None
    return w_inf, u, "extrapolated"


# ---------------------------------------------------------------------------------------------
# Regression


def factor_regression(groups, x, y, extra=None):
    """y on x with one intercept per group (a factor), the slope of x shared, plus optional extra
    regressors (lists of dicts name -> value per point): (slope, its 95% half width, dof, the other
    coefficients {name: (b, half width)})."""
    levels = sorted(set(groups))
    names = [f"group {g}" for g in levels] + ["slope"] + (sorted(extra[0]) if extra else [])
    rows = []
    for i, (g, xv) in enumerate(zip(groups, x)):
        r = [1.0 if g == lv else 0.0 for lv in levels] + [xv]
        if extra:
            r += [extra[i][k] for k in sorted(extra[0])]
        rows.append(r)
    b, se, dof, _ = ols(rows, y)
    t = t_quantile(LEVEL, dof) if dof > 0 else math.nan
    coef = {n: (bi, t * si) for n, bi, si in zip(names, b, se)}
    s = coef.pop("slope")
    return s[0], s[1], dof, coef


# ---------------------------------------------------------------------------------------------
# Convergence in a numerical parameter (Richardson extrapolation)


def power_fit(xs, ys, p):
    """Least squares of y = y0 + a x^p, p given: (y0, a, residual sum of squares)."""
    k = len(xs)
    u = [x ** p for x in xs]
    mu, my = sum(u) / k, sum(ys) / k
    suu = sum((v - mu) ** 2 for v in u)
    if suu <= 0:
        return my, 0.0, sum((y - my) ** 2 for y in ys)
    a = sum((v - mu) * (y - my) for v, y in zip(u, ys)) / suu
    y0 = my - a * mu
    return y0, a, sum((y - y0 - a * v) ** 2 for v, y in zip(u, ys))


def richardson(runs, grid=None):
    """Richardson extrapolation of W to a zero step over the seeds: runs {seed: {level s: W}} (each seed
    at 3 levels or more; a seed's levels share its sample), W_i(s) = W0_i + a_i s^p with W0_i and a_i per
    seed and the order p shared. p: the grid value (P_GRID) that minimises the summed residuals; its 95%
    range the p whose summed residuals exceed the least by less than F_{1, dof} times the residual
    variance (dof = points - 2 seeds - 1), flagged where it reaches an end of the grid. Returns a dict:
    p, p_lo, p_hi, open (the ends the range reaches: '' / 'low' / 'high' / 'low and high'), dof, sd
    (residual sd), rss {p: summed residuals} at 1 and 2, seeds, w0 {seed: W0_i}, a {seed: a_i}, mean
    (n, mean, sd, half width of the 95% Student-t interval of the W0_i over the seeds), mean_range
    (the least and largest mean W0 over p's range); None with fewer than 2 seeds or 3 levels a seed."""
    grid = grid or P_GRID
    runs = {i: dict(sorted(w.items())) for i, w in runs.items() if len(w) >= 3}
    if len(runs) < 2:
        return None

    def total(p):
        return sum(power_fit(list(w), list(w.values()), p)[2] for w in runs.values())

    def w0s(p):
        return {i: power_fit(list(w), list(w.values()), p)[:2] for i, w in runs.items()}
    ss = {p: total(p) for p in grid}
    dof = sum(len(w) - 2 for w in runs.values()) - 1
    pb, lo, hi, var = profile_range(ss, dof)  # as the stationary W's decay ratio (pooled_rate)
    inside = [p for p in grid if lo <= p <= hi]
    ends = [e for e, x in (("low", grid[0]), ("high", grid[-1])) if x in inside]
    fit = w0s(pb)
    means = [interval([v[0] for v in w0s(p).values()])[1] for p in inside]
    return {"p": pb, "p_lo": lo, "p_hi": hi, "open": " and ".join(ends), "dof": dof, "sd": math.sqrt(var), "rss": {1: total(1.0), 2: total(2.0), pb: ss[pb]},
            "seeds": sorted(runs), "w0": {i: v[0] for i, v in fit.items()}, "a": {i: v[1] for i, v in fit.items()},
            "mean": interval([v[0] for v in fit.values()]), "mean_range": (min(means), max(means))}


def level_bias(runs, w0):
    """Each level's relative bias against the converged W, paired over the seeds: runs {seed: {s: W}},
    w0 {seed: W0_i}; {s: (n, mean, sd, half width of the 95% Student-t interval)} of (W_i(s) - W0_i) / W0_i."""
    levels = sorted({s for w in runs.values() for s in w})
    return {s: interval([(runs[i][s] - w0[i]) / w0[i] for i in w0 if i in runs and s in runs[i] and w0[i]])
            for s in levels}


def converged_level(bias, tol=CONVERGED):
    """The default rule: the largest level whose mean bias lies within +-tol (bias: level_bias()).
    (level or None, its 95% interval within +-tol, the finer levels whose mean bias lies outside)."""
    ok = [s for s, b in bias.items() if b[0] and abs(b[1]) <= tol]
    if not ok:
        return None, False, []
    s = max(ok)
    n, m, _, h = bias[s]
    finer = [x for x, b in bias.items() if x < s and not (b[0] and abs(b[1]) <= tol)]
    return s, bool(n >= 2 and math.isfinite(h) and abs(m) + h <= tol), sorted(finer)
