"""Generated contact kernels compiled by numba, one module per contact case. DO NOT EDIT.

Written by `regenerate-equations`; the same expressions as the NumPy kernels one level up, with
batch loops over contacts. Import a case's module only when a scene needs it.
"""

CASES = (
    "circle_circle",
    "circle_edge",
    "vertex_circle",
    "vertex_edge",
)
