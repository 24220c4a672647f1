"""Hypothesis strategies for random valid scenes, and the checks of a run of one.

Used by tests/runtime/test_fuzz.py (CI: fixed seed, few examples) and bench/soak.py (random,
for minutes). A scene is drawn as the plain dict that ``runtime.scene_from_dict`` takes, so it
goes through every check a scene file gets: a scene that the loader refuses is a bug of this
generator (or a false alarm of the loader), never bad luck.

What is drawn (``drawn_scenes``):

- a **scale** ``L`` from 1e-3 m to 1e3 m (six orders of magnitude): the largest body's size;
  the other bodies' sizes lie in ``[L / 10, L]``;
- 1 .. ``max_bodies`` moving bodies: discs, convex polygons (3-8 corners on a circle),
  rounded rectangles (corner radius 0, i.e. a plain rectangle, included), half discs and
  ellipses (axis ratio 1 .. 5), at random angles (a quarter of them written up to 1e11 turns
  further: the loader reduces them), densities 10 .. 1e4 kg/m^2 (``densities`` decades),
  restitution 0 .. 1 (all 1 with ``elastic=True``);
- speeds up to ``sqrt(g L)`` and spins up to ``sqrt(g / L)`` (a quarter of the bodies at rest);
- an **environment**: a long floor (a wall) or an open box (``box_walls``), fixed;
- a **layout** without overlap at t = 0: the bodies stand in columns, each either resting
  exactly on the floor (its lowest point at y = 0) or lifted by up to half its size, further
  bodies of a column above the one below (bounding circles apart or touching);
- the **time step** from the speeds: ``dt = travel * h / V`` with ``h`` the half-width of the
  thinnest body and ``V`` a bound on every point speed during the run (``Drawn.speed``:
  twice the initial speed plus the speed of a fall from the top of the layout), so no body
  moves more than ``travel`` half-widths per step (default 0.1); 10 .. 40 steps;
- tolerances scaled with the bodies: contact ``1e-6 h``, overlap ``1e-9 h`` (the defaults,
  1e-4 m and 1e-9 m, are absolute and the loader refuses them for millimetre bodies).

``check_scene(drawn)`` loads and runs a drawn scene and returns a ``Report``: the failures
found by kind (see ``KINDS``), which the tests assert empty and bench/soak.py counts.
"""

from __future__ import annotations

import math
import re
import traceback
import warnings
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from hypothesis import assume
from hypothesis import strategies as st

from runtime import settings
from runtime.model import shapes as _shapes

G = 9.81
SHAPE_KINDS = ("disc", "polygon", "rounded_rect", "half_disc", "ellipse")
ENVIRONMENTS = ("floor", "box")
METHODS = ("rk4", "rk4", "midpoint", "euler")  # drawn: rk4 twice as often
TRAVEL = 0.1  # dt: a body moves at most this many half-widths of the thinnest body per step
GAP = 0.2  # horizontal gaps between columns: up to this many body sizes
LIFT = 0.5  # bodies not resting start up to this many body sizes above their support
CONTACT_TOLERANCE = 1e-6  # times the half-width of the thinnest body
OVERLAP_TOLERANCE = 1e-9  # times the half-width of the thinnest body

# The bounds the properties assert (see check_run):
ENERGY_BOUND = 1e-6  # E(t) - E(0) <= this x Drawn.energy_scale (no friction, restitution <= 1)
PENETRATION_BOUND = 1e-3  # penetration <= this x the thinnest body's half-width
EULER_PENETRATION = 1e-2  # the same for explicit Euler: its constraint drift is first order
# (a disc resting on a tilting box sank 6.9e-3 half-widths at travel 0.1, half that at half
# the step; midpoint 4.3e-5, RK4 3.4e-10)
CONSERVATIVE_METHODS = ("rk4", "midpoint", "rk45", "dop853")  # exact for free fall; not Euler


