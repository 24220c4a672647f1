"""Impacts with Coulomb friction: 2-D impulses that stick or slip (issue #15).

Why: a frictionless impact leaves the tangential velocity alone, so a ball spinning onto a
floor keeps its spin through the impact. With friction the impulse has a tangential part
T, |T| <= mu P_n, opposing the slip, up to stopping it. Like the frictionless policy
(runtime.solve.impulses), in waves of the contacts approaching faster than the resting speed,
each wave in Poisson's two phases (as Routh's construction for a single contact):

1. compression: impulses P_n >= 0 with post-impact d' >= 0, complementary, and per frictional
   contact the 2-D cone T = T+ - T-, |T| <= mu P_n, sticking (v_t = 0 after) or sliding with T
   at the bound against v_t after -- the velocity-level LCP of Stewart and Trinkle, solved by
   Lemke's method (runtime.solve.lemke). It never raises the kinetic energy:
   dK = P.(J v+) - P.A P / 2 with P_n d'+ = 0 and T v_t+ <= 0;
2. restitution: the normal impulse e P_n of the same contacts, with friction again up to
   mu e P_n against the remaining slip (a second LCP in T+, T-, lambda).

Then, as without friction, a final plastic (compression only) pass over the island's touching
contacts. For a disc on a floor (normal and tangential decoupled) this is Routh's result: it
sticks if the slip impulse m s0 / 3 is at most mu (1 + e) m u, else slides with T = -mu (1 + e) m u.
With coupled contacts, restitution with friction can add energy (Kane's paradox, which
Stronge's energetic coefficient avoids); here an impact whose kinetic energy would rise is
done again plastic (e = 0), which never raises it.
"""

from __future__ import annotations

import numpy as np

from runtime import settings
from runtime.solve import lemke
from runtime.solve.friction_rows import dense_rows, island_bodies
from runtime.solve.lcp_problem import ContactSolverError


def _cone_lcp(Jn, Jt, w, mu, vn, vt, normal=None):
    """(P_n, T) of the velocity-level friction LCP over these rows: P_n unknown (``normal``
    None) or given; T in the cone |T| <= mu P_n of each frictional row, opposing v_t after."""
    k = len(mu)
    S = np.flatnonzero(mu > 0)
    s = S.size
    Jts = Jt[S]
    free_n = normal is None
    kn = k if free_n else 0
    n = kn + 3 * s
    M, q = np.zeros((n, n)), np.zeros(n)
    plus, minus, slack = slice(kn, kn + s), slice(kn + s, kn + 2 * s), slice(kn + 2 * s, n)
    A_ss = (Jts * w) @ Jts.T
    if free_n:
        A_nn, A_ns, A_sn = (Jn * w) @ Jn.T, (Jn * w) @ Jts.T, (Jts * w) @ Jn.T
        M[:k, :k], M[:k, plus], M[:k, minus] = A_nn, A_ns, -A_ns
        M[plus, :k], M[minus, :k] = A_sn, -A_sn
        M[kn + 2 * s + np.arange(s), S] = mu[S]
        q[:k], q[plus], q[minus] = vn, vt[S], -vt[S]
    else:
        shift = (Jts * w) @ (Jn.T @ normal)
        q[plus], q[minus], q[slack] = vt[S] + shift, -(vt[S] + shift), mu[S] * normal[S]
    M[plus, plus], M[plus, minus], M[minus, plus], M[minus, minus] = A_ss, -A_ss, -A_ss, A_ss
    eye = np.eye(s)
    M[plus, slack], M[minus, slack], M[slack, plus], M[slack, minus] = eye, eye, -eye, -eye
    z, status = lemke.solve(M, q)
    if status != lemke.SOLVED:
        raise ContactSolverError("the frictional impulses of an impact have no solution", [])
    P = z[:k] if free_n else np.asarray(normal, dtype=float)
    T = np.zeros(k)
    T[S] = z[plus] - z[minus]
    return P, T


def resolve_frictional(
    rows, restitution, bodies, velocities, resting_speed: float, creep_speed: float
):
    """(normal impulse per contact (K,), velocity change (n, 3)) of the impacts among one
    island's touching contacts (``rows``: their FrictionRows; ``bodies``:
    runtime.step.classify.Bodies; ``velocities`` (n, 3) before), by the policy of the module
    docstring."""
    done = _waves(rows, restitution, bodies, resting_speed, creep_speed)
    before = bodies.kinetic(velocities)
    if bodies.kinetic(velocities + done[1]) > before * (1.0 + settings.IMPACT_ENERGY_SLACK):
        done = _waves(rows, np.zeros_like(restitution), bodies, resting_speed, creep_speed)
    return done


def _waves(rows, restitution, bodies, resting_speed, creep_speed):
    fixed = bodies.fixed
    b1, b2, mu = rows.body1, rows.body2, rows.mu
    moving, local = island_bodies(b1, b2, fixed)
    Jn = dense_rows(rows.jacobian, b1, b2, local, fixed, moving.size)
    Jt = dense_rows(rows.tangent_jacobian, b1, b2, local, fixed, moving.size)
    w = bodies.inverse_mass[moving].ravel()
    vn, vt = rows.gap_velocity.astype(float), rows.tangent_velocity.astype(float)
    total = np.zeros(len(mu))
    dv = np.zeros(3 * moving.size)

    def apply(index, P, T):
        nonlocal vn, vt, dv
        change = w * (Jn[index].T @ P + Jt[index].T @ T)
        dv = dv + change
        vn, vt = vn + Jn @ change, vt + Jt @ change
        total[index] += P

    for _ in range(settings.MAX_WAVES):
        wave = np.flatnonzero(vn < -resting_speed)
        if wave.size == 0:
            break
        P, T = _cone_lcp(Jn[wave], Jt[wave], w, mu[wave], vn[wave], vt[wave])
        apply(wave, P, T)
        e = restitution[wave]
        if np.any(e > 0):
            R, T = _cone_lcp(Jn[wave], Jt[wave], w, mu[wave], vn[wave], vt[wave], e * P)
            apply(wave, R, T)
    if np.any(vn < -creep_speed):
        every = np.arange(len(mu))
        apply(every, *_cone_lcp(Jn, Jt, w, mu, vn, vt))
    out = np.zeros((len(fixed), 3))
    out[moving] = dv.reshape(-1, 3)
    return total, out
