"""A sub-step that every island takes together moves each island by its own resting forces.

Why: where a trial is cut short (no forces obey the frame's friction modes before its end:
settings.TRIAL_CUTS), every island sub-steps to the first event of any of them; the state there
came for every body from the event island's own trajectory, integrated without the other
islands' resting contacts, so their bodies fell free for the sub-step (a disc resting on the
side of a box spinning at 84 rad/s went 6.3e-7 m into it in 4.7e-5 s so, in a trial cut for
another reason). runtime.step.stepper._IslandTrajectories.everyone_at takes the others from
the trial.
"""

from __future__ import annotations

import numpy as np

from runtime.step.stepper import _IslandTrajectories


class _Constant:
    """A trajectory that stays at (q, v)."""

    def __init__(self, q, v) -> None:
        self.q, self.v = q, v

    def at(self, t: float):
        return self.q, self.v


def test_a_sub_step_of_every_island_moves_each_by_its_own_forces():
    """Bodies 1 and 2 in islands 0 and 1 (body 0 fixed): at an event of island 0, body 1 comes
    from island 0's own trajectory and bodies 0 and 2 from the trial, whose arrays are left as
    they were; not split into islands, the trial is every island's trajectory."""
    labels = np.array([-1, 0, 1])
    trial = _Constant(np.zeros((3, 3)), np.zeros((3, 3)))
    own = _Constant(np.ones((3, 3)), 2 * np.ones((3, 3)))
    trajectories = _IslandTrajectories(None, trial, None, labels, split=True)
    trajectories.made[0] = own
    q, v = trajectories.everyone_at(0, 0.5)
    assert np.array_equal(q, [[0, 0, 0], [1, 1, 1], [0, 0, 0]])
    assert np.array_equal(v, [[0, 0, 0], [2, 2, 2], [0, 0, 0]])
    assert not trial.q.any() and not trial.v.any()
    unsplit = _IslandTrajectories(None, trial, None, labels, split=False)
    assert unsplit.everyone_at(0, 0.5)[0] is trial.q
