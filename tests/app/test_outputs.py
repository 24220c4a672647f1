"""What a run's files hold: every contact with its force, the poses as CSV, the energy split into
impact losses and drift, and plots whose legends stay off the data and whose names are text.

References: the weight of a resting body (its one contact carries m g; a box's two corners carry
m g / 2 each), the free fall and bounce of a disc (impact speeds sqrt(2 g h) e^k, losses
(1 - e^2) m v^2 / 2), and the trajectory arrays themselves for the CSV.
"""

from __future__ import annotations

import csv
import json
import math
from types import SimpleNamespace

import matplotlib
import numpy as np
import pytest
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

import runtime
from runtime.app import cli, plotting
from runtime.app.contact_table import CONTACT_FIELDS, contact_table
from runtime.app.energy import energy_budget
from runtime.collide.contact_set import Contacts

G = 9.81
DISC_WEIGHT = 1000.0 * math.pi * 0.1**2 * G  # the resting disc of SMALL_SCENE


def run_cli(args, capsys):
    status = cli.main([*args, "--quiet"])
    captured = capsys.readouterr()
    assert status == 0, captured.err
    return captured.out


# -- the contact table ---------------------------------------------------------------------------


def test_trajectory_holds_each_contact_with_bodies_case_point_and_force(
    tmp_path, scene_file, capsys
):
    out = tmp_path / "out"
    run_cli([str(scene_file()), "--duration", "0.05", "--out", str(out), "--no-gif"], capsys)
    with np.load(out / "trajectory.npz") as data:
        steps = len(data["t"])
        assert list(data["contact_step"]) == list(range(steps))  # one contact per step
        assert set(data["contact_body1"]) == {1} and set(data["contact_body2"]) == {0}
        assert list(data["body_names"][[1, 0]]) == ["resting", "floor"]
        assert set(data["contact_case"]) == {"circle_edge"}
        np.testing.assert_allclose(data["contact_force"], DISC_WEIGHT, rtol=1e-9)
        np.testing.assert_allclose(data["contact_point"], [[0.0, 0.0]] * steps, atol=1e-12)
        np.testing.assert_allclose(data["contact_normal"], [[0.0, 1.0]] * steps, atol=1e-12)
        assert np.all(np.abs(data["contact_gap"]) < 1e-9)
        kinds = list(data["contact_kinds"])
        assert [kinds[k] for k in data["contact_feature"][0, [0, 2]]] == ["edge", "edge"]
        np.testing.assert_array_equal(data["total_contact_force"], data["contact_force"])
        assert data["contact_force"].dtype == np.float64 and data["contact_case"].dtype.kind == "U"


def test_a_box_on_a_floor_has_two_corner_contacts_sharing_its_weight():
    scene = runtime.scene_from_dict(
        {
            "body": [
                {"name": "floor", "fixed": True,
                 "shape": {"type": "wall", "start": [-1.0, 0.0], "end": [1.0, 0.0]}},
                {"name": "box", "mass": 2.0, "position": [0.3, 0.1],
                 "shape": {"type": "polygon",
                           "points": [[-0.2, -0.1], [0.2, -0.1], [0.2, 0.1], [-0.2, 0.1]]}},
            ]
        }
    )  # fmt: skip
    run = runtime.simulate(scene, 0.003, 0.001, "rk4")
    table = contact_table(run)
    assert list(table["contact_step"]) == [0, 0, 1, 1, 2, 2, 3, 3]
    assert set(table["contact_case"]) == {"vertex_edge"}
    np.testing.assert_allclose(table["contact_force"], 2.0 * G / 2, rtol=1e-9)
    corners = sorted(map(tuple, np.round(table["contact_point"][:2], 12)))
    assert corners == [(0.1, 0.0), (0.5, 0.0)]
    kinds = table["contact_kinds"][table["contact_feature"][:, [0, 2]]]
    assert (kinds == ["vertex", "edge"]).all()


