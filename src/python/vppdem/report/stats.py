"""The statistics of the reports (vppdem.report): one Student t, one interval, one paired and one
Welch difference, which every report calls.

    t_quantile(p, dof)     the t with P(T <= t) = p, Student's t with dof (any real >= 1) degrees
                           of freedom; the method of src/vpp/analysis/stats.cpp (student_t_quantile), step
                           for step, so the pages and the C++ tables print the same numbers
    incomplete_beta(x, a, b)   the regularised incomplete beta function I_x(a, b) (its tail)
    mean(xs), sd(xs)       the mean and the sample standard deviation (n - 1) of the finite values
    interval(xs)           (n, mean, sd, half width of the 95% interval t_{0.975, n-1} sd / sqrt(n))
                           of the finite values (None, NaN and inf left out), as vpp::mean_interval
    paired(a, b)           b - a seed for seed ({seed: value}): Student t on the differences
    welch(a, b)            mean(b) - mean(a) of independent samples: Welch's t, its degrees of
                           freedom by Welch-Satterthwaite (welch_dof)
    contrast(groups)       sum c_k mean(x_k) of independent samples with its Welch-Satterthwaite
                           interval (a difference of differences)
    satterthwaite(terms)   the Welch-Satterthwaite degrees of freedom of a sum of variances
    log_ratio(a, b), ratio(a, b)   ln(mean b / mean a) of independent samples by the delta method
                           (standard error, Welch's degrees of freedom), and the ratio with its
                           95% half width
    ols(x, y)              ordinary least squares with the coefficients' standard errors
    profile_range(ss, dof) one parameter's 95% range by the profile F test (F_{1,dof} = t^2)

A difference is a Diff (test, n, d, h, dof, ref: the mean of a) with .ok, .resolved, .rel and
.text(). No SciPy (Debian's /usr/bin/python3 has numpy and matplotlib only): the t quantile is
bisection on the tail probability, the tail from the incomplete beta function's continued
fraction (modified Lentz), 200 halvings at most, to round-off; t_{0.975, 1} = 12.7062,
t_{0.975, 4} = 2.7764, t_{0.975, 9} = 2.2622.
"""
import math

LEVEL = 0.975  # two-sided 95%: the quantile of every interval

__all__ = ["LEVEL", "incomplete_beta", "t_quantile", "finite", "mean", "sd", "interval", "welch_dof",
           "satterthwaite", "Diff", "paired", "welch", "contrast", "log_ratio", "ratio", "solve", "inverse",
           "ols", "profile_range"]


# ---- Student t (src/vpp/analysis/stats.cpp: beta_continued_fraction, incomplete_beta, student_t_quantile)

def _betacf(x, a, b):
    """The continued fraction of the incomplete beta function (modified Lentz), valid for
    x < (a + 1) / (a + b + 2)."""
    tiny, eps = 1e-300, 1e-15
    c, d = 1.0, 1.0 - (a + b) * x / (a + 1.0)
    d = 1.0 / (d if abs(d) > tiny else tiny)
    h = d
    for m in range(1, 10001):
        m2 = 2 * m
        # The even step d_{2m} = m (b - m) x / ((a + 2m - 1)(a + 2m)), then the odd step
        # d_{2m+1} = -(a + m)(a + b + m) x / ((a + 2m)(a + 2m + 1)).
        for aa in (m * (b - m) * x / ((a + m2 - 1) * (a + m2)), -(a + m) * (a + b + m) * x / ((a + m2) * (a + m2 + 1))):
            d = 1.0 + aa * d
            d = 1.0 / (d if abs(d) > tiny else tiny)
            c = 1.0 + aa / c
            c = c if abs(c) > tiny else tiny
            h *= d * c
        if abs(d * c - 1.0) < eps:
            break
    return h


