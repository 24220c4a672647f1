"""A run's per-step contacts as one flat table: a row per contact per recorded step.

Why: the forces of the individual contacts, and which bodies, case and point each belongs to,
are what one needs to check a run against a hand calculation; trajectory.npz keeps them as
flat arrays (no pickled objects) with a step index into ``t``.

This is the one place that reads how a Run stores its contacts: ``run.contacts[k]``, a
``Contacts`` array set (runtime.collide.contact_set), ``run.contact_forces[k]`` their forces and
``run.friction_forces[k]`` their friction forces (0 where a run has none recorded).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from runtime.collide.contact_set import CASE_NAMES, KIND_NAMES

__all__ = ["CONTACT_FIELDS", "contact_table"]

# name in trajectory.npz: (dtype, shape of one row)
CONTACT_FIELDS: dict[str, tuple[str, tuple[int, ...]]] = {
    "contact_step": ("int64", ()),  # index into t of the recorded step
    "contact_body1": ("int64", ()),  # body indices (body_names); body 2 owns the normal
    "contact_body2": ("int64", ()),
    "contact_case": ("U13", ()),  # vertex_edge, vertex_circle, circle_edge, circle_circle
    "contact_feature": ("int64", (4,)),  # kind 1, index 1, kind 2, index 2 (contact_kinds)
    "contact_point": ("float64", (2,)),  # world point of body 1's feature, m
    "contact_normal": ("float64", (2,)),  # world unit normal, from body 2 toward body 1
    "contact_gap": ("float64", ()),  # the kernel's gap d, m
    "contact_force": ("float64", ()),  # normal force, N
    "contact_friction": ("float64", ()),  # friction force f_t on body 1 along n turned +90°, N
}


def _rows_of_arrays(contacts: Any) -> dict[str, Any]:
    return {
        "contact_body1": contacts.body1,
        "contact_body2": contacts.body2,
        "contact_case": [CASE_NAMES[int(c)] for c in contacts.case],
        "contact_feature": contacts.feature,
        "contact_point": contacts.point,
        "contact_normal": contacts.normal,
        "contact_gap": contacts.gap,
    }


def contact_table(run: Any) -> dict[str, np.ndarray]:
    """The contacts of every recorded step of ``run`` with their forces, as the arrays of
    :data:`CONTACT_FIELDS` (m rows in all), plus ``contact_kinds`` (the feature kind names)."""
    columns: dict[str, list[np.ndarray]] = {name: [] for name in CONTACT_FIELDS}
    friction = getattr(run, "friction_forces", None) or [None] * len(run.contacts)
    for k, (contacts, forces) in enumerate(zip(run.contacts, run.contact_forces, strict=True)):
        forces = np.atleast_1d(np.asarray(forces, dtype=float))
        if len(forces) != len(contacts):
            raise ValueError(f"step {k} records {len(contacts)} contacts but {len(forces)} forces")
        if not len(contacts):
            continue
        rows = _rows_of_arrays(contacts)
        rows["contact_step"] = np.full(len(contacts), k)
        rows["contact_force"] = forces
        rows["contact_friction"] = np.zeros(len(forces)) if friction[k] is None else friction[k]
        for name, (dtype, shape) in CONTACT_FIELDS.items():
            columns[name].append(np.asarray(rows[name], dtype=dtype).reshape(-1, *shape))
    table = {
        name: np.concatenate(parts) if parts else np.zeros((0, *shape), dtype=dtype)
        for (name, (dtype, shape)), parts in zip(
            CONTACT_FIELDS.items(), columns.values(), strict=True
        )
    }
    table["contact_kinds"] = np.array(KIND_NAMES)
    return table