def test_contact_sets_recorded_as_arrays_give_the_same_table():
    """The Run the step rewrite records (a Contacts set per step) reads the same way."""
    one = Contacts(
        case=np.array([2]),
        body1=np.array([1]),
        body2=np.array([0]),
        geometry=np.zeros((1, 7)),
        feature=np.array([[1, 0, 1, 0]]),
        gap=np.array([1e-12]),
        point=np.array([[0.5, 0.0]]),
        normal=np.array([[0.0, 1.0]]),
    )
    run = SimpleNamespace(
        t=[0.0, 0.1, 0.2],
        contacts=[one, Contacts.empty(), one],
        contact_forces=[np.array([3.0]), np.zeros(0), np.array([4.0])],
    )
    table = contact_table(run)
    assert list(table["contact_step"]) == [0, 2]
    assert list(table["contact_case"]) == ["circle_edge"] * 2
    assert list(table["contact_force"]) == [3.0, 4.0]
    assert table["contact_point"].tolist() == [[0.5, 0.0]] * 2
    for name, (dtype, shape) in CONTACT_FIELDS.items():
        assert table[name].dtype == np.dtype(dtype) and table[name].shape[1:] == shape


def test_a_step_whose_forces_do_not_match_its_contacts_is_an_error():
    run = SimpleNamespace(t=[0.0], contacts=[[]], contact_forces=[np.array([1.0])])
    with pytest.raises(ValueError, match="step 0 records 0 contacts but 1 forces"):
        contact_table(run)


# -- CSV -----------------------------------------------------------------------------------------


def test_csv_holds_every_pose_exactly_with_named_columns(tmp_path, scene_file, capsys):
    from conftest import SMALL_SCENE

    scene = scene_file(SMALL_SCENE.replace('name = "falling"', 'name = "box, \\"B\\""'))
    out = tmp_path / "out"
    run_cli([str(scene), "--duration", "0.02", "--out", str(out), "--no-gif", "--csv"], capsys)
    with (out / "poses.csv").open(newline="") as stream:
        rows = list(csv.reader(stream))
    names = ["floor", "resting", 'box, "B"']
    assert rows[0] == ["t [s]"] + [
        f"{n} {w}" for n in names for w in ("x [m]", "y [m]", "angle [rad]")
    ]
    values = np.array(rows[1:], dtype=float)
    with np.load(out / "trajectory.npz") as data:
        np.testing.assert_array_equal(values[:, 0], data["t"])
        np.testing.assert_array_equal(values[:, 1:], data["poses"].reshape(len(data["t"]), -1))
    assert "poses.csv" in json.loads((out / "summary.json").read_text())["files"]


# -- energy: lost at impacts and drift -----------------------------------------------------------

BOUNCE = {
    "body": [
        {"name": "floor", "fixed": True,
         "shape": {"type": "wall", "start": [-1.0, 0.0], "end": [1.0, 0.0]}},
        {"name": "ball", "mass": 2.0, "restitution": 0.5, "position": [0.0, 1.1],
         "shape": {"type": "disc", "radius": 0.1}},
    ]
}  # fmt: skip


def bounce_losses(run, mass=2.0, h=1.0, e=0.5):
    """The exact energy lost at each impact of the ball dropped from h, binned into the recorded
    steps (the loss between record k-1 and record k at k)."""
    v = math.sqrt(2 * G * h)
    times, losses, t = [], [], math.sqrt(2 * h / G)
    while t <= run.t[-1]:
        times.append(t)
        losses.append(0.5 * mass * v * v * (1 - e * e))
        t += 2 * e * v / G
        v *= e
    binned = np.zeros(len(run.t))
    for when, loss in zip(times, losses, strict=True):
        binned[np.searchsorted(run.t, when)] += loss
    return times, binned


@pytest.fixture(scope="module")
def bounce_run():
    scene = runtime.scene_from_dict(BOUNCE)
    return scene, runtime.simulate(scene, 1.0, 1e-3, "rk4")


