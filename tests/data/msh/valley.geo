// A V-shaped valley floor as a bare line mesh (2D, z = 0), for the surface
// reader tests: from (1, 0.5) down to (0.5, 0), along y = 0 to (-0.5, 0) and
// up to (-1, 0.5). The curves run from right to left, so the normal
// (t_y, -t_x) of every segment points up (+y side). 5 nodes, 4 segments.
// Regenerate: gmsh -1 -format msh41 valley.geo -o valley.msh
Point(1) = {1, 0.5, 0};
Point(2) = {0.5, 0, 0};
Point(3) = {-0.5, 0, 0};
Point(4) = {-1, 0.5, 0};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Transfinite Curve{1, 3} = 2;
Transfinite Curve{2} = 3;
Physical Curve("floor") = {2};
Physical Curve("slopes") = {1, 3};