@dataclass(frozen=True)
class Drawn:
    """A drawn scene (``data`` for ``scene_from_dict``) and its characteristic numbers."""

    data: dict[str, Any]
    scale: float  # L: the largest body size, m
    thinnest: float  # h: half the smallest width of any moving body, m
    dt: float  # the time step, s
    speed: float  # V: a bound on every point speed during the run, m/s
    height: float  # the top of the layout, m (the floor is y = 0)
    environment: str  # "floor" or "box"
    half_width: float  # half the box's width (inf for a floor), m
    elastic: bool
    wall_top: float = math.inf  # the top of the box's side walls (its open side), m

    @property
    def bodies(self) -> list[dict[str, Any]]:
        return self.data["body"]

    @property
    def energy_scale(self) -> float:
        """Sum over the moving bodies of m (V^2 + g (height + L)): bounds |E| and its changes."""
        total = 0.0
        for b in self.data["body"]:
            if b.get("fixed"):
                continue
            shape = _build(b["shape"]["type"], b["shape"])
            mass = b["density"] * shape.area
            total += mass * (self.speed**2 + G * (self.height + self.scale))
        return total


def _rot(th: float, x: float, y: float) -> tuple[float, float]:
    c, s = math.cos(th), math.sin(th)
    return c * x - s * y, s * x + c * y


def lowest_point(shape: _shapes.Shape, th: float) -> float:
    """Lowest y of the shape (body coordinates) turned by ``th``: exact for segments and arcs."""
    low = math.inf
    for e in shape.edges:
        if isinstance(e, _shapes.Segment):
            low = min(low, _rot(th, *e.start)[1], _rot(th, *e.end)[1])
        elif isinstance(e, _shapes.Ellipse):  # support in -y of the turned ellipse
            turn = th + e.angle
            reach = math.hypot(e.a * math.sin(turn), e.b * math.cos(turn))
            low = min(low, _rot(th, *e.centre)[1] - reach)
        else:  # a convex arc
            cy = _rot(th, *e.centre)[1]
            if e.contains_angle(-math.pi / 2 - th):
                low = min(low, cy - abs(e.radius))
            low = min(low, *(_rot(th, *p)[1] for p in e.end_points))
    return low


def _shape_table(kind: str, size: float, draw_params: tuple) -> dict[str, Any]:
    """The ``shape`` table of a body of overall size ``size`` (its diameter or longer side)."""
    a, b, angles = draw_params
    if kind == "disc":
        return {"type": "disc", "radius": size / 2}
    if kind == "half_disc":
        return {"type": "half_disc", "radius": size / 2}
    if kind == "ellipse":
        return {"type": "ellipse", "a": size / 2, "b": size / 2 * (0.2 + 0.8 * a)}
    if kind == "rounded_rect":
        width, height = size, size * (0.3 + 0.7 * a)
        corner = 0.0 if b < 0.2 else 0.5 * min(width, height) * (b - 0.2) / 0.8 * 0.999
        return {"type": "rounded_rect", "width": width, "height": height, "corner_radius": corner}
    # polygon: corners on a circle of radius size / 2, in order, each at least 0.28 rad from
    # the next (strictly convex; not always around the circle's centre)
    gaps = [0.3 + g for g in angles]
    total = sum(gaps)
    turn = 2 * math.pi * b
    points, phi = [], turn
    for g in gaps:
        points.append([size / 2 * math.cos(phi), size / 2 * math.sin(phi)])
        phi += 2 * math.pi * g / total
    return {"type": "polygon", "points": points}


def _build(kind: str, table: dict[str, Any]) -> _shapes.Shape:
    params = {k: v for k, v in table.items() if k != "type"}
    return getattr(_shapes, kind)(**params)


_UNIT = st.floats(0.0, 1.0)
_SIGNED = st.floats(-1.0, 1.0)


@st.composite
def _body(draw, *, elastic: bool | None, densities: float = 3.0) -> dict[str, Any]:
    kind = draw(st.sampled_from(SHAPE_KINDS))
    n_corners = draw(st.integers(3, 8))
    params = (
        draw(_UNIT),
        draw(_UNIT),
        # angular gaps: well apart (>= 0.3 + 0 before scaling) and none above pi after scaling
        draw(st.lists(st.floats(0.0, 0.6), min_size=n_corners, max_size=n_corners)),
    )
    return {
        "kind": kind,
        "params": params,
        "size": draw(st.floats(-1.0, 0.0)),  # log10 of size / L
        "angle": draw(st.floats(-math.pi, math.pi)),
        # a quarter of the bodies written N turns further, N up to 1e11 (the loader reduces)
        "turns": round(10.0 ** draw(st.floats(3.0, 11.0))) if draw(st.integers(0, 3)) == 0 else 0,
        "density": 10.0 ** draw(st.floats(1.0, 1.0 + densities)),
        "restitution": 1.0 if elastic else draw(st.sampled_from([0.0, 0.5, 1.0]) | _UNIT),
        "velocity": (draw(_SIGNED), draw(_SIGNED)),
        "spin": draw(_SIGNED),
        "new_column": draw(st.booleans()),
        "resting": draw(st.booleans()),
        "lift": draw(_UNIT),  # height above the floor or the body below, in body sizes
        "gap": draw(_UNIT),  # horizontal gap to the previous column, in body sizes
        "still": draw(st.integers(0, 3)) == 0,  # a quarter of the bodies start at rest
    }


