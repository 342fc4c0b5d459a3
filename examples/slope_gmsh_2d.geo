// The 2:1 slope of Griffiths & Lane (1999), Example 1, for examples/slope_gmsh_2d.toml:
// height H = 10 m above a foundation of depth H (depth factor 2), the crest at x = 20 m,
// the toe at x = 40 m. Two physical surfaces: the slope above the toe's level, the
// foundation below it. Mesh it with
//   gmsh examples/slope_gmsh_2d.geo -2 -format msh41 -o examples/slope_gmsh_2d.msh
h = 2.0;  // element size (m): the MPM grid, not this mesh, resolves the solution
Point(1) = {0, 0, 0, h};
Point(2) = {60, 0, 0, h};
Point(3) = {60, 10, 0, h};
Point(4) = {40, 10, 0, h};
Point(5) = {20, 20, 0, h};
Point(6) = {0, 20, 0, h};
Point(7) = {0, 10, 0, h};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 7};
Line(5) = {7, 1};
Line(6) = {4, 5};
Line(7) = {5, 6};
Line(8) = {6, 7};
Curve Loop(1) = {1, 2, 3, 4, 5};
Plane Surface(1) = {1};
Curve Loop(2) = {-4, 6, 7, 8};
Plane Surface(2) = {2};
Physical Surface("foundation") = {1};
Physical Surface("slope") = {2};
