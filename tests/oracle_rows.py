"""Independent mpmath oracle for the tangential (friction) rows and the joint constraints.

Written from the definitions only (docs/derivations.pdf, sections "Tangential (friction) rows" and
"Joints"); it shares no code and no derivative formula with derive/ or generated/. It follows
tests/oracle.py (and uses its quadratic trajectories, world points and mpmath context): every
body moves along X_i(t) = X_i + V_i t + A_i t^2/2, th_i(t) = th_i + w_i t + al_i t^2/2.

Friction, for a contact case at time t: body 1's feature q (vertex or circle centre), the case's
normal n (edge: exp(i th2)(nx2 + i ny2); circle: sigma (q - c2)/|q - c2|) and gap d; the contact
points p1 = q - r1 n and p2 = p1 - d n; the tangent t = i n (n turned by +90 degrees); the
velocity of body i's material point at p, u_i(p) = V_i(t) + w_i(t) i (p - X_i(t)); and
v_t(t) = Re(conj(t) (u1(p1) - u2(p2))). Then d/dt v_t at t = 0 by mpmath differentiation, the
row J_t = dv_t/d(velocities) by differentiating v_t(0) in each velocity, the bias = d/dt v_t with
every acceleration zero.

Joints: anchors p_i = X_i + exp(i th_i)(px_i + i py_i), s = p1 - p2; pin rows (Re s, Im s),
distance row |s| - length. d', d'' by mpmath in t, the Jacobian rows dd/dq by differentiating in
each pose coordinate, the bias = d'' with every acceleration zero.
"""

from __future__ import annotations

import math
from collections.abc import Mapping

import oracle as O

CTX = O.CTX
FRICTION_FUNCTIONS = (
    "tangent_velocity",
    "tangent_acceleration",
    "tangent_jacobian",
    "tangent_bias",
)
JOINTS = ("pin_joint", "distance_joint")
JOINT_GEOMETRY = {
    "pin_joint": ("px1", "py1", "px2", "py2"),
    "distance_joint": ("px1", "py1", "px2", "py2", "length"),
}
JOINT_FUNCTIONS = ("gap", "gap_velocity", "gap_acceleration", "jacobian", "bias")


def _still(state: Mapping[str, float]) -> dict[str, float]:
    return {**state, **{k: 0.0 for k in O.ACCELERATION}}


# ------------------------------------------------------------------------------------------
# friction
# ------------------------------------------------------------------------------------------


def _material_velocity(s, i: int, t, p, dv):
    """u_i(p) at time t: V_i(t) + w_i(t) i (p - X_i(t)); velocities shifted by dv."""
    origin, _ = O._pose_at(s, i, t, (0,) * 6)
    k = 3 * (i - 1)
    vx = s[f"vx{i}"] + s[f"ax{i}"] * t + dv[k]
    vy = s[f"vy{i}"] + s[f"ay{i}"] * t + dv[k + 1]
    w = s[f"w{i}"] + s[f"al{i}"] * t + dv[k + 2]
    return CTX.mpc(vx, vy) + CTX.mpc(0, w) * (p - origin)


def _tangent_velocity_mp(case: str, s, t, dv=(0,) * 6):
    """v_t at time t (velocities shifted by dv), from the definitions above."""
    zero = (0,) * 6
    feature = ("px1", "py1") if case.startswith("vertex") else ("cx1", "cy1")
    q = O._world_point(s, 1, *feature, t, zero)
    r1 = s["r1"] if case.startswith("circle") else 0
    if case.endswith("edge"):
        _, th2 = O._pose_at(s, 2, t, zero)
        n = CTX.expj(th2) * CTX.mpc(s["nx2"], s["ny2"])
        d = CTX.re(CTX.conj(n) * (q - O._world_point(s, 2, "ex2", "ey2", t, zero))) - r1
    else:
        v = q - O._world_point(s, 2, "cx2", "cy2", t, zero)
        sigma = O._sign(s["r2"])
        n = sigma * v / abs(v)
        d = sigma * abs(v) - s["r2"] - r1
    p1 = q - r1 * n
    p2 = p1 - d * n
    slip = _material_velocity(s, 1, t, p1, dv) - _material_velocity(s, 2, t, p2, dv)
    return CTX.re(CTX.conj(CTX.mpc(0, 1) * n) * slip)


def friction_values(case: str, state: Mapping[str, float], *, static2: bool = False) -> dict:
    """Oracle value of every friction kernel (tangent_jacobian: 6-tuple), as mpf."""
    s = O._mp_state(case, state, static2)
    v0, v1 = CTX.diffs(lambda t: _tangent_velocity_mp(case, s, t), 0, 1)
    row = []
    for k in range(6):

        def shifted(h, k=k):
            dv = [0] * 6
            dv[k] = h
            return _tangent_velocity_mp(case, s, 0, dv)

        row.append(+CTX.diff(shifted, 0))
    still = O._mp_state(case, _still(state), static2)
    bias = CTX.diff(lambda t: _tangent_velocity_mp(case, still, t), 0)
    return {
        "tangent_velocity": +v0,
        "tangent_acceleration": +v1,
        "tangent_jacobian": tuple(row),
        "tangent_bias": +bias,
    }


