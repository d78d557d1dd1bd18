"""bpm from Python: read boundary-parametrized surfaces (.bpm) and evaluate phi.

    f = bpm.read("femur.bpm")
    positions = f.phi(triangles, barycentrics)   # (k,) ints, (k, 3) floats -> (k, 3)

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
    set_hdf5_isolation,
)

__all__ = ["read", "File", "Error", "InputError", "OutputError", "OptionError", "AlgorithmError",
           "set_hdf5_isolation", "format_version", "__version__"]
