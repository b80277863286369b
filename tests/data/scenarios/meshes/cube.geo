// A coarse unit cube: cell group "cube", facet groups "bottom" and "top".
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 1, 1, 1};
Physical Volume("cube") = {1};
Physical Surface("bottom") = {5};
Physical Surface("top") = {6};
Mesh.MeshSizeMax = 1.0;
