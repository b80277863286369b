// The §6.3 ball's spherical shell (radii 0.2 and 0.4 m) with its groups,
// meshed at the uniform size h (gmsh shell.geo -setnumber h H -3 -bin ...):
// what bench/run_large.sh reads as a binary .msh file.
SetFactory("OpenCASCADE");
Sphere(1) = {0, 0, 0, 0.4};
Sphere(2) = {0, 0, 0, 0.2};
BooleanDifference(3) = { Volume{1}; Delete; }{ Volume{2}; Delete; };
Physical Volume("ball") = {3};
s() = Boundary{ Volume{3}; };
Physical Surface("outer") = {s(0)};
Physical Surface("inner") = {s(1)};
Mesh.MeshSizeMin = h;
Mesh.MeshSizeMax = h;
