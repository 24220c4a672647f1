"""The four contact cases of the note, each written as the note defines its gap d.

Body 2 owns the normal n, which points from body 2 toward body 1; d > 0 means separated.
A circular edge has a signed radius: negative means concave (a bowl). With sigma = sign(r2) the
note's definitions hold unchanged for a vertex or disc inside a bowl: n = sigma v/|v|, d = n.v - r.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import sympy as sp

from derive.kinematics import BODY1, BODY2, real

PX1, PY1 = real("px1"), real("py1")
EX2, EY2, NX2, NY2 = real("ex2"), real("ey2"), real("nx2"), real("ny2")
CX1, CY1, R1 = real("cx1"), real("cy1"), real("r1")
CX2, CY2, R2 = real("cx2"), real("cy2"), real("r2")
SIGMA2 = real("sg2")  # sign of r2: +1 convex, -1 concave


@dataclass(frozen=True)
class CaseDefinition:
    """A contact case: the world vector v(t) whose geometry gives the gap, and how.

    kind "line":   d = n(t) . v(t) - offset   (n rigidly attached to body 2's straight edge)
    kind "circle": d = sigma |v(t)| - offset  (n = sigma v/|v| follows body 1's feature)
    """

    name: str
    title: str
    kind: str
    v: sp.Matrix
    offset: sp.Expr
    geometry: tuple[sp.Symbol, ...]
    body1_feature: str
    body2_feature: str
    note_equations: str
    lever1: str  # the note's name of body 1's lever vector: R (contact point) or U (centre)
    lever2: str
    normal: sp.Matrix | None = None
    formulas: dict[str, str] = field(default_factory=dict)


def _line_formulas(q: str) -> dict[str, str]:
    return {
        "gap": f"d = n . ({q} - e2){' - r1' if q == 'c1' else ''},  n = R(th2) (nx2, ny2)",
        "gap_velocity": f"d' = n' . ({q} - e2) + n . ({q}' - e2')",
        "gap_acceleration": f"d'' = n'' . ({q} - e2) + 2 n' . ({q}' - e2') + n . ({q}'' - e2'')",
    }


def _circle_formulas(q: str) -> dict[str, str]:
    return {
        "gap": f"d = sigma |v| - r2{' - r1' if q == 'c1' else ''},  v = {q} - c2,  sigma = sign(r2)",
        "gap_velocity": "d' = n . v',  n = sigma v/|v|",
        "gap_acceleration": "d'' = n . v'' + sigma v_tan^2 / |v|,  v_tan = (v x v') / |v|   (= n' . v' + n . v'')",
    }


def vertex_edge() -> CaseDefinition:
    return CaseDefinition(
        name="vertex_edge",
        title="Vertex on straight edge",
        kind="line",
        v=BODY1.point(PX1, PY1) - BODY2.point(EX2, EY2),
        offset=sp.Integer(0),
        normal=BODY2.rotate(NX2, NY2),
        geometry=(PX1, PY1, EX2, EY2, NX2, NY2),
        body1_feature="vertex p1 = (px1, py1)",
        body2_feature="straight edge through e2 = (ex2, ey2) with outward unit normal (nx2, ny2)",
        note_equations="(1)-(4)",
        lever1="R",
        lever2="R",
        formulas=_line_formulas("p1"),
    )


def vertex_circle() -> CaseDefinition:
    return CaseDefinition(
        name="vertex_circle",
        title="Vertex on circular edge",
        kind="circle",
        v=BODY1.point(PX1, PY1) - BODY2.point(CX2, CY2),
        offset=R2,
        geometry=(PX1, PY1, CX2, CY2, R2),
        body1_feature="vertex p1 = (px1, py1)",
        body2_feature="circular edge with centre c2 = (cx2, cy2) and signed radius r2",
        note_equations="(5)-(8)",
        lever1="R",
        lever2="U",
        formulas=_circle_formulas("p1"),
    )


def circle_edge() -> CaseDefinition:
    return CaseDefinition(
        name="circle_edge",
        title="Circular edge on straight edge",
        kind="line",
        v=BODY1.point(CX1, CY1) - BODY2.point(EX2, EY2),
        offset=R1,
        normal=BODY2.rotate(NX2, NY2),
        geometry=(CX1, CY1, R1, EX2, EY2, NX2, NY2),
        body1_feature="convex circular edge with centre c1 = (cx1, cy1) and radius r1 > 0",
        body2_feature="straight edge through e2 = (ex2, ey2) with outward unit normal (nx2, ny2)",
        note_equations="(9)-(11)",
        lever1="U",
        lever2="R",
        formulas=_line_formulas("c1"),
    )


def circle_circle() -> CaseDefinition:
    return CaseDefinition(
        name="circle_circle",
        title="Circular edge on circular edge",
        kind="circle",
        v=BODY1.point(CX1, CY1) - BODY2.point(CX2, CY2),
        offset=R1 + R2,
        geometry=(CX1, CY1, R1, CX2, CY2, R2),
        body1_feature="convex circular edge with centre c1 = (cx1, cy1) and radius r1 > 0",
        body2_feature="circular edge with centre c2 = (cx2, cy2) and signed radius r2",
        note_equations="(12)",
        lever1="U",
        lever2="U",
        formulas=_circle_formulas("c1"),
    )


ALL_CASES = {c().name: c for c in (vertex_edge, vertex_circle, circle_edge, circle_circle)}