def friction_scales(case: str, state: Mapping[str, float], *, static2: bool = False) -> dict:
    """Magnitude of the terms of each friction kernel (float64 errors are judged against it):
    oracle.error_scales with the radii in the levers (v_t has the terms w_i r_i)."""
    base = O.error_scales(case, state, static2=static2)
    radii = abs(state.get("r1", 0.0)) + abs(state.get("r2", 0.0))
    w1, w2 = abs(state["w1"]), abs(state["w2"])
    if static2:
        w2 = 0.0
    om = w1 + w2
    al = abs(state["al1"]) + (0.0 if static2 else abs(state["al2"]))
    kappa = base["jacobian"][0]
    spin = om * radii * kappa
    return {
        "tangent_velocity": base["gap_velocity"] + spin,
        "tangent_acceleration": base["gap_acceleration"] + (al + om * om) * radii * kappa,
        "tangent_jacobian": tuple(j + radii * kappa for j in base["jacobian"]),
        "tangent_bias": base["bias"] + om * om * radii * kappa,
    }


# ------------------------------------------------------------------------------------------
# joints
# ------------------------------------------------------------------------------------------


def joint_keys(joint: str) -> tuple[str, ...]:
    return O.POSE + O.VELOCITY + O.ACCELERATION + JOINT_GEOMETRY[joint]


def _joint_state(joint: str, state: Mapping[str, float], static2: bool) -> dict:
    out = {}
    for key in joint_keys(joint):
        value = state.get(key, 0.0)
        if static2 and key in O.BODY2_MOTION:
            value = 0.0
        out[key] = CTX.mpf(float(value))
    return out


def _joint_rows_mp(joint: str, s, t, dq=(0,) * 6) -> tuple:
    sep = O._world_point(s, 1, "px1", "py1", t, dq) - O._world_point(s, 2, "px2", "py2", t, dq)
    if joint == "pin_joint":
        return (CTX.re(sep), CTX.im(sep))
    return (abs(sep) - s["length"],)


def joint_values(joint: str, state: Mapping[str, float], *, static2: bool = False) -> dict:
    """Oracle value of every joint kernel, per row (jacobian: a 6-tuple per row), as mpf."""
    s = _joint_state(joint, state, static2)
    still = _joint_state(joint, _still(state), static2)
    rows = len(_joint_rows_mp(joint, s, 0))
    out: dict[str, list] = {name: [] for name in JOINT_FUNCTIONS}
    for r in range(rows):
        d0, d1, d2 = CTX.diffs(lambda t, r=r: _joint_rows_mp(joint, s, t)[r], 0, 2)
        row = []
        for k in range(6):

            def shifted(h, k=k, r=r):
                dq = [0] * 6
                dq[k] = h
                return _joint_rows_mp(joint, s, 0, dq)[r]

            row.append(+CTX.diff(shifted, 0))
        bias = CTX.diff(lambda t, r=r: _joint_rows_mp(joint, still, t)[r], 0, 2)
        for name, value in zip(JOINT_FUNCTIONS, (d0, d1, d2, tuple(row), bias), strict=True):
            out[name].append(value if name == "jacobian" else +value)
    return out


def joint_scales(joint: str, state: Mapping[str, float], *, static2: bool = False) -> dict:
    """Magnitude of the terms of each joint kernel: L = |X1 - X2| + |a1| + |a2| (+ length),
    material-point speeds W and accelerations A as in oracle.error_scales; a distance joint's
    direction s/|s| is known to eps L/|s|, which amplifies its d', d'', J by kappa = 1 + L/|s|."""
    g = {k: float(state.get(k, 0.0)) for k in joint_keys(joint)}
    if static2:
        g.update({k: 0.0 for k in O.BODY2_MOTION})
    l1, l2 = math.hypot(g["px1"], g["py1"]), math.hypot(g["px2"], g["py2"])
    length = math.hypot(g["x1"] - g["x2"], g["y1"] - g["y2"]) + l1 + l2 + abs(g.get("length", 0))
    w1, w2 = abs(g["w1"]), abs(g["w2"])
    om = w1 + w2
    vel = math.hypot(g["vx1"], g["vy1"]) + math.hypot(g["vx2"], g["vy2"]) + w1 * l1 + w2 * l2
    centripetal = w1 * w1 * l1 + w2 * w2 * l2
    acc = math.hypot(g["ax1"], g["ay1"]) + math.hypot(g["ax2"], g["ay2"]) + centripetal
    acc += abs(g["al1"]) * l1 + abs(g["al2"]) * l2
    if joint == "distance_joint":
        sep = O._world_float(g, 1, "px1", "py1") - O._world_float(g, 2, "px2", "py2")
        rho = max(abs(sep), O.EPS * length)
        kappa, curv = 1.0 + length / rho, 1.0 / rho
    else:
        kappa, curv = 1.0, 0.0
    terms = om * vel + vel * vel * curv
    return {
        "gap": length,
        "gap_velocity": kappa * vel + om * length,
        "gap_acceleration": kappa * (acc + terms)
        + (abs(g["al1"]) + abs(g["al2"]) + om * om) * length,
        "jacobian": (kappa, kappa, kappa * l1 + length, kappa, kappa, kappa * l2 + length),
        "bias": kappa * (centripetal + terms) + om * om * length,
    }