def incomplete_beta(x, a, b):
    """I_x(a, b), the regularised incomplete beta function, for a, b > 0 (x outside (0, 1) clamped)."""
    if x <= 0.0 or x >= 1.0:
        return max(0.0, min(1.0, x))
    front = math.exp(math.lgamma(a + b) - math.lgamma(a) - math.lgamma(b) + a * math.log(x) + b * math.log1p(-x))
    if x < (a + 1.0) / (a + b + 2.0):
        return front * _betacf(x, a, b) / a
    return 1.0 - front * _betacf(1.0 - x, b, a) / b


def t_quantile(p, dof):
    """t with P(T <= t) = p for Student's t with dof degrees of freedom (p in (0, 1), dof >= 1, real):
    P(T > t) = I_{dof / (dof + t^2)}(dof / 2, 1 / 2) / 2, bisection on [0, hi], hi doubled until the
    tail is below 1 - p. Raises ValueError outside the domain."""
    if not 0.0 < p < 1.0:
        raise ValueError(f"t_quantile: p = {p} must be in (0, 1)")
    if not (dof >= 1 and math.isfinite(dof)):
        raise ValueError(f"t_quantile: dof = {dof} must be >= 1")
    if p == 0.5:
        return 0.0
    if p < 0.5:
        return -t_quantile(1.0 - p, dof)
    tail = 1.0 - p
    upper = lambda t: 0.5 * incomplete_beta(dof / (dof + t * t), 0.5 * dof, 0.5)  # noqa: E731
    lo, hi = 0.0, 1.0
    while upper(hi) > tail:
        lo, hi = hi, 2.0 * hi
        if hi > 1e300:
            raise ValueError(f"t_quantile: p = {p} too close to 1")
    for _ in range(200):
        if not hi - lo > 1e-15 * hi:
            break
        mid = 0.5 * (lo + hi)
        if upper(mid) > tail:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


# ---- one sample

def finite(xs):
    """The finite values of xs (None, NaN and inf left out: a failed run, a quantity a run lacks)."""
    return [x for x in xs if x is not None and math.isfinite(x)]


def mean(xs):
    """The mean of the finite values; NaN without any."""
    xs = finite(xs)
    return sum(xs) / len(xs) if xs else math.nan


def sd(xs):
    """The sample standard deviation (n - 1 in the denominator) of the finite values; NaN with
    fewer than 2."""
    xs = finite(xs)
    if len(xs) < 2:
        return math.nan
    m = sum(xs) / len(xs)
    return math.sqrt(sum((x - m) ** 2 for x in xs) / (len(xs) - 1))


def interval(xs, level=LEVEL):
    """(n, mean, sd, half width of the interval t_{level, n-1} sd / sqrt(n)) of the finite values
    (default the two-sided 95% interval); NaN where undefined (mean with n = 0, sd and half width
    with n < 2)."""
    xs = finite(xs)
    n = len(xs)
    if n == 0:
        return 0, math.nan, math.nan, math.nan
    m = sum(xs) / n
    if n < 2:
        return n, m, math.nan, math.nan
    s = math.sqrt(sum((x - m) ** 2 for x in xs) / (n - 1))
    return n, m, s, t_quantile(level, n - 1) * s / math.sqrt(n)


# ---- two samples

def welch_dof(s1, n1, s2, n2):
    """Welch-Satterthwaite degrees of freedom of the difference of two means (sample sds s1, s2 over
    n1, n2 runs): (v1 + v2)^2 / (v1^2 / (n1 - 1) + v2^2 / (n2 - 1)) with v = s^2 / n; n1 + n2 - 2
    when both sds are 0."""
    v1, v2 = s1 * s1 / n1, s2 * s2 / n2
    den = v1 * v1 / (n1 - 1) + v2 * v2 / (n2 - 1)
    return (v1 + v2) ** 2 / den if den > 0 else float(n1 + n2 - 2)