def _half_width(shape: _shapes.Shape) -> float:
    """Half the smallest width of a convex shape (over 360 directions, exact enough here)."""
    pts: list = []
    for e in shape.edges:
        if isinstance(e, _shapes.Ellipse):
            return min(e.a, e.b)
        if isinstance(e, _shapes.Segment):
            pts += [e.start, e.end]
        else:
            pts += [e.point(e.start_angle + e.span * i / 64) for i in range(65)]
    angles = np.pi * np.arange(360) / 360
    proj = np.asarray(pts) @ np.array([np.cos(angles), np.sin(angles)])
    return 0.5 * float(np.min(proj.max(axis=0) - proj.min(axis=0)))


@st.composite
def drawn_scenes(
    draw,
    *,
    max_bodies: int = 4,
    elastic: bool | None = None,
    environment: str | None = None,
    method: str | None = None,
    steps: int | tuple[int, int] = (10, 40),
    log_scale: tuple[float, float] = (-3.0, 3.0),
    travel: float = TRAVEL,
    densities: float = 3.0,
) -> Drawn:
    """A random valid scene with its characteristic numbers; see the module docstring.

    ``elastic``: all restitutions 1 (True) or drawn (None/False); ``environment``: "floor",
    "box" or drawn; ``method``: an integrator name or drawn from rk4/midpoint/euler;
    ``steps``: the number of time steps of ``[simulation] duration`` (an int or a range);
    ``travel``: the largest distance a body may move in one step, in half-widths of the
    thinnest body (sets dt); ``densities``: decades of density (10 .. 10^(1 + densities)
    kg/m^2; 9 gives mass ratios beyond 1e9 with the sizes)."""
    scale = 10.0 ** draw(st.floats(*log_scale))
    env = environment or draw(st.sampled_from(ENVIRONMENTS))
    elastic = bool(elastic) if elastic is not None else draw(st.booleans())
    count = draw(st.integers(1, max_bodies))  # uniform (a list strategy favours short lists)
    specs = [draw(_body(elastic=elastic, densities=densities)) for _ in range(count)]
    n_steps = steps if isinstance(steps, int) else draw(st.integers(*steps))
    method = method or draw(st.sampled_from(METHODS))

    sizes = [scale * 10.0 ** s["size"] for s in specs]
    sizes[0] = scale  # the largest body sets the scale
    v_scale, w_scale = math.sqrt(G * scale), math.sqrt(G / scale)

    bodies: list[dict[str, Any]] = []
    columns: list[tuple[float, float, float]] = []  # (x, top of the last body, base's reach)
    x_cursor = 0.0
    speed = 0.0
    thinnest = math.inf
    for k, (spec, size) in enumerate(zip(specs, sizes, strict=True)):
        kind = spec["kind"]
        table = _shape_table(kind, size, spec["params"])
        centred, offset = _build(kind, table).centred()
        thinnest = min(thinnest, _half_width(centred))
        reach = centred.bounding_radius  # about the centre of mass
        written = spec["angle"] + 2.0 * math.pi * spec["turns"]
        th = math.atan2(math.sin(written), math.cos(written))  # what the loader makes of it
        # a body goes on top of the last column only if it is no wider than that column's base
        if not columns or spec["new_column"] or reach > columns[-1][2]:
            x = x_cursor + (reach if columns else 0.0) + GAP * spec["gap"] * size
            low = lowest_point(centred, th)
            lift = 0.0 if spec["resting"] else LIFT * spec["lift"] * size
            y = -low + lift
            x_cursor = x + reach
            columns.append((x, y + reach, reach))
        else:
            x, top, base = columns[-1]
            y = top + reach + (0.0 if spec["resting"] else LIFT * spec["lift"] * size)
            x_cursor = max(x_cursor, x + reach)
            columns[-1] = (x, y + reach, base)
        vx, vy = (0.0, 0.0) if spec["still"] else (v_scale * spec["velocity"][0],
                                                    v_scale * spec["velocity"][1])  # fmt: skip
        w = 0.0 if spec["still"] else w_scale * spec["spin"]
        speed = max(speed, math.hypot(vx, vy) + abs(w) * reach)
        ox, oy = _rot(th, *offset)  # the shape's own origin sits at com - R(th) offset
        origin_v = (vx + w * oy, vy - w * ox)  # v_origin = v_com + w x (origin - com)
        bodies.append(
            {
                "name": f"{kind}{k + 1}",
                "shape": table,
                "density": spec["density"],
                "position": [x - ox, y - oy],
                "angle": written,
                "velocity": list(origin_v),
                "angular_velocity": w,
                "restitution": spec["restitution"],
            }
        )

    # centre the layout on x = 0 and add the environment
    left = min(b["position"][0] for b in bodies) - 2 * scale
    right = x_cursor + 2 * scale
    middle = 0.5 * (left + right)
    for b in bodies:
        b["position"][0] -= middle
    half = 0.5 * (right - left)
    top = max(t for _, t, _ in columns)
    # every point speed stays below this (energy: falling from the top, spin, and at most
    # doubled by an elastic hit of a heavier body)
    bound = 2.0 * (speed + math.sqrt(2.0 * G * top))
    dt = travel * thinnest / bound
    duration = n_steps * dt
    if env == "floor":
        wide = half + 10 * scale + 2 * bound * duration
        fixed = {"name": "floor", "fixed": True,
                 "shape": {"type": "wall", "start": [-wide, 0.0], "end": [wide, 0.0]}}  # fmt: skip
    else:
        height = 2.0 * (top + speed**2 / G + 2 * scale)
        fixed = {"name": "box", "fixed": True,
                 "shape": {"type": "box_walls", "width": 2 * half, "height": height}}  # fmt: skip
    data = {
        "scene": {
            "name": f"fuzz-{env}-{len(bodies)}",
            "contact_tolerance": CONTACT_TOLERANCE * thinnest,
            "overlap_tolerance": OVERLAP_TOLERANCE * thinnest,
        },
        "simulation": {"duration": duration, "dt": dt, "method": method},
        "body": [fixed, *bodies],
    }
    box_half = math.inf if env == "floor" else half
    wall_top = math.inf if env == "floor" else height
    return Drawn(data, scale, thinnest, dt, bound, top, env, box_half, elastic, wall_top)


