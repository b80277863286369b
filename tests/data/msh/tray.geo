// A shallow tray as a bare triangle surface (no volume), for the surface
// reader tests and rigid obstacles: bottom [-0.5, 0.5]² at z = 0 and four
// walls sloping up to [-0.75, 0.75]² at z = 0.25; every curve loop runs
// counter-clockwise seen from inside the tray, so the triangles' normals
// point into it (+z side). 25 nodes, 40 triangles.
// Regenerate: gmsh -2 -format msh41 tray.geo -o tray.msh
Point(1) = {-0.5, -0.5, 0};
Point(2) = {0.5, -0.5, 0};
Point(3) = {0.5, 0.5, 0};
Point(4) = {-0.5, 0.5, 0};
Point(5) = {-0.75, -0.75, 0.25};
Point(6) = {0.75, -0.75, 0.25};
Point(7) = {0.75, 0.75, 0.25};
Point(8) = {-0.75, 0.75, 0.25};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Line(5) = {5, 6};
Line(6) = {6, 7};
Line(7) = {7, 8};
Line(8) = {8, 5};
Line(9) = {1, 5};
Line(10) = {2, 6};
Line(11) = {3, 7};
Line(12) = {4, 8};
Curve Loop(1) = {1, 2, 3, 4};
Curve Loop(2) = {9, 5, -10, -1};
Curve Loop(3) = {10, 6, -11, -2};
Curve Loop(4) = {11, 7, -12, -3};
Curve Loop(5) = {12, 8, -9, -4};
Plane Surface(1) = {1};
Plane Surface(2) = {2};
Plane Surface(3) = {3};
Plane Surface(4) = {4};
Plane Surface(5) = {5};
Transfinite Curve{1:12} = 3;
Transfinite Surface{1:5};
Physical Surface("bottom") = {1};
Physical Surface("walls") = {2, 3, 4, 5};