def satterthwaite(terms):
    """The Welch-Satterthwaite degrees of freedom of a sum of independent variances, terms
    [(variance, its degrees of freedom)]: (sum v)^2 / sum v^2 / dof (an infinite dof adds 0)."""
    return sum(v for v, _ in terms) ** 2 / sum((v * v / d if math.isfinite(d) else 0) for v, d in terms)


class Diff:
    """A difference b - a with its 95% half width: test ('paired' or 'Welch'), n (seeds paired, or
    (n_a, n_b)), d, h, dof, ref (the mean of a)."""

    def __init__(self, test, n, d, h, dof, ref):
        self.test, self.n, self.d, self.h, self.dof, self.ref = test, n, d, h, dof, ref

    @property
    def ok(self):
        return self.d is not None and self.h is not None and math.isfinite(self.d) and math.isfinite(self.h)

    @property
    def resolved(self):
        return self.ok and abs(self.d) > self.h

    @property
    def rel(self):
        return self.d / self.ref if self.ok and self.ref else math.nan

    def text(self, digits=0, pct=True):
        if not self.ok:
            return "pending"
        s = f"{self.d:+.{digits}f} +- {self.h:.{digits}f}"
        if pct and self.ref:
            s += f" ({100 * self.rel:+.0f}%)"
        return s

    def rel_interval(self):
        return f"{100 * (self.d - self.h) / self.ref:+.0f}% to {100 * (self.d + self.h) / self.ref:+.0f}%"


def paired(a, b):
    """b - a seed for seed ({seed: value}; the seeds both have): Student t on the differences."""
    seeds = sorted(s for s in a if s in b and a[s] is not None and b[s] is not None)
    n, m, _, h = interval([b[s] - a[s] for s in seeds])
    _, ref, _, _ = interval([a[s] for s in seeds])
    return Diff("paired", n, m if n else None, h if n >= 2 else None, n - 1, ref)


def welch(a, b):
    """mean(b) - mean(a) of independent samples (lists, or {seed: value}): Welch's t, its degrees
    of freedom by Welch-Satterthwaite."""
    a = [x for x in (a.values() if isinstance(a, dict) else a) if x is not None]
    b = [x for x in (b.values() if isinstance(b, dict) else b) if x is not None]
    na, ma, sa, _ = interval(a)
    nb, mb, sb, _ = interval(b)
    if na < 2 or nb < 2:
        return Diff("Welch", (na, nb), mb - ma if na and nb else None, None, None, ma)
    dof = welch_dof(sa, na, sb, nb)
    se = math.sqrt(sa * sa / na + sb * sb / nb)
    return Diff("Welch", (na, nb), mb - ma, t_quantile(LEVEL, dof) * se if se > 0 else 0.0, dof, ma)


def contrast(groups, ref=None):
    """sum c_k mean(x_k) over independent samples (groups: (c_k, list or {seed: value})), its 95% half
    width by the Welch-Satterthwaite degrees of freedom of the sum, (sum c_k^2 s_k^2 / n_k)^2 /
    sum (c_k^2 s_k^2 / n_k)^2 / (n_k - 1): welch() is the contrast (-1, a), (+1, b). Used for a
    difference of differences (the radius effect at equal packing against the unadjusted one)."""
    stats = []
    for c, x in groups:
        x = [v for v in (x.values() if isinstance(x, dict) else x) if v is not None]
        stats.append((c, interval(x)))
    ns = tuple(st[0] for _, st in stats)
    if any(n == 0 for n in ns):
        return Diff("Welch", ns, None, None, None, ref)
    d = sum(c * st[1] for c, st in stats)
    if any(n < 2 for n in ns):
        return Diff("Welch", ns, d, None, None, ref)
    v = [c * c * st[2] ** 2 / st[0] for c, st in stats]
    den = sum(vk * vk / (st[0] - 1) for vk, (_, st) in zip(v, stats))
    dof = sum(v) ** 2 / den if den > 0 else float(sum(ns) - len(ns))
    return Diff("Welch", ns, d, t_quantile(LEVEL, dof) * math.sqrt(sum(v)), dof, ref)


