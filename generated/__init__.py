"""Generated contact kernels, one module per contact case. DO NOT EDIT.

Written by `regenerate-equations`; import a case's module only
when a scene needs it (runtime.solve.kernels does this), e.g. `import generated.vertex_circle`.
"""

CASES = (
    "circle_circle",
    "circle_edge",
    "vertex_circle",
    "vertex_edge",
)
