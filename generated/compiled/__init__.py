"""Generated kernels compiled by numba: one module per contact case, friction row and joint. DO NOT EDIT.

Written by `regenerate-equations`; the same expressions as the NumPy kernels one level up, with
batch loops over contacts (or joints). Import a module only when a scene needs it.
"""

CASES = (
    "circle_circle",
    "circle_edge",
    "vertex_circle",
    "vertex_edge",
)

FRICTION_CASES = (
    "circle_circle",
    "circle_edge",
    "vertex_circle",
    "vertex_edge",
)

JOINTS = (
    "distance_joint",
    "pin_joint",
)
