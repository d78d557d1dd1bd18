"""bpm from Python: read boundary-parametrized surfaces (.bpm) and evaluate phi, or make one.

    f = bpm.read("femur.bpm")
    positions = f.phi(triangles, barycentrics)   # (k,) ints, (k, 3) floats -> (k, 3)
    g = bpm.simplify(vertices, triangles, ratio=0.1)   # (n, 3), (m, 3) -> a bpm.File
    g.mesh().write("coarse.bpm")                       # with a tet mesh (TetGen)
    v, t, p, report = bpm.repair_self_intersections(vertices, triangles)   # a scan that crosses itself

See README.md, "Using bpm from a solver", and help(bpm.File).
"""
from ._bpm import (  # noqa: F401
    AlgorithmError,
    Error,
    File,
    InputError,
    OptionError,
    OutputError,
    __version__,
    format_version,
    read,
    repair_self_intersections,
    set_hdf5_isolation,
    simplify,
)

__all__ = ["read", "simplify", "repair_self_intersections", "File", "Error", "InputError", "OutputError", "OptionError", "AlgorithmError",
           "set_hdf5_isolation", "format_version", "__version__"]
