"""Meshes of the bodies (gmsh / structured quadrilaterals -> DOLFINx), units mm.

Facet tags everywhere: 1 contact face, 2 opposite face, 3 left, 4 right (see
:mod:`rubberfriction.meshes.common`). All builders return :class:`BodyMesh`.
"""

from rubberfriction.meshes.block import contact_element_size, rubber_block
from rubberfriction.meshes.common import CONTACT, LEFT, OPPOSITE, RIGHT, BodyMesh
from rubberfriction.meshes.cylinder import hertz_cylinder
from rubberfriction.meshes.grading import geometric_sizes, graded_nodes
from rubberfriction.meshes.patch import patch_test_pair
from rubberfriction.meshes.road import road_body

__all__ = ["BodyMesh", "CONTACT", "OPPOSITE", "LEFT", "RIGHT", "rubber_block",
           "contact_element_size", "road_body", "hertz_cylinder", "patch_test_pair",
           "geometric_sizes", "graded_nodes"]
