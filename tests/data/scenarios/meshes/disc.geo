// A coarse disc of radius 0.5 m: cell group "disc1", facet group "rim".
SetFactory("OpenCASCADE");
Disk(1) = {0, 0, 0, 0.5};
Physical Surface("disc1") = {1};
Physical Curve("rim") = {1};
Mesh.MeshSizeMax = 0.25;
Mesh.MshFileVersion = 4.1;
