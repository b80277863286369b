#pragma once
// Small .msh 4.1 files for the reader tests, hand-written or as Gmsh wrote
// them (line numbers matter: the tests check them in error messages).
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

/// A single 10-node tetrahedron as Gmsh 4.8 writes it (`gmsh -3 -order 2`
/// of the tet (0,0,0), (1,0,0), (0,1,0), (0,0,1) with mesh size 10):
/// physical groups "bottom" (the 6-node triangle z = 0, tags 1 2 3 5 6 7)
/// and "solid". Gmsh numbers the element's nodes 1 3 4 2 (vertices) then
/// 7 10 8 5 9 6, the midside nodes of edges (0,1) (1,2) (2,0) (3,0) (3,2)
/// (3,1) in its vertex order. Lines: node 5's coordinates 43, facet block
/// header 64, facet 65, tet block header 66, tet 67.
inline constexpr const char* kGmshTet10 = R"($MeshFormat
4.1 0 8
$EndMeshFormat
$PhysicalNames
2
2 1 "bottom"
3 2 "solid"
$EndPhysicalNames
$Entities
4 6 4 1
1 0 0 0 0 
2 1 0 0 0 
3 0 1 0 0 
4 0 0 1 0 
1 0 0 0 1 0 0 0 2 1 -2 
2 0 0 0 1 1 0 0 2 2 -3 
3 0 0 0 0 1 0 0 2 3 -1 
4 0 0 0 0 0 1 0 2 1 -4 
5 0 0 0 1 0 1 0 2 2 -4 
6 0 0 0 0 1 1 0 2 3 -4 
1 0 0 0 1 1 0 1 1 3 1 2 3 
2 0 0 0 1 0 1 0 3 1 5 -4 
3 0 0 0 1 1 1 0 3 2 6 -5 
4 0 0 0 0 1 1 0 3 3 4 -6 
1 0 0 0 1 1 1 1 2 4 1 2 3 4 
$EndEntities
$Nodes
12 10 1 10
0 1 0 1
1
0 0 0
0 2 0 1
2
1 0 0
0 3 0 1
3
0 1 0
0 4 0 1
4
0 0 1
1 1 0 1
5
0.4999999999986718 0 0
1 2 0 1
6
0.5000000000013294 0.4999999999986707 0
1 3 0 1
7
0 0.5000000000013305 0
1 4 0 1
8
0 0 0.4999999999986718
1 5 0 1
9
0.5000000000013294 0 0.4999999999986707
1 6 0 1
10
0 0.5000000000013294 0.4999999999986707
2 1 0 0
3 1 0 0
$EndNodes
$Elements
2 2 1 2
2 1 9 1
1 1 2 3 5 6 7 
3 1 11 1
2 1 3 4 2 7 10 8 5 9 6 
$EndElements
)";

/// The unit square as Gmsh 4.8 writes it with `gmsh -2 -order 2` and mesh
/// size 10: four 6-node triangles around the centre node 9, physical
/// groups "left" (the 3-node line x = 0, nodes 4 1 8) and "plate". Lines:
/// line block 61-62, triangle block header 63, first triangle 64.
inline constexpr const char* kGmshSquareTri6 = R"($MeshFormat
4.1 0 8
$EndMeshFormat
$PhysicalNames
2
1 1 "left"
2 2 "plate"
$EndPhysicalNames
$Entities
4 4 1 0
1 0 0 0 0 
2 1 0 0 0 
3 1 1 0 0 
4 0 1 0 0 
1 0 0 0 1 0 0 0 2 1 -2 
2 1 0 0 1 1 0 0 2 2 -3 
3 0 1 0 1 1 0 0 2 3 -4 
4 0 0 0 0 1 0 1 1 2 4 -1 
1 0 0 0 1 1 0 1 2 4 1 2 3 4 
$EndEntities
$Nodes
9 13 1 13
0 1 0 1
1
0 0 0
0 2 0 1
2
1 0 0
0 3 0 1
3
1 1 0
0 4 0 1
4
0 1 0
1 1 0 1
5
0.4999999999986718 0 0
1 2 0 1
6
1 0.4999999999986718 0
1 3 0 1
7
0.5000000000013305 1 0
1 4 0 1
8
0 0.5000000000013305 0
2 1 0 5
9
10
11
12
13
0.5 0.5 0
0.75 0.25 0
0.25 0.25 0
0.25 0.75 0
0.75 0.75 0
$EndNodes
$Elements
2 5 1 5
1 4 8 1
1 4 1 8 
2 1 9 4
2 1 2 9 5 10 11 
3 4 1 9 8 11 12 
4 2 3 9 6 13 10 
5 3 4 9 7 12 13 
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
