"""Meshes of the bodies (gmsh / structured quadrilaterals -> DOLFINx), units mm.

Facet tags everywhere: 1 contact face, 2 opposite face, 3 left, 4 right (see
:mod:`rubberfriction.meshes.common`). All builders return :class:`BodyMesh`.
"""

from rubberfriction.meshes.block import contact_element_size, rubber_block
from rubberfriction.meshes.common import CONTACT, LEFT, OPPOSITE, RIGHT, BodyMesh
from rubberfriction.meshes.grading import geometric_sizes, graded_nodes

__all__ = ["BodyMesh", "CONTACT", "OPPOSITE", "LEFT", "RIGHT", "rubber_block",
           "contact_element_size", "geometric_sizes", "graded_nodes"]
