"""A primal active-set method for an island's definite impulse LCP, on the envelope factor.

    f >= 0,  a = S f + b >= 0,  f . a = 0   <=>   min q(f) = 1/2 f.S f + b.f  over f >= 0

(S: the scaled, regularised A of an island, positive definite). Why not block pivoting, which
exchanges every violated row at once: it cycles on a packed pile's near-dependent rows -- their
forces on a trial set are rounding amplified ~1e9 times and their signs decide the exchanges
(bench/README.md, session 28). This method keeps f feasible and q never rises, so it does not
cycle. It starts from the given f (the last step's impulses) or the minimiser over the guessed
set clipped at 0, whichever has the lower q, with the guessed rows and those of f > 0 free.
Each round minimises q over the free set W (a factor of W's rows alone, packed in the envelope
order: rows that left W since the last round are taken out of it by rank-one updates, else it is
redone from the first row whose membership changed); if that point y leaves f >= 0, it moves f
along the projected path max(f + t (y - f), 0) to the path's first minimiser of q, freeing the
rows that reach 0; if not, it takes y and clamps every row with a < 0. After such a round q
falls at once along the next path (its slope at t = 0 is sum a_i y_i over the clamped rows,
< 0 since y over the larger set lowers q), so q falls between any two visits of a minimiser
over a set: no set comes back. A round that neither lowers q nor frees a row (rounding) ends the
method; the dense solver then takes the island (none of 3,280 islands of 24 rows and more of four
falling 200-disc piles, replayed; before the updates below, one of ~650 did, its dense solve 0.09
s, 4 % of that pile's second). Its stopping test is the solver's own
(runtime.solve.lcp_envelope.valid): the last point solves S_WW f_W = -b_W with a backward-stable
factor, so its residuals meet the row tolerances even where its forces are ill-determined.

Measured (replayed from the guess alone): the 657 islands of 129-551 rows of the falling 200-disc
pile take 46 factorizations each on average (the most 306); session 28's 40 captured islands,
where block pivoting had cycled, 2,732 factorizations in 0.19 s against 18,333 in 1.47 s for that
session's form of this method (from f = 0, which discarded the guess; one row freed a step; every
factorization whole). With the last step's impulses as a start too, the falling 200-disc pile
(1 s, side by side) takes 2.27 s against 2.59 s from the guess alone. The updates for rounds
that only free rows (most rounds), instead of refactoring: the pile's islands of 24 rows and more
(820, captured with their starts, replayed) 1.27 s against 1.75 s, the same solutions to 9e-10 of
|b| in A f (rounding: the factor's own rounding moves them by 4e-10).
"""

from __future__ import annotations

import numpy as np

from runtime import settings
from runtime.compiled import njit
from runtime.solve import lcp_envelope as env


@njit
def active_set(S, envelope, b, live, member, f):
    """Whether the method ends on a valid solution within settings.PRIMAL_FACTORIZATIONS,
    starting from f (>= 0) and the rows of ``member`` (f written; ``member`` changed)."""
    indptr, indices, data = S
    K = b.size
    y, p, Sp = np.empty(K), np.empty(K), np.empty(K)
    a, tol_a = np.empty(K), np.empty(K)
    L, factored = np.empty(envelope[2].size), np.zeros(K, np.bool_)  # (packed: no larger)
    kept = np.zeros(K, np.bool_)
    work = (
        np.empty(K, np.bool_),
        np.empty(K),
        np.zeros(K),
    )  # (runtime.solve.lcp_primal._minimiser)
    packed = (np.zeros(K + 1, np.int64), np.empty(K, np.int64), np.empty(K, np.int64),
              np.zeros(K + 1, np.int64))  # fmt: skip
    scales = np.empty((K, 2))  # of the factor's rows (runtime.solve.lcp_envelope)
    breaks, rows, joint = np.empty(K), np.empty(K, np.int64), np.zeros(K, np.bool_)
    tol = settings.LCP_TOL
    for i in range(K):
        member[i] = member[i] and live[i]
    _minimiser(S, b, member, factored, packed, L, scales, work, kept, y)
    for i in range(K):
        y[i] = max(y[i], 0.0)  # the guess's start: its minimiser clipped at 0
    if _q(S, b, f, a, tol_a) >= _q(S, b, y, a, tol_a):
        f[:] = y
    for i in range(K):
        member[i] = f[i] > 0.0 or member[i]
    for _ in range(settings.PRIMAL_FACTORIZATIONS):
        _minimiser(S, b, member, factored, packed, L, scales, work, kept, y)
        count = 0
        for i in range(K):
            p[i] = y[i] - f[i]
            if y[i] < 0.0:
                breaks[count], rows[count] = f[i] / (f[i] - y[i]), i
                count += 1
        if count > 0:  # y leaves f >= 0: the projected search, rows that reach 0 freed
            moved = _projected_search(S, b, f, p, breaks, rows, count, Sp) > 0.0
            for i in range(K):
                now = kept[i] and f[i] > 0.0
                moved = moved or now != member[i]
                member[i] = now
            if not moved:
                return False  # no descent (rounding); the caller's dense solver decides
            continue
        for i in range(K):
            f[i] = y[i]
            member[i] = kept[i]
        env.residual(indptr, indices, data, b, f, tol, a, tol_a)
        violated = False
        for i in range(K):
            if not kept[i] and live[i] and a[i] < -tol_a[i]:
                member[i], violated = True, True  # clamped, with f = 0 for now
        if not violated:
            return env.valid(indptr, indices, data, b, joint, f, tol, a, tol_a)
    return False


