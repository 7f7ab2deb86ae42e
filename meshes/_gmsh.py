"""gmsh session handling for the mesh builders.

gmsh keeps global state. `gmsh_session` initialises it, silences its terminal output unless
`verbose`, pins the options that influence reproducibility (one thread, fixed random seed) and
always finalises it, also on errors. The mesh builders therefore must not be called while the
caller holds an initialised gmsh session of its own (gmsh 4.8 cannot tell whether it is
initialised). gmsh is imported here, lazily: importing it resets the SIGINT handler (so
Ctrl-C would no longer raise KeyboardInterrupt); the session puts the caller's handler back.
"""

from __future__ import annotations

import signal
import threading
from contextlib import contextmanager
from typing import Iterator

import numpy as np

_GMSH_QUAD = 3


@contextmanager
def gmsh_session(name: str, verbose: bool = False) -> Iterator:
    """Yield the `gmsh` module with a fresh model `name`; finalise gmsh on exit and put back
    the SIGINT handler the caller had."""
    handler = signal.getsignal(signal.SIGINT)
    import gmsh

    gmsh.initialize(readConfigFiles=False)
    try:
        gmsh.option.setNumber("General.Terminal", 1 if verbose else 0)
        gmsh.option.setNumber("General.Verbosity", 5 if verbose else 0)
        gmsh.option.setNumber("General.NumThreads", 1)
        gmsh.option.setNumber("Mesh.RandomSeed", 1)
        gmsh.model.add(name)
        yield gmsh
    finally:
        gmsh.finalize()
        if handler is not None and threading.current_thread() is threading.main_thread():
            signal.signal(signal.SIGINT, handler)


def quad_mesh_arrays(gmsh) -> tuple[np.ndarray, np.ndarray]:
    """Points (N, 2) and quadrilaterals (M, 4, vertices around the cell, gmsh order) of the
    2D mesh of the current model. Raises if gmsh produced any other 2D element type."""
    types, _, node_tags = gmsh.model.mesh.getElements(2)
    types = [int(t) for t in types]
    if types != [_GMSH_QUAD]:
        names = [gmsh.model.mesh.getElementProperties(t)[0] for t in types]
        raise RuntimeError(f"gmsh produced 2D elements {names}; only 4-node quadrilaterals "
                           "are accepted (DOLFINx needs a single cell type)")
    quads = np.asarray(node_tags[0], dtype=np.int64).reshape(-1, 4)
    tags, coords, _ = gmsh.model.mesh.getNodes()
    coords = np.asarray(coords, dtype=float).reshape(-1, 3)
    used, inverse = np.unique(quads, return_inverse=True)
    position = {int(t): i for i, t in enumerate(np.asarray(tags, dtype=np.int64))}
    points = coords[[position[int(t)] for t in used], :2]
    return points, inverse.reshape(-1, 4).astype(np.int64)
