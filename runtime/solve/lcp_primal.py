"""A primal active-set method for a large island's definite LCP, on the envelope factor.

    f >= 0,  a = S f + b >= 0,  f . a = 0   <=>   min q(f) = 1/2 f.S f + b.f  over f >= 0

(S: the scaled, regularised A of an island, positive definite). Why: block pivoting, which
exchanges every violated row at once, cycles on a packed pile's near-dependent rows -- their
forces on a trial set are rounding amplified ~1e9 times and their signs decide the exchanges
(bench/README.md, session 28) -- and the dense solver that ends it costs 40-300 ms on the
400-540-row islands of a landing 200-disc pile. This method keeps f feasible and q never rises,
so it does not cycle: minimise q over the free set W (one envelope factorization);
if that point leaves f >= 0, step towards it until the first force reaches 0 and free that row
(q falls); otherwise take it and clamp rows with a < 0 -- a block of them, halved whenever
rows just added come straight out again (one row at a time always lowers q). Its stopping test
is the solver's own (runtime.solve.lcp_envelope.valid): the last point solves S_WW f_W = -b_W
with a backward-stable factor, so its residuals meet the row tolerances even where its forces
are ill-determined. Measured on 40 captured islands of 147-541 rows where block pivoting had
cycled: all 40 solved, 59-1,910 factorizations, 1.56 s against the dense solver's 2.92 s.
"""

from __future__ import annotations

import numpy as np

from runtime import settings
from runtime.compiled import njit
from runtime.solve import lcp_envelope as env


@njit
def active_set(S, envelope, b, live, member, f):
    """Whether the method ends on a valid solution within settings.PRIMAL_FACTORIZATIONS,
    starting with the rows of ``member`` free (f written; ``member`` changed)."""
    indptr, indices, data = S
    first, offset, values = envelope
    K = b.size
    y, rhs, a, tol_a = np.empty(K), np.empty(K), np.empty(K), np.empty(K)
    L, kept = np.empty(values.size), np.empty(K, np.bool_)
    added, joint = np.zeros(K, np.bool_), np.zeros(K, np.bool_)
    score, rows = np.empty(K), np.empty(K, np.int64)  # the violated rows and how far
    tol = settings.LCP_TOL
    f[:] = 0.0
    for i in range(K):
        member[i] = member[i] and live[i]
    block, last, pending = K, K, False  # rows clamped at once, the last block, its outcome open
    for _ in range(settings.PRIMAL_FACTORIZATIONS):
        env.factor(first, offset, values, member, settings.LCP_DEPENDENT, L, kept)
        for i in range(K):
            rhs[i] = -b[i] if kept[i] else 0.0
        env.solve(first, offset, L, rhs, y)  # the minimiser of q over the free rows
        alpha = 1.0
        for i in range(K):
            if kept[i] and y[i] < 0.0:
                alpha = min(alpha, f[i] / (f[i] - y[i]))
        if alpha < 1.0:  # step to the first force that reaches 0, free it (and its ties)
            undone = False
            for i in range(K):
                if kept[i] and y[i] < 0.0 and f[i] / (f[i] - y[i]) <= alpha:
                    undone = undone or added[i]
                    f[i] = 0.0
                elif kept[i]:
                    f[i] += alpha * (y[i] - f[i])
                else:
                    f[i] = 0.0
            if pending:
                block = max(1, last // 2) if undone and alpha == 0.0 else min(K, 2 * block)
                pending = False
            for i in range(K):
                member[i] = kept[i] and f[i] > 0.0
                added[i] = False
            continue
        if pending:
            block, pending = min(K, 2 * block), False
        for i in range(K):
            f[i] = y[i] if kept[i] else 0.0
            member[i] = kept[i]
            added[i] = False
        env.residual(indptr, indices, data, b, f, tol, a, tol_a)
        violated = 0
        for i in range(K):
            if not kept[i] and live[i] and a[i] < -tol_a[i]:
                score[violated], rows[violated] = a[i] / tol_a[i], i
                violated += 1
        if violated == 0:
            return env.valid(indptr, indices, data, b, joint, f, tol, a, tol_a)
        last = min(block, violated)
        for q in np.argsort(score[:violated], kind="mergesort")[:last]:  # most violated first
            member[rows[q]], added[rows[q]] = True, True
        pending = True
    return False