@njit
def _minimiser(S, b, member, factored, packed, L, scales, work, kept, y):
    """y = the minimiser of q over the rows of ``member`` (0 elsewhere, and at rows the factor
    leaves out as dependent on the rows before them; ``kept`` says which rows it kept). The
    factor is of the member rows alone, packed (runtime.solve.lcp_envelope.refactor_members).
    If rows only left the set since the last call (``factored``: its set), each is taken out of
    the factor by a rank-one update (runtime.solve.lcp_envelope.remove_member), up to
    settings.PRIMAL_UPDATES of them; else the factor is redone from the first row whose
    membership changed. Either way the forward substitution (z) is redone from the first
    packed row that changed."""
    pos, rows, first, offset = packed
    held, x, z = work  # by packed row: kept, the right-hand side and solution, z = L^-1 x
    K = b.size
    start = 0
    while start < K and member[start] == factored[start]:
        start += 1
    left, joined = 0, False
    for i in range(start, K):
        joined = joined or (member[i] and not factored[i])
        left += factored[i] and not member[i]
    n = pos[K]  # (the packed rows: the members of the last factorization)
    if not joined and left <= settings.PRIMAL_UPDATES:
        w0 = n
        rotations = np.empty((n, 2))
        for i in range(start, K):
            if factored[i] and not member[i]:
                w0 = min(w0, pos[i])
                if held[pos[i]]:
                    env.remove_member(first, offset, L, held, scales, n, pos[i], rotations)
    else:
        w0 = pos[start]
        n = env.refactor_members(
            S[0], S[1], S[2], member, settings.LCP_DEPENDENT, start, packed, L, held, scales
        )
    factored[:] = member
    for w in range(w0, n):
        x[w] = -b[rows[w]] if held[w] else 0.0
    env.forward(first[:n], offset[: n + 1], L, x, z, w0)
    x[:n] = z[:n]
    env.backward(first[:n], offset[: n + 1], L, x)
    y[:] = 0.0
    kept[:] = False
    for w in range(n):
        y[rows[w]], kept[rows[w]] = x[w], held[w]


@njit
def _projected_search(S, b, f, p, breaks, rows, count, Sp):
    """Move f to the first minimiser of q along the path max(f + t p, 0), t in [0, 1]
    (breaks[:count] at ``rows``: where a force reaches 0 and stops); returns that t. Why not
    stop at the first breakpoint (the textbook step): on a packed pile that frees one row per
    factorization; the path frees every row whose force q wants at 0, each breakpoint costing
    one row of S."""
    indptr, indices, data = S
    K = b.size
    slope, curve = 0.0, 0.0  # dq/dt and d2q/dt2 along the path's current piece
    for i in range(K):
        s, u = b[i], 0.0
        for q in range(indptr[i], indptr[i + 1]):
            s += data[q] * f[indices[q]]
            u += data[q] * p[indices[q]]
        Sp[i] = u
        slope += s * p[i]
        curve += u * p[i]
    order = np.argsort(breaks[:count])
    t, k = 0.0, 0
    while slope < 0.0:
        t_next = breaks[order[k]] if k < count else 1.0
        if curve > 0.0 and -slope / curve < t_next - t:
            t -= slope / curve
            break
        slope += (t_next - t) * curve
        t = t_next
        if k == count:
            break
        while k < count and breaks[order[k]] <= t:  # stop row j: p_j leaves the direction
            j = rows[order[k]]
            k += 1
            g_j, s_jj = b[j], 0.0
            for q in range(indptr[j], indptr[j + 1]):
                c = indices[q]
                if c == j:
                    s_jj = data[q]
                else:
                    g_j += data[q] * max(f[c] + t * p[c], 0.0)
            slope -= p[j] * g_j
            curve += p[j] * (p[j] * s_jj - 2.0 * Sp[j])
            for q in range(indptr[j], indptr[j + 1]):
                Sp[indices[q]] -= p[j] * data[q]
            f[j], p[j] = 0.0, 0.0
    for i in range(K):
        f[i] = max(f[i] + t * p[i], 0.0)
    return t


@njit
def _q(S, b, f, a, tol_a):
    """q(f) = 1/2 f.S f + b.f = 1/2 f.(a + b), a = S f + b (``a`` and ``tol_a`` overwritten)."""
    env.residual(S[0], S[1], S[2], b, f, 0.0, a, tol_a)
    total = 0.0
    for i in range(b.size):
        total += f[i] * (a[i] + b[i])
    return 0.5 * total