@st.composite
def moving_pairs(
    draw,
    *,
    max_bodies: int = 3,
    elastic: bool | None = None,
    travel: float | tuple[float, ...] = (0.5, 2.0, 8.0),
    densities: float = 9.0,
    log_scale: tuple[float, float] = (-4.0, 4.0),
    max_steps: int = 60,
) -> Drawn:
    """2 .. ``max_bodies`` bodies flying at each other in empty space (no gravity, no fixed
    body), fast: each step moves the fastest point ``travel`` half-widths of the thinnest body
    (drawn from the values given; > 1: pairs pass through each other between two steps unless
    the impact search samples them). Sizes ``L / 10 .. L`` with L from 10^log_scale m, speeds
    0.1 .. 1000 body sizes per second (at least 10x the resting speed, so impacts bounce)
    aimed at the bodies' centroid with a miss of up to half the pair's size (so some hit
    off-centre or graze), spins up to the speed over the reach, restitution as
    :func:`drawn_scenes` (``elastic``),
    densities over ``densities`` decades (mass ratios beyond 1e9), shapes and large angles as
    :func:`drawn_scenes`. Laid out along a random zig-zag, bounding circles apart. With no
    external force, momentum and angular momentum are conserved exactly and energy never
    grows (:func:`check_conservation`)."""
    scale = 10.0 ** draw(st.floats(*log_scale))
    count = draw(st.integers(2, max_bodies))
    specs = [draw(_body(elastic=elastic, densities=densities)) for _ in range(count)]
    step_travel = travel if isinstance(travel, float) else draw(st.sampled_from(travel))
    speed = max(scale * 10.0 ** draw(st.floats(-1.0, 3.0)), 10.0 * settings.RESTING_SPEED)
    bodies: list[dict[str, Any]] = []
    placed: list[tuple[float, float, float]] = []  # (x, y, reach) of each centre of mass
    thinnest, bound = math.inf, 0.0
    for k, spec in enumerate(specs):
        size = scale * (1.0 if k == 0 else 10.0 ** spec["size"])
        kind = spec["kind"]
        table = _shape_table(kind, size, spec["params"])
        centred, offset = _build(kind, table).centred()
        thinnest = min(thinnest, _half_width(centred))
        reach = centred.bounding_radius
        x, y = 0.0, 0.0
        if placed:
            px, py, preach = placed[-1]
            heading = 2.0 * math.pi * draw(_UNIT)
            distance = preach + reach + scale * (0.05 + 3.0 * spec["gap"])
            x, y = px + distance * math.cos(heading), py + distance * math.sin(heading)
            if any(math.hypot(x - qx, y - qy) <= reach + qr for qx, qy, qr in placed):
                x, y = (
                    px + distance * math.cos(heading + math.pi),
                    py - distance * math.sin(heading),
                )
                assume(all(math.hypot(x - qx, y - qy) > reach + qr for qx, qy, qr in placed))
        placed.append((x, y, reach))
        bodies.append((spec, table, offset, reach, x, y))
    cx = sum(b[4] for b in bodies) / count
    cy = sum(b[5] for b in bodies) / count
    data_bodies = []
    for k, (spec, table, offset, reach, x, y) in enumerate(bodies):
        dx, dy = cx - x, cy - y
        norm = math.hypot(dx, dy) or 1.0
        miss = 0.5 * spec["velocity"][1]  # of the aim, sideways
        v = speed * (0.2 + 0.8 * abs(spec["velocity"][0]))
        vx = v * (dx - miss * dy) / norm
        vy = v * (dy + miss * dx) / norm
        w = spec["spin"] * v / reach
        bound = max(bound, math.hypot(vx, vy) + abs(w) * reach)
        written = spec["angle"] + 2.0 * math.pi * spec["turns"]
        th = math.atan2(math.sin(written), math.cos(written))
        ox, oy = _rot(th, *offset)
        data_bodies.append(
            {
                "name": f"{spec['kind']}{k + 1}",
                "shape": table,
                "density": spec["density"],
                "position": [x - ox, y - oy],
                "angle": written,
                "velocity": [vx + w * oy, vy - w * ox],
                "angular_velocity": w,
                "restitution": spec["restitution"],
            }
        )
    bound *= 3.0  # a light body hit by a heavy one leaves at up to twice its speed, plus its own
    dt = step_travel * thinnest / bound
    spread = max(math.hypot(x - cx, y - cy) + r for x, y, r in placed)
    steps = max(4, min(max_steps, math.ceil(3.0 * spread / (speed * 0.2) / dt)))
    data = {
        "scene": {
            "name": f"fuzz-space-{count}",
            "gravity": [0.0, 0.0],
            "contact_tolerance": CONTACT_TOLERANCE * thinnest,
            "overlap_tolerance": OVERLAP_TOLERANCE * thinnest,
        },
        "simulation": {"duration": steps * dt, "dt": dt, "method": "rk4"},
        "body": data_bodies,
    }
    return Drawn(data, scale, thinnest, dt, bound, 0.0, "space", math.inf, bool(elastic))


