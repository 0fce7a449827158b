// A rectangular block of granular material on a flat base: the test geometry of the
// gravity-loaded column with a closed-form stress field. Lengths in metres.
//
//   gmsh -2 block.geo -setnumber width_m 1 -setnumber height_m 1 -setnumber element_size_m 0.1
//
// Boundary tags: BoundaryID:1 base (y = 0), BoundaryID:4 side walls (x = -w/2, x = +w/2),
// BoundaryID:5 top (y = h, free).
DefineConstant[ width_m = 1, height_m = 1, element_size_m = 0.1 ];

Point(1) = {-width_m / 2, 0, 0, element_size_m};
Point(2) = { width_m / 2, 0, 0, element_size_m};
Point(3) = { width_m / 2, height_m, 0, element_size_m};
Point(4) = {-width_m / 2, height_m, 0, element_size_m};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};

Physical Curve("BoundaryID:1", 1) = {1};
Physical Curve("BoundaryID:4", 4) = {2, 4};
Physical Curve("BoundaryID:5", 5) = {3};
Physical Surface("MaterialID:0", 100) = {1};
