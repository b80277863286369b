// Unit cube [0,1]^3 with named physical groups, for the msh reader tests.
// Regenerate: gmsh -3 -format msh41 cube.geo -o cube_ascii.msh
//             gmsh -3 -format msh41 -bin cube.geo -o cube_binary.msh
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 1, 1, 1};
Mesh.MeshSizeMax = 0.5;
Mesh.MeshSizeMin = 0.5;
Physical Volume("body") = {1};
Physical Surface("xmin") = {1};
Physical Surface("zmax") = {6};