def scenes(**kwargs: Any) -> st.SearchStrategy[dict[str, Any]]:
    """Random valid scene dicts (``scene_from_dict`` input); arguments as ``drawn_scenes``."""
    return drawn_scenes(**kwargs).map(lambda d: d.data)


# -- bad input: one mutation of a valid scene ----------------------------------------------

BAD_VALUES = (
    math.nan,
    math.inf,
    -math.inf,
    -1.0,
    0.0,
    "1.0",
    True,
    None,
    [],
    [1.0],
    [1.0, 2.0, 3.0],
    {"x": 1.0},
    [[0.0, 0.0], [1.0, 1.0], [1.0, 0.0], [0.0, 1.0]],  # a self-intersecting polygon
    1e300,  # extremes: squares and fourth powers overflow or underflow
    -1e300,
    1e-300,
    5e-324,
    10**400,  # a TOML integer this large is a Python int beyond the float range
)


@st.composite
def mutated_scenes(draw) -> tuple[dict[str, Any], str]:
    """A valid scene with one value replaced by a bad one, or one unknown key added, or one
    required key removed: ``(data, description)``.  Whether the result is still valid (e.g.
    angle = 0.0) is for the test to find out."""
    data = draw(drawn_scenes(max_bodies=3, steps=5)).data
    bodies = data["body"]
    k = draw(st.integers(0, len(bodies) - 1))
    body = bodies[k]
    where = draw(st.sampled_from(["body", "shape", "scene", "simulation"]))
    table = {"body": body, "shape": body["shape"], "scene": data["scene"],
             "simulation": data["simulation"]}[where]  # fmt: skip
    action = draw(st.sampled_from(["replace", "add", "remove"]))
    keys = sorted(table)
    key = draw(st.sampled_from(keys))
    if action == "add":
        key = draw(st.sampled_from([key + "s", key[:-1], "colour", "Position", "mass "]))
        table[key] = 1.0
    elif action == "remove":
        del table[key]
    else:
        value = draw(st.sampled_from(BAD_VALUES))
        if isinstance(table[key], list) and table[key] and draw(st.booleans()):
            i = draw(st.integers(0, len(table[key]) - 1))
            table[key][i] = value
            key = f"{key}[{i}]"
        else:
            table[key] = value
    return data, f"{action} {where} {key!r} (body #{k + 1})"


