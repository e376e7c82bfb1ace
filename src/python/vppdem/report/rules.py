"""The decision rules of every study page (docs/paper_comparison.md, grains.md, operation.md,
devices.md, studies.md's velocity results, membrane.md's cylinder), written once: one function per
rule on per-run values, with no page- or claim-specific arithmetic, and one function (section())
that states a page's rules on the page itself.

  difference   paired(): Student t on the per-seed differences where the cases of a seed branch from
               one prepared sample; welch(): Welch's t with the Welch-Satterthwaite degrees of
               freedom where each case prepares its own sample. 95% two-sided.
  equivalence  band(): a difference whose whole 95% interval lies within +-MARGIN of the reference's
               mean is "no effect" ("within"); one whose interval lies wholly beyond it, "beyond";
               0 outside the interval, reaching inside the margin: "resolved"; 0 inside, reaching
               past the margin: "unresolved".
  direction    direction(): a difference resolved the claim's way ("yes"), resolved against it
               ("against"), or not resolved.
  saturation   saturation(): per seed, the later step's change as a fraction of the earlier step's;
               saturating where the 95% interval of the ratio lies below SATURATION.
  W            stationary(): a run's stationary W, its W_settled where it settled, else extrapolated
               from its cycles (geometric decay with a rate pooled over the runs), with an uncertainty.
  seeds        the seeds fixed before a study ran decide; seeds added after a look are reported beside
               the verdict, never in it (adding seeds until an interval excludes 0 is optional stopping).
  numerical    within_margin_level(): the largest level of a numerical parameter (the time step's
               safety factor) whose paired bias against the finest level has its whole 95% interval
               within a stated margin; richardson(), level_bias(), converged_level(): the extrapolation
               to a zero step that the first time-step study used (kept to show why it did not decide).
  verdicts     verdict_direction(), verdict_equivalence(), verdict_saturation(), combine(): a claim's
               verdict from its tests' outcomes (VERDICTS); label(): the rows no test decides (LABELS:
               inputs, protocol, definitions, one run, nothing measured).

The statistics they use (Student t, intervals, the paired and Welch differences, least squares)
are vppdem.report.stats'.
"""
import math
from dataclasses import dataclass, field

from .stats import LEVEL, Diff, interval, log_ratio, ols, paired, profile_range, ratio, t_quantile, welch

MARGIN = 0.10       # equivalence margin: a fraction of the reference's mean
SATURATION = 0.5    # a later step's change under half the earlier one's: saturating
CONVERGED = 0.02    # a numerical level whose mean bias lies within 2% of the converged W
P_GRID = [0.5 + i / 100 for i in range(251)]  # the orders p a convergence fit tries: 0.5 ... 3.0

