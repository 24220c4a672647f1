"""N copies of one scene as one scene, each copy in its own collision group.

Why: the engine already steps independent islands together -- every generated kernel called
once per stage for all contacts, the forces solved island by island, an impact located and
sub-stepped on its own island. Copies whose bodies can never touch are such islands, so N
copies become one scene with N times the bodies and the step needs no change. Collision groups
(runtime.collide.finder.ContactFinder) keep the copies apart however they lie, so a copy sits
exactly where its own scene puts it (same coordinates, same rounding).

Layout of a combined scene: first the template's fixed bodies that no variation touches,
shared by all copies (group -1: they touch every group); then each member copy's own bodies
(the moving ones and the varied fixed ones) in the template's order, in the group of the
copy's number. A :class:`Layout` maps both ways, and :func:`carry` moves the stepper's memory
(resting contacts, warm-start guesses) to the layout of fewer copies when some are dropped.
Within a copy the bodies keep the template's order, so each pair is computed as in the copy's
own scene (from its higher-index body); only where the template lists a shared fixed body after
a moving one does that order flip, which can change the last bits.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from runtime.collide.contact_keys import Guesses, key_set, objects
from runtime.model.scene import Scene
from runtime.solve.forces import Stabilisation
from runtime.step.stepper import Stepper
from runtime.step.variations import Variations


@dataclass(frozen=True)
class Layout:
    """The combined scene of the copies ``members`` (increasing copy numbers): ``index``
    (M, n) is the combined index of each template body in each member; per combined body,
    ``member`` is its member position (-1: shared) and ``template`` its template index;
    ``shared`` and ``own``: the template indices of the shared bodies and of a copy's own."""

    scene: Scene
    members: np.ndarray
    index: np.ndarray
    member: np.ndarray
    template: np.ndarray
    shared: np.ndarray
    own: np.ndarray

    def per_copy(self, values: np.ndarray) -> np.ndarray:
        """(M, n, ...) from a per-body array of the combined scene, (bodies, ...): the copies'
        own bodies are one block (a reshape), the shared ones are repeated."""
        rest = values.shape[1:]
        out = np.empty((len(self.members), self.index.shape[1], *rest))
        s = len(self.shared)
        out[:, self.own] = values[s:].reshape(len(self.members), len(self.own), *rest)
        out[:, self.shared] = values[:s]
        return out


class Copies:
    """The bodies of every copy (built once) and the combined scene of any set of them."""

    def __init__(self, template: Scene, variations: Variations) -> None:
        self.template, self.n = template, len(template.bodies)
        if template.joints or template.springs or template.mutual_gravity:
            raise ValueError(
                f"{template.source}: copies of a scene with joints, springs or mutual gravity "
                "are not supported yet (issue #16); run its variations one by one"
            )
        self.count, self.columns = variations.copies, variations.columns
        own = [i for i, b in enumerate(template.bodies) if not b.fixed or i in variations.bodies]
        self.own = np.array(own, dtype=np.int64)
        self.shared = np.array([i for i in range(self.n) if i not in own], dtype=np.int64)
        self.bodies = [
            [
                variations.body(template.bodies[i], i, c, f"{template.bodies[i].name}[{c}]")
                for i in own
            ]
            for c in range(self.count)
        ]
        g = template.gravity if variations.gravity is None else variations.gravity
        self.gravity = np.broadcast_to(np.asarray(g, dtype=float), (self.count, 2)).copy()
        self.varied_gravity = variations.gravity is not None

    def layout(self, members) -> Layout:
        members = np.asarray(members, dtype=np.int64)
        shared, own = len(self.shared), len(self.own)
        bodies = [self.template.bodies[i] for i in self.shared]
        for c in members.tolist():
            bodies += self.bodies[c]
        index = np.empty((len(members), self.n), dtype=np.int64)
        index[:, self.shared] = np.arange(shared)
        index[:, self.own] = shared + own * np.arange(len(members))[:, None] + np.arange(own)
        member = np.r_[np.full(shared, -1), np.repeat(np.arange(len(members)), own)]
        groups = np.r_[np.full(shared, -1), np.repeat(members, own)]
        template = np.r_[self.shared, np.tile(self.own, len(members))]
        scene = replace(self.template, bodies=bodies, groups=groups.tolist())
        return Layout(
            scene, members, index, member.astype(np.int64), template.astype(np.int64),
            self.shared, self.own,
        )  # fmt: skip

    def stepper(
        self,
        layout: Layout,
        method: str,
        stabilisation: Stabilisation | None,
        resting_speed: float,
    ) -> Stepper:
        """A stepper of the layout's scene with each copy's gravity. The engine has one |g| per
        scene (the margins of the swept contact search and the hold gap of resting contacts):
        with varied gravity it takes the largest, so the margins still bound every copy's
        motion (the hold gap then differs from a copy's own run only where g dt^2 is above
        2e-4 m: settings.DRIFT, HOLD)."""
        stepper = Stepper(layout.scene, method, stabilisation, resting_speed)
        if self.varied_gravity:
            g = self.gravity[layout.members]
            moving = ~stepper.fixed
            acc = stepper.forces.free_acceleration
            acc[moving, :2] = g[layout.member[moving]]
            stepper.gravity = float(np.max(np.hypot(g[:, 0], g[:, 1]), initial=0.0))
        return stepper


def snapshot(stepper: Stepper) -> tuple:
    """The stepper's memory between steps (restored by :func:`carry` when a step is redone)."""
    memory = stepper.forces.memory.copy()
    return stepper.held, stepper.recent, memory, stepper.evaluations, stepper.collision.finder.keys


def carry(memory: tuple, old: Layout, new: Layout, stepper: Stepper, own: int) -> None:
    """Give ``stepper`` (of ``new``) the ``memory`` (:func:`snapshot`) a stepper of ``old``
    had, for the copies in both: the resting contacts of the last frame and of the last step's
    end, and the warm-start guesses, with body indices moved. ``own``: bodies per copy."""
    shared = len(old.member) - own * len(old.members)
    position = np.searchsorted(new.members, old.members)
    kept = (position < len(new.members)) & (
        new.members[np.minimum(position, len(new.members) - 1)] == old.members
    )
    moved = np.full(len(old.member), -1, dtype=np.int64)
    moved[:shared] = np.arange(shared)
    for m in np.flatnonzero(kept).tolist():
        start = shared + own * m
        moved[start : start + own] = shared + own * int(position[m]) + np.arange(own)
    held, recent, guesses, evaluations, old_keys = memory
    new_keys = stepper.collision.finder.keys

    def keys(items: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(which of ``items`` have both bodies kept, their new keys)."""
        kept, out = [], []
        for key in items.tolist():
            b1, b2, *features = old_keys.parts(key)
            i, j = int(moved[b1]), int(moved[b2])
            kept.append(i >= 0 and j >= 0)
            if kept[-1]:
                out.append(new_keys.make((i, j, *features)))
        made = np.array(out, np.int64) if new_keys.packed else objects(out)
        return np.array(kept, bool), made

    stepper.held = key_set(keys(held)[1])
    stepper.recent = key_set(keys(recent)[1])
    kept, made = keys(guesses.keys)
    loaded = guesses.loaded
    if loaded is not None:
        loaded_kept, loaded_made = keys(loaded.keys)
        loaded = Guesses(loaded_made, loaded.clamped[loaded_kept])
    stepper.forces.memory = Guesses(made, guesses.clamped[kept], loaded)
    stepper.evaluations = evaluations
