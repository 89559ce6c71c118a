"""bagdem from Python: load a case, apply overrides, run any bagdem command with its progress shown,
and read every output as numpy arrays and pandas frames, with tools/plot's figures (docs/python.md).

From a clone, after the build (tools/test or tools/demo), with nothing installed:

    PYTHONPATH=python python3 -c 'import bagdem; print(bagdem.Case("cases/pipe-beanbag").check())'

The package runs the clone's build/bagdem ($BAGDEM names another executable).
"""
from .case import Case
from .command import BagdemError, binary, run
from .results import H5, Results, read_table

__all__ = ["Case", "Results", "H5", "read_table", "run", "binary", "BagdemError"]