def log_ratio(a, b):
    """ln(mean b / mean a) of independent samples with its standard error and Welch-Satterthwaite
    degrees of freedom: the delta method, var(ln R) = sd_a^2 / (n_a m_a^2) + sd_b^2 / (n_b m_b^2)
    (infinite dof when both sds are 0). None when a side has fewer than 2 values."""
    na, ma, sa, _ = interval(a)
    nb, mb, sb, _ = interval(b)
    if na < 2 or nb < 2:
        return None
    va, vb = sa * sa / (na * ma * ma), sb * sb / (nb * mb * mb)
    dof = (va + vb) ** 2 / (va * va / (na - 1) + vb * vb / (nb - 1)) if va + vb > 0 else math.inf
    return math.log(mb / ma), math.sqrt(va + vb), dof


def ratio(a, b):
    """b's mean over a's (independent samples) as (R, half width of its 95% interval, n_a, n_b):
    R t se of log_ratio (first order). NaN half width when a side has one value."""
    (na, ma, _, _), (nb, mb, _, _) = interval(a), interval(b)
    R, e = mb / ma, log_ratio(a, b)
    if e is None:
        return R, math.nan, na, nb
    return R, (R * t_quantile(LEVEL, e[2]) * e[1] if e[1] > 0 else 0.0), na, nb


# ---- least squares

def solve(a, b):
    """Gaussian elimination with partial pivoting: x with a x = b (a square, lists)."""
    n = len(a)
    m = [row[:] + [v] for row, v in zip(a, b)]
    scale = [max(abs(row[i]) for row in a) or 1.0 for i in range(n)]
    for i in range(n):
        p = max(range(i, n), key=lambda r: abs(m[r][i]))
        m[i], m[p] = m[p], m[i]
        if abs(m[i][i]) <= 1e-12 * scale[i]:  # a column a combination of the others
            raise ValueError("singular")
        for r in range(n):
            if r != i:
                f = m[r][i] / m[i][i]
                m[r] = [x - f * y for x, y in zip(m[r], m[i])]
    return [m[i][n] / m[i][i] for i in range(n)]


def inverse(a):
    n = len(a)
    cols = [solve(a, [1.0 if i == j else 0.0 for i in range(n)]) for j in range(n)]
    return [[cols[j][i] for j in range(n)] for i in range(n)]


def ols(x, y):
    """Ordinary least squares y = X b (x: rows of regressors, the intercepts included by the caller):
    (b, standard errors, residual dof, residual sd)."""
    k = len(x[0])
    xtx = [[sum(r[i] * r[j] for r in x) for j in range(k)] for i in range(k)]
    xty = [sum(r[i] * v for r, v in zip(x, y)) for i in range(k)]
    b = solve(xtx, xty)
    res = [v - sum(bi * ri for bi, ri in zip(b, r)) for r, v in zip(x, y)]
    dof = len(y) - k
    s2 = sum(e * e for e in res) / dof if dof > 0 else math.nan
    inv = inverse(xtx)
    return b, [math.sqrt(s2 * inv[i][i]) for i in range(k)], dof, math.sqrt(s2)


def profile_range(ss, dof):
    """One parameter's profile least squares: ss {value: summed squared residuals with the other
    parameters fitted}, dof the residual degrees of freedom at the best value. (best, lowest and
    largest value inside the 95% range, residual variance): the range holds the values whose summed
    residuals exceed the least by less than F_{1, dof} (= t_{0.975, dof}^2) times the residual
    variance; without dof it is the whole grid (variance NaN)."""
    best = min(ss, key=ss.get)
    if dof <= 0:
        return best, min(ss), max(ss), math.nan
    var = ss[best] / dof
    lim = ss[best] + t_quantile(LEVEL, dof) ** 2 * var
    inside = [v for v in ss if ss[v] <= lim]
    return best, min(inside), max(inside), var