# -- checks of a run -----------------------------------------------------------------------

KINDS = {
    "generator": "SceneError for a drawn scene (a generator bug or a false alarm of the loader)",
    "simulation": "SimulationError (a documented failure; counted by cause)",
    "exception": "any other exception out of load or simulate",
    "bad-error": "a SimulationError without step/time in its message, or with a bad .state",
    "nan": "a non-finite number in the recorded run",
    "warning": "a NumPy RuntimeWarning (overflow, invalid value) during the run",
    "energy": f"energy grew by more than {ENERGY_BOUND:g} x the energy scale",
    "penetration": f"penetration deeper than {PENETRATION_BOUND:g} x the thinnest half-width",
    "escaped": "a body's centre of mass left the floor's or box's free side",
    "momentum": "linear or angular momentum changed in empty space (no external force)",
}
_STEP_MESSAGE = re.compile(r"^step \d+ at t = \S+ s ")


@dataclass
class Report:
    """What ``check_scene`` found: ``problems`` maps a kind of ``KINDS`` to details."""

    drawn: Drawn
    scene: Any = None
    run: Any = None
    error: BaseException | None = None
    problems: dict[str, list[str]] = field(default_factory=dict)
    beyond: set[str] = field(default_factory=set)  # kinds past what the engine's guards catch

    def add(self, kind: str, detail: str, beyond_guards: bool = False) -> None:
        self.problems.setdefault(kind, []).append(detail)
        if beyond_guards:
            self.beyond.add(kind)

    def failures(self, *ignore: str) -> dict[str, list[str]]:
        """The problems but those of the kinds ``ignore``."""
        return {k: v for k, v in self.problems.items() if k not in ignore}


def simulation_cause(message: str) -> str:
    """A short cause of a SimulationError for counting: its message without the numbers."""
    inner = message.split("failed (", 1)[-1].split("); contacts:", 1)[0]
    inner = message if inner == message else inner
    inner = re.sub(r"^step \d+ at t = \S+ s ", "", inner)
    inner = re.sub(r"[-+]?\d[\d.e+-]*", "#", inner)
    inner = re.sub(r"\[[^\]]*\]", "[...]", inner)
    inner = re.sub(r"'[^']*'", "'...'", inner)
    return inner[:100]


def check_scene(drawn: Drawn, *, source: str = "fuzz") -> Report:
    """Load and run a drawn scene; check the properties (see ``KINDS``) of what it recorded."""
    import runtime

    report = Report(drawn)
    try:
        report.scene = runtime.scene_from_dict(drawn.data, source=source)
    except runtime.SceneError as exc:
        report.add("generator", str(exc))
        return report
    except Exception as exc:  # noqa: BLE001 -- counted, with its traceback
        report.error = exc
        report.add("exception", _summary(exc))
        return report
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            report.run = runtime.simulate(report.scene)
        except runtime.SimulationError as exc:
            report.error, report.run = exc, exc.run
            report.add("simulation", simulation_cause(str(exc)))
            _check_error(report, exc)
        except Exception as exc:  # noqa: BLE001
            report.error = exc
            report.add("exception", _summary(exc))
            return report
    for w in caught:
        if issubclass(w.category, RuntimeWarning):
            report.add("warning", f"{w.filename.rsplit('/', 1)[-1]}:{w.lineno}: {w.message}")
    check_run(report)
    return report


