"""Generated kernels: one module per contact case, friction row and joint. DO NOT EDIT.

Written by `regenerate-equations`; import a module only
when a scene needs it (runtime.solve.kernels does this), e.g. `import generated.vertex_circle`.
generated/compiled/ holds the same kernels compiled by numba, for the engine's batch loops.

CASES: the contact cases generated here. CASE_ID: a fixed number per case (the same whatever subset
is generated), which the engine stores per contact. GEOMETRY_COLUMNS: where each geometry argument
of a case sits in the engine's (m, 7) geometry array (body 1's feature from column 0, body 2's
from column 3).

FRICTION_CASES: the contact cases whose tangential (friction) row is generated here, in
generated/<case>_friction.py (the same contacts: CASE_ID and GEOMETRY_COLUMNS of the case).

JOINTS: the joints generated here (generated/<joint>.py). JOINT_ID: a fixed number per joint.
JOINT_ROWS: the constraint rows of each joint (pin 2: x and y; distance 1). JOINT_GEOMETRY_COLUMNS:
the columns of each joint's geometry in its (m, 7) array (anchor 1 from column 0, anchor 2 from 3,
then the length).

APPLIED: the applied forces generated here (generated/spring.py, mutual_gravity.py,
body_damping.py): generalized forces and potentials, called with keyword arguments (ARGUMENTS).
"""

CASES = (
    "circle_circle",
    "circle_edge",
    "vertex_circle",
    "vertex_edge",
)

CASE_ID = {
    "vertex_edge": 0,
    "vertex_circle": 1,
    "circle_edge": 2,
    "circle_circle": 3,
}

GEOMETRY_COLUMNS = {
    "vertex_edge": {
        "px1": 0,
        "py1": 1,
        "ex2": 3,
        "ey2": 4,
        "nx2": 5,
        "ny2": 6,
    },
    "vertex_circle": {
        "px1": 0,
        "py1": 1,
        "cx2": 3,
        "cy2": 4,
        "r2": 5,
    },
    "circle_edge": {
        "cx1": 0,
        "cy1": 1,
        "r1": 2,
        "ex2": 3,
        "ey2": 4,
        "nx2": 5,
        "ny2": 6,
    },
    "circle_circle": {
        "cx1": 0,
        "cy1": 1,
        "r1": 2,
        "cx2": 3,
        "cy2": 4,
        "r2": 5,
    },
}

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

APPLIED = (
    "body_damping",
    "mutual_gravity",
    "spring",
)

JOINT_ID = {
    "pin_joint": 0,
    "distance_joint": 1,
}

JOINT_ROWS = {
    "pin_joint": 2,
    "distance_joint": 1,
}

JOINT_GEOMETRY_COLUMNS = {
    "pin_joint": {
        "px1": 0,
        "py1": 1,
        "px2": 3,
        "py2": 4,
    },
    "distance_joint": {
        "px1": 0,
        "py1": 1,
        "px2": 3,
        "py2": 4,
        "length": 5,
    },
}
