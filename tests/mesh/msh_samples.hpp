#pragma once
// Small hand-written .msh 4.1 files for the reader tests (line numbers
// matter: the tests check them in error messages).
#include <gtest/gtest.h>

#include <string>

namespace conserve::mesh::test {

/// One positive tet (tags 1-4) plus an unused node 5, a cell group "solid"
/// and a facet group "bottom" (z = 0). Lines: tet block header 32, tet 33,
/// facet 31, node tags 17-21, coordinates 22-26.
inline constexpr const char* kTinyTet = R"($MeshFormat
4.1 0 8
$EndMeshFormat
$PhysicalNames
2
2 1 "bottom"
3 2 "solid"
$EndPhysicalNames
$Entities
0 0 1 1
1 0 0 0 1 1 0 1 1 0
1 0 0 0 1 1 1 1 2 1 1
$EndEntities
$Nodes
1 5 1 5
3 1 0 5
1
2
3
4
5
0 0 0
1 0 0
0 1 0
0 0 1
7 7 7
$EndNodes
$Elements
2 2 1 2
2 1 2 1
1 1 3 2
3 1 4 1
2 1 2 3 4
$EndElements
)";

/// The unit square as two counter-clockwise triangles, no groups. Node 3
/// (1, 1, 0) is on line 17.
inline constexpr const char* kTinySquare2D = R"($MeshFormat
4.1 0 8
$EndMeshFormat
$Entities
0 0 1 0
1 0 0 0 1 1 0 0 0
$EndEntities
$Nodes
1 4 1 4
2 1 0 4
1
2
3
4
0 0 0
1 0 0
1 1 0
0 1 0
$EndNodes
$Elements
1 2 1 2
2 1 2 2
1 1 2 3
2 1 3 4
$EndElements
)";

/// A bare surface (no cells): the unit square z = 0 as two triangles of
/// the physical group "pad", normals +z. The triangles use the nodes in
/// the order 3, 4, 1, 2 (tags), which is their numbering; element 2 is on
/// line 28.
inline constexpr const char* kTinySurface = R"($MeshFormat
4.1 0 8
$EndMeshFormat
$PhysicalNames
1
2 1 "pad"
$EndPhysicalNames
$Entities
0 0 1 0
1 0 0 0 1 1 0 1 1 0
$EndEntities
$Nodes
1 4 1 4
2 1 0 4
1
2
3
4
0 0 0
1 0 0
1 1 0
0 1 0
$EndNodes
$Elements
1 2 1 2
2 1 2 2
1 3 4 1
2 3 1 2
$EndElements
)";

/// A bare line (2D, no cells): (1, 0) → (0, 0) → (-1, 0) as two segments,
/// normals (t_y, −t_x) = +y. Element 2 is on line 22.
inline constexpr const char* kTinyLine2D = R"($MeshFormat
4.1 0 8
$EndMeshFormat
$Entities
0 1 0 0
1 -1 0 0 1 0 0 0 0
$EndEntities
$Nodes
1 3 1 3
1 1 0 3
1
2
3
1 0 0
0 0 0
-1 0 0
$EndNodes
$Elements
1 2 1 2
1 1 1 2
1 1 2
2 2 3
$EndElements
)";

/// `text` with the first occurrence of `from` replaced by `to`.
inline std::string replace(std::string text, const std::string& from, const std::string& to) {
  const std::size_t at = text.find(from);
  if (at == std::string::npos) {
    ADD_FAILURE() << "sample does not contain '" << from << "'";
    return text;
  }
  return text.replace(at, from.size(), to);
}

}  // namespace conserve::mesh::test