def _summary(exc: BaseException) -> str:
    """``Type: message`` and the innermost frames, for counting other exceptions."""
    frames = traceback.extract_tb(exc.__traceback__)[-3:]
    where = " <- ".join(
        f"{f.filename.rsplit('/', 1)[-1]}:{f.lineno} {f.name}" for f in frames[::-1]
    )
    return f"{type(exc).__name__}: {str(exc)[:120]} [{where}]"


def _check_error(report: Report, exc: Any) -> None:
    """A SimulationError names the step and time, and keeps the finite state before it."""
    n = len(report.scene.bodies)
    if not _STEP_MESSAGE.match(str(exc)):
        report.add("bad-error", f"message without 'step N at t = T s': {str(exc)[:120]}")
    try:
        poses, velocities = (np.asarray(x, dtype=float) for x in exc.state)
    except (TypeError, ValueError):
        report.add("bad-error", f".state is not (poses, velocities): {exc.state!r:.120}")
        return
    if poses.shape != (n, 3) or velocities.shape != (n, 3):
        report.add("bad-error", f".state shapes {poses.shape}, {velocities.shape}")
    elif not (np.all(np.isfinite(poses)) and np.all(np.isfinite(velocities))):
        report.add("bad-error", ".state is not finite")


def check_run(report: Report) -> None:
    """No NaN, energy bound (conservative integrators), penetration bound, nobody escaped."""
    drawn, scene, run = report.drawn, report.scene, report.run
    if run is None or len(run.t) == 0:
        return
    arrays = {
        "t": np.asarray(run.t, dtype=float),
        "poses": np.asarray(run.poses, dtype=float),
        "velocities": np.asarray(run.velocities, dtype=float),
        "energy": np.asarray(run.energy, dtype=float),
        "contact_forces": np.concatenate([np.ravel(f) for f in run.contact_forces] or [[]]),
    }
    for name, values in arrays.items():
        if not np.all(np.isfinite(values)):
            report.add("nan", f"run.{name} has {int(np.sum(~np.isfinite(values)))} non-finite")
    if "nan" in report.problems:
        return
    energy = arrays["energy"]
    if scene.simulation.method in CONSERVATIVE_METHODS:
        growth = float(np.max(energy - energy[0]))
        if growth > ENERGY_BOUND * drawn.energy_scale:
            k = int(np.argmax(energy - energy[0]))
            report.add(
                "energy",
                f"E grew by {growth:.3g} J = {growth / drawn.energy_scale:.3g} x the energy "
                f"scale at t = {arrays['t'][k]:.6g} s (step {k})",
                growth > settings.ENERGY_GROWTH_LIMIT * _guard_energy_scale(scene),
            )
    euler = scene.simulation.method == "euler"
    bound = (EULER_PENETRATION if euler else PENETRATION_BOUND) * drawn.thinnest
    depth, k, what, pair = _deepest(scene, run.poses, bound)
    if depth > bound:
        size = min(scene.shapes[i].bounding_radius for i in pair)
        report.add(
            "penetration",
            f"{what} by {depth:.3g} m = {depth / drawn.thinnest:.3g} half-widths at "
            f"t = {arrays['t'][k]:.6g} s (step {k})",
            depth > settings.PENETRATION_LIMIT * size,
        )
    if drawn.environment == "space":
        check_conservation(report)
        return
    moving = ~np.asarray(scene.fixed, dtype=bool)
    centres = arrays["poses"][:, moving, :2]
    names = [body.name for body in scene.bodies if not body.fixed]
    for b, name in enumerate(names):
        k = _escape(centres[:, b], drawn)
        if k is not None:
            where = f"{name!r} at {centres[k, b].tolist()} at t = {arrays['t'][k]:.6g} s"
            report.add("escaped", where, True)
            break


def _escape(path: np.ndarray, drawn: Drawn) -> int | None:
    """The first sample of a centre's ``path`` (K, 2) that went through the floor or a side
    wall, or None. Leaving over the top of the box's walls is no escape: a light body struck by
    a heavy one (mass ratios up to 1e9) can gain many times its own energy and fly out of the
    open box, and what it does afterwards (falling past the floor's end) is free flight."""
    below = path[:, 1] < -PENETRATION_BOUND * drawn.thinnest
    outside = np.abs(path[:, 0]) > drawn.half_width
    out = np.flatnonzero(below | outside)
    if out.size == 0:
        return None
    k = int(out[0])
    if outside[k] and k > 0:
        x0, y0 = abs(float(path[k - 1, 0])), float(path[k - 1, 1])
        x1, y1 = abs(float(path[k, 0])), float(path[k, 1])
        y_cross = y0 + (y1 - y0) * (drawn.half_width - x0) / (x1 - x0)
        if y_cross >= drawn.wall_top:
            return None
    return k


