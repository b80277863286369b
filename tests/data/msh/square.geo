// Unit square [0,1]^2 (z = 0) with named physical groups, for the 2D reader tests.
// Regenerate: gmsh -2 -format msh41 square.geo -o square.msh
SetFactory("OpenCASCADE");
Rectangle(1) = {0, 0, 0, 1, 1};
Mesh.MeshSizeMax = 0.5;
Mesh.MeshSizeMin = 0.5;
Physical Surface("plate") = {1};
Physical Curve("bottom") = {1};
Physical Curve("left") = {4};