def test_energy_budget_splits_impact_losses_from_drift(bounce_run):
    """The engine's impact losses are the exact bounce losses (1 - e^2) m v^2 / 2, each in the
    record after its impact; what is left of the energy change is the integrator's drift."""
    scene, run = bounce_run
    times, losses = bounce_losses(run)
    np.testing.assert_allclose(run.impact_times, times, atol=1e-9)  # 2 impacts
    np.testing.assert_allclose(run.impact_losses, losses, rtol=1e-9, atol=1e-12)
    budget = energy_budget(run)
    np.testing.assert_allclose(budget.lost, np.cumsum(losses), rtol=1e-9)
    assert budget.lost[-1] == pytest.approx(0.5 * 2.0 * 2 * G * 1.0 * (1 - 0.25) * 1.25)
    assert np.max(np.abs(budget.drift)) < 1e-9 * 2.0 * G * 1.0  # the integrator's only
    assert budget.impacts == 2


def test_command_names_impact_losses_and_drift_apart(bounce_run, tmp_path, capsys):
    scene, run = bounce_run
    _, losses = bounce_losses(run)
    path = tmp_path / "bounce.toml"
    path.write_text(
        '[[body]]\nname = "floor"\nfixed = true\n'
        'shape = { type = "wall", start = [-1.0, 0.0], end = [1.0, 0.0] }\n'
        '[[body]]\nname = "ball"\nmass = 2.0\nrestitution = 0.5\nposition = [0.0, 1.1]\n'
        'shape = { type = "disc", radius = 0.1 }\n'
    )
    args = [str(path), "--duration", "1", "--dt", "0.001", "--out", str(tmp_path / "o"), "--no-gif"]
    line = run_cli(args, capsys)
    total = float(np.sum(losses))
    assert f"energy lost at 2 impacts {total:.3g} J, numerical drift " in line
    info = json.loads((tmp_path / "o" / "summary.json").read_text())
    assert info["impact_energy_loss"] == pytest.approx(total)
    assert abs(info["numerical_drift"]) < 1e-9 * 2.0 * G
    assert info["energy_drift"] == pytest.approx(-total, rel=1e-9)
    with np.load(tmp_path / "o" / "trajectory.npz") as data:
        np.testing.assert_allclose(data["impact_losses"], losses, rtol=1e-9, atol=1e-12)
        assert len(data["impact_times"]) == 2


# -- plots ---------------------------------------------------------------------------------------


def overlaps(a, b) -> bool:
    return a.x0 < b.x1 and b.x0 < a.x1 and a.y0 < b.y1 and b.y0 < a.y1


def test_legends_sit_beside_the_axes_not_on_the_data(bounce_run):
    scene, run = bounce_run
    fig = plotting.energy_forces_figure(run, [b.name for b in scene.bodies])
    renderer = FigureCanvasAgg(fig).get_renderer()
    fig.draw(renderer)
    legends = [(ax, ax.get_legend()) for ax in fig.axes if ax.get_legend() is not None]
    assert len(legends) == 2  # the energy panel (with losses) and the forces panel
    for ax, legend in legends:
        assert not overlaps(legend.get_window_extent(renderer), ax.get_window_extent(renderer))
    texts = [t.get_text() for t in legends[0][1].get_texts()]
    assert texts == ["E(t) - E(0)", "lost at impacts", "numerical drift"]


def test_names_with_dollars_are_plain_text(tmp_path):
    """'$' starts mathtext in matplotlib: a name it cannot parse used to crash the plot after the
    run. The same names as plain text draw fine and read as written."""
    name, body = "cost $5 \\nope$", "a$b^$"
    resting = {**BOUNCE["body"][1], "position": [0.0, 0.1], "name": body}
    scene = runtime.scene_from_dict({"scene": {"name": name}, "body": [BOUNCE["body"][0], resting]})
    run = runtime.simulate(scene, 0.01, 1e-3, "rk4")
    fig = plotting.energy_forces_figure(run, [b.name for b in scene.bodies])
    fig.savefig(tmp_path / "plot.png")
    assert fig.axes[0].get_title() == f"{name}: rk4, dt = 0.001 s"
    legend = [t.get_text() for t in fig.axes[1].get_legend().get_texts()]
    assert legend == ["total", f"{body}/floor (circle_edge)"]
    # the control: with mathtext on, matplotlib cannot draw that title
    with matplotlib.rc_context({"text.parse_math": True}):
        control = Figure()
        control.suptitle(name)
        with pytest.raises(ValueError):
            control.savefig(tmp_path / "control.png")