MOMENTUM_BOUND = 1e-9  # relative change of linear momentum in empty space (a linear invariant:
# impulses and forces are equal and opposite, and Runge-Kutta methods keep linear invariants)
ANGULAR_BOUND = 1e-6  # relative change of angular momentum (quadratic in the state: RK4 keeps it
# to its truncation error while contact forces act, as the energy, ENERGY_BOUND)


def check_conservation(report: Report) -> None:
    """Linear momentum and angular momentum about the origin stay what they were, to
    MOMENTUM_BOUND and ANGULAR_BOUND of their scales (sums over the bodies of m |v| and of
    m |r x v| + I |w|, the largest over the run): contacts act equal and opposite at a point."""
    scene, run = report.scene, report.run
    mass = np.array([b.mass for b in scene.bodies])
    inertia = np.array([b.inertia for b in scene.bodies], dtype=float)
    q, v = np.asarray(run.poses), np.asarray(run.velocities)
    p = np.einsum("b,kbc->kc", mass, v[:, :, :2])
    moment = mass * (q[:, :, 0] * v[:, :, 1] - q[:, :, 1] * v[:, :, 0]) + inertia * v[:, :, 2]
    p_scale = np.max(np.sum(mass * np.hypot(v[:, :, 0], v[:, :, 1]), axis=1))
    l_scale = np.max(
        np.sum(
            mass * np.hypot(q[:, :, 0], q[:, :, 1]) * np.hypot(v[:, :, 0], v[:, :, 1])
            + inertia * np.abs(v[:, :, 2]),
            axis=1,
        )
    )
    dp = float(np.max(np.hypot(*(p - p[0]).T)))
    dl = float(np.max(np.abs(moment.sum(axis=1) - moment[0].sum())))
    if dp > MOMENTUM_BOUND * p_scale or dl > ANGULAR_BOUND * l_scale:
        report.add(
            "momentum",
            f"momentum changed by {dp / p_scale:.3g}, angular momentum by {dl / l_scale:.3g} "
            f"of their scales ({len(run.impact_times)} impacts)",
            True,  # no guard watches momentum
        )


def deepest_penetration(scene: Any, poses_list: Any, bound: float) -> tuple[float, int, str]:
    """The deepest overlap over the recorded poses: the engine's own contacts (exact gaps,
    tolerance 0) and, since those leave out implausibly deep ones, sampled boundary points
    of one body inside another (runtime/scene_overlap.py). ``(depth, step, description)``."""
    return _deepest(scene, poses_list, bound)[:3]


def _deepest(scene: Any, poses_list: Any, bound: float) -> tuple[float, int, str, tuple]:
    """:func:`deepest_penetration` and the pair of bodies (scene indices)."""
    from runtime.io.scene_overlap import deepest_overlap

    worst: tuple = (0.0, 0, "", (0, 0))
    for k, poses in enumerate(poses_list):
        found = scene.contacts(poses, tolerance=0.0)
        for c, gap in enumerate(found.gap.tolist()):
            if -gap > worst[0]:
                pair = int(found.body1[c]), int(found.body2[c])
                names = scene.bodies[pair[0]].name, scene.bodies[pair[1]].name
                worst = (-gap, k, f"{found.case_name(c)} contact {names[0]}/{names[1]}", pair)
        deep = deepest_overlap(scene.shapes, poses, scene.fixed, max(bound, worst[0]))
        if deep is not None and deep[2] > worst[0]:
            names = scene.bodies[deep[0]].name, scene.bodies[deep[1]].name
            worst = (deep[2], k, f"{names[0]} inside {names[1]} (sampled)", deep[:2])
    return worst


def _guard_energy_scale(scene: Any) -> float:
    """The energy scale the engine's energy guard measures growth in (runtime.step.guards)."""
    from runtime.step.guards import energy_scale
    from runtime.step.world import kinetic_energy

    radii = np.array([s.bounding_radius for s in scene.shapes], dtype=float)
    return energy_scale(scene, radii, kinetic_energy(scene, scene.velocities()))