VERDICTS = [
    ("reproduced", "the claim's test passes at 95%: a difference in the claim's direction resolved from 0, "
                   "or, for a claim of no effect, the whole 95% interval within the margin"),
    ("consistent, not established", "vppdem's runs point the claim's way or are compatible with it, but "
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


# Rows that no test decides: what they are, in place of a verdict (label()).
LABELS = [
    ("input", "a value the model takes from the paper, a datasheet or a measurement; nothing to test"),
    ("protocol", "the procedure vppdem follows, as the paper's; nothing to test"),
    ("definition", "how a quantity or the model is defined or built; nothing to test"),
    ("a choice, measured", "vppdem's own choice where the paper is silent, its effect measured"),
    ("consistent, not established (one run)", "a single run: no scatter to decide against, whatever it shows"),
    ("not decidable (nothing measured)", "no run or measure of vppdem's addresses it"),
]


def label(kind, detail=""):
    """The label of a row no test decides: kind 'input', 'protocol', 'definition', 'choice',
    'one run' or 'nothing measured'; detail, when given, follows after a colon."""
    names = {"input": LABELS[0][0], "protocol": LABELS[1][0], "definition": LABELS[2][0], "choice": LABELS[3][0],
             "one run": LABELS[4][0], "nothing measured": LABELS[5][0]}
    if kind not in names:
        raise ValueError(f"rules.label: unknown kind '{kind}' (one of {', '.join(names)})")
    return names[kind] + (f": {detail}" if detail else "")


def combine(outcomes, passes, fails):
    """A claim's verdict from its tests' outcomes: reproduced where every one passes, not reproduced
    where one fails, else consistent, not established; open while one is missing (None)."""
    if not outcomes or None in outcomes:
        return "open (runs pending)"
    if all(o == passes for o in outcomes):
        return "reproduced"
    return "not reproduced" if fails in outcomes else "consistent, not established"


def verdict_direction(outcomes):
    """A trend claim from direction() outcomes: every one the claim's way ("yes") reproduces it, one
    resolved against it ("against") does not."""
    return combine(outcomes, "yes", "against")


def verdict_equivalence(bands):
    """A claim of no (or a few per cent) effect from band() outcomes: every interval within the
    margin reproduces it, one wholly beyond it does not."""
    return combine(bands, "within", "beyond")


def verdict_saturation(status):
    """A claim of saturation from saturation()'s status."""
    return {None: "open (runs pending)", "saturating": "reproduced", "not saturating": "not reproduced",
            "undecided": "consistent, not established"}[status]


def verdict_mechanism(reversed_resolved, measured=True):
    """A claim about the mechanism: 'contradicted' only where a measure that addresses it (the energy
    ledger split the way the claim splits the dissipation) reverses it, resolved at 95%; without such
    a measure 'not decidable'."""
    if not measured:
        return label("nothing measured")
    return "contradicted" if reversed_resolved else "consistent, not established"


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


def within_margin_level(bias, margin):
    """The time step's rule (issue 60, fixed before its runs): the largest level whose bias (bias:
    {level: (n, mean, sd, half width)} of the paired relative differences against the reference)
    has its whole 95% interval within +-margin. (level or None, {level: the margin its interval
    resolves, |mean| + half width, or None with fewer than 2 seeds}). None: no level qualifies, the
    default is the reference."""
    resolves = {s: (abs(b[1]) + b[3] if b[0] >= 2 and math.isfinite(b[3]) else None) for s, b in bias.items()}
    ok = [s for s, r in resolves.items() if r is not None and r <= margin]
    return (max(ok) if ok else None), resolves


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


# ---------------------------------------------------------------------------------------------
# A page's rules, stated on the page


@dataclass
class PageRules:
    """What a study page states of its rules (section()): which tests it applies and where, which W,
    the seeds, the labels it uses, and which rules were fixed before its data and which after."""
    module: str                     # the report that writes the page, e.g. "vppdem.report.operation"
    tests: list                     # (rule, where it applies): rule a key of RULE_TEXT
    which_w: str                    # which W (or quantity) its verdicts read
    planned: str                    # the seeds fixed before the runs
    added: str = ""                 # seeds added after a look, and where they are reported
    margin: float = MARGIN          # [-] the equivalence margin, a fraction of the reference's mean
    labels: list = field(default_factory=list)        # kinds of label() its rows use
    fixed_before: list = field(default_factory=list)  # rules (or plans) fixed before its data
    fixed_after: list = field(default_factory=list)   # rules written after its data were seen


RULE_TEXT = {
    "paired": lambda m: "**Paired t** (95%, two-sided) on the per-seed differences, where the cases of a seed "
                        "branch from one prepared sample",
    "welch": lambda m: "**Welch t** (95%, two-sided; Welch-Satterthwaite degrees of freedom), where each case "
                       "prepares its own sample",
    "direction": lambda m: "**Direction**: a trend claim passes where the difference is resolved (0 outside its "
                           "95% interval) the claim's way, fails where it is resolved the other way",
    "equivalence": lambda m: f"**Equivalence margin** (claims of no effect, or of 'a few per cent'): +-{100 * m:.0f}% "
                             "of the reference's mean; no effect where the whole 95% interval lies within it, an "
                             "effect where it lies wholly beyond it, otherwise undecided",
    "saturation": lambda m: f"**Saturation**: per seed, the later step's change as a fraction of the earlier "
                            f"step's; saturating where the 95% interval of that ratio lies below {SATURATION:g}, "
                            "not saturating where it lies above",
    "ratio": lambda m: "**Ratio of means** (effects of independent cases): the ratio of the two means with its "
                       "95% interval by the delta method on its logarithm (Welch's degrees of freedom); resolved "
                       "where the interval excludes 1",
    "numerical": lambda m: "**A numerical parameter's level** (the time step): the largest level whose paired "
                           "bias against the finest level has its whole 95% interval within the stated margin",
}


def section(page):
    """The '## Decision rules' section of a page (a list of markdown lines)."""
    out = ["## Decision rules", "",
           f"Applied by `{page.module}` through `vppdem.report.rules`, the one set of rules of every study page "
           "(docs/paper_comparison.md, grains.md, operation.md, devices.md, studies.md's velocity results, "
           "membrane.md's cylinder).", ""]
    for rule, where in page.tests:
        if rule not in RULE_TEXT:
            raise ValueError(f"rules.section: unknown rule '{rule}' (one of {', '.join(RULE_TEXT)})")
        out.append("- " + RULE_TEXT[rule](page.margin) + (f" ({where})" if where else "") + ".")
    out.append(f"- **Which W**: {page.which_w}")
    out.append(f"- **Seeds**: {page.planned}" + (f" {page.added}" if page.added else
                                                   " No seeds were added after a look."))
    out.append("- **Verdicts**: " + "; ".join(f"**{v}**: {d}" for v, d in VERDICTS) + ".")
    if page.labels:
        meaning = dict(LABELS)
        out.append("- **Labels** of rows that no test decides: "
                   + "; ".join(f"**{label(k)}**: {meaning[label(k)]}" for k in page.labels) + ".")
    when = []
    if page.fixed_before:
        when.append("fixed before the data: " + "; ".join(page.fixed_before))
    if page.fixed_after:
        when.append("written after the data were seen (a reader should weigh them so): " + "; ".join(page.fixed_after))
    if when:
        out.append("- **When**: " + ". ".join(w[0].upper() + w[1:] for w in when) + ".")
    return out + [""]


# ---------------------------------------------------------------------------------------------
# Added for the study pages (grains, operation, devices, velocity, membrane; issue 60, items 1
# and 5): the same rules on what those pages hold, and the statements a page may make from their
# outcomes. Nothing above changes.


def resolved(diff):
    """A difference no claim gives a direction: 'resolved' (0 outside its 95% interval),
    'unresolved', None (pending)."""
    if diff is None or not diff.ok:
        return None
    return "resolved" if diff.resolved else "unresolved"


def from_interval(test, n, d, h, dof, ref):
    """A difference a published table holds (its mean d, the half width h of its 95% interval, the
    reference's mean ref), for the rules above (band, direction, resolved)."""
    return Diff(test, n, d, h, dof, ref)


def one_sample(values, value):
    """The mean of the values against a fixed value (a published number): mean - value with the 95%
    Student-t interval of the mean, ref = value; test 'one sample'."""
    n, m, _, h = interval(values)
    return Diff("one sample", n, m - value if n else None, h if n >= 2 else None, n - 1, value)


def ratio_diff(a, b):
    """The ratio of b's mean to a's (independent samples) less 1, with the 95% half width of the ratio
    by the delta method on its logarithm (stats.ratio; Welch's degrees of freedom), ref = 1: resolved
    where the interval of the ratio excludes 1; band() reads the margin as a fraction of 1."""
    R, h, na, nb = ratio(a, b)
    e = log_ratio(a, b)
    return Diff("ratio", (na, nb), R - 1.0, h if math.isfinite(h) else None, e[2] if e else None, 1.0)


def reach(diff):
    """The largest change the 95% interval does not exclude, as a fraction of the reference's mean:
    (|d| + h) / |ref|; None where pending or without a reference."""
    if diff is None or not diff.ok or not diff.ref:
        return None
    return (abs(diff.d) + diff.h) / abs(diff.ref)


def statement_equivalence(diff, margin=MARGIN):
    """What a page may say of an effect that a claim (or the page) calls absent, from band()'s
    outcome: 'within' -> no change beyond the margin; 'beyond' -> a change beyond it; 'resolved'
    -> a change resolved from 0, not beyond the margin; 'unresolved' -> no change resolved, changes
    up to reach() not excluded (never 'does not depend', never 'equal'). The interval in % of the
    reference's mean follows in brackets."""
    b = band(diff, margin)
    if b is None:
        return "pending (fewer than 2 runs)"
    lo, hi = 100 * (diff.d - diff.h) / abs(diff.ref), 100 * (diff.d + diff.h) / abs(diff.ref)
    iv = f"{lo:+.1f}% to {hi:+.1f}%"
    m = f"+-{100 * margin:.0f}%"
    if b == "within":
        return f"no change beyond the {m} margin (the whole 95% interval within it: {iv})"
    if b == "beyond":
        return f"a change beyond the {m} margin, resolved ({iv})"
    if b == "resolved":
        return f"a change resolved from 0, not beyond the {m} margin ({iv})"
    return f"no change resolved; changes up to {100 * reach(diff):.1f}% not excluded ({iv})"


def verdict_text(verdict, detail=""):
    """A verdict (VERDICTS' names, or a label()) with what decided it after a colon."""
    return verdict + (f": {detail}" if detail else "")


def planned_seeds(study):
    """The seeds a study file fixed before its runs: its `seeds` (1 without the key); None without
    the file."""
    import os
    import tomllib
    if not study or not os.path.isfile(study):
        return None
    with open(study, "rb") as f:
        return int(tomllib.load(f).get("seeds", 1))
