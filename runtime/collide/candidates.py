"""Candidate contacts: the table the narrow phase fills, and what its helpers share.

Why a table: the candidate stage (runtime.collide.narrowphase) runs compiled and cannot call
the generated kernels of only the cases a scene needs, so it writes each feature pair it
chooses as a row of one float table (:data:`COLUMNS`: pair, case, bodies, features, the
kernel's geometry row, the screening gap, point, normal, and what the selection needs later),
the kernels give the gaps, and runtime.collide.selection decides with them.
"""

from __future__ import annotations

import math
from typing import NamedTuple

from generated import CASE_ID, GEOMETRY_COLUMNS
from runtime.compiled import leaf
from runtime.settings import SPAN_EPS

TAU = 2.0 * math.pi
VERTEX_EDGE, VERTEX_CIRCLE = CASE_ID["vertex_edge"], CASE_ID["vertex_circle"]
CIRCLE_EDGE, CIRCLE_CIRCLE = CASE_ID["circle_edge"], CASE_ID["circle_circle"]
PAIR, CASE, BODY1, BODY2, KIND1, INDEX1, KIND2, INDEX2, G = range(9)  # G: 7 geometry columns
SCREEN, PX, PY, NX, NY, END_ANGLE, WAY_OUT = range(G + 7, G + 14)
COLUMNS = G + 14


class PairContext(NamedTuple):
    """What the helpers of one pair of bodies i < j share (all floats, one tuple for numba)."""

    tolerance: float  # the pair's, widened by slack: what the screening gaps are held to
    slack: float  # SCREEN_SLACK times the pair's size
    i: float
    j: float
    oix: float  # offset of body i's centre of mass from body j's (positions are relative to j)
    oiy: float
    number: float  # of the pair, in the broad phase's order
    thi: float  # angles of the bodies
    thj: float
    closed_i: float  # 1.0: the body is closed (a vertex can be inside it)
    closed_j: float


# the geometry written below: feature 1 from column 0, feature 2 from column 3
assert GEOMETRY_COLUMNS["vertex_edge"] == dict(px1=0, py1=1, ex2=3, ey2=4, nx2=5, ny2=6)
assert GEOMETRY_COLUMNS["circle_circle"] == dict(cx1=0, cy1=1, r1=2, cx2=3, cy2=4, r2=5)
assert GEOMETRY_COLUMNS["vertex_circle"] == dict(px1=0, py1=1, cx2=3, cy2=4, r2=5)
assert GEOMETRY_COLUMNS["circle_edge"] == dict(cx1=0, cy1=1, r1=2, ex2=3, ey2=4, nx2=5, ny2=6)


@leaf
def emit(cand, k, ctx, case, b1, kind1, index1, b2, kind2, index2, g, gap, p, n, aux):
    """Write candidate k (``aux``: end angle, way out) if there is room; returns k + 1 (the
    count goes on, so the caller can grow the table and search again)."""
    if k < len(cand):
        row = cand[k]
        row[PAIR], row[CASE], row[BODY1], row[BODY2] = ctx.number, case, b1, b2
        row[KIND1], row[INDEX1], row[KIND2], row[INDEX2] = kind1, index1, kind2, index2
        for c in range(7):
            row[G + c] = g[c]
        row[SCREEN], row[PX], row[PY], row[NX], row[NY] = gap, p[0], p[1], n[0], n[1]
        row[END_ANGLE], row[WAY_OUT] = aux
    return k + 1


@leaf
def offset(ctx, b):
    """World offset of body b (i or j of the pair) from body j."""
    return (ctx.oix, ctx.oiy) if b == ctx.i else (0.0, 0.0)


@leaf
def in_span(y, x, start, span):
    """Whether the direction (x, y) lies in the span (closed by SPAN_EPS); a full turn holds
    every direction (no atan2)."""
    if span + SPAN_EPS >= TAU:
        return True
    d = (math.atan2(y, x) - start) % TAU
    return d <= span + SPAN_EPS or d >= TAU - SPAN_EPS
