// A 2D pile cross-section: a triangular wedge on a flat base, apex on the axis x = 0.
// Symmetric when left_angle_deg == right_angle_deg, asymmetric otherwise.
// Lengths in metres, angles in degrees from the horizontal.
//
//   gmsh -2 wedge.geo -setnumber height_m 0.33 -setnumber left_angle_deg 28 \
//        -setnumber right_angle_deg 28 -setnumber element_size_m 0.01 -o pile.msh
//
// Boundary tags follow pilelab's convention (named, so deal.II's gmsh reader keeps them):
//   BoundaryID:1 base (y = 0), BoundaryID:2 left flank, BoundaryID:3 right flank.
// The axis from apex to base is embedded, so element edges follow it: the FPA stress field
// has a kink there and converges much faster on a mesh that resolves the kink.
DefineConstant[ height_m = 0.33, left_angle_deg = 28, right_angle_deg = 28,
                element_size_m = 0.02, axis_element_size_m = element_size_m ];

x_left  = -height_m / Tan(left_angle_deg * Pi / 180);
x_right =  height_m / Tan(right_angle_deg * Pi / 180);

Point(1) = {x_left, 0, 0, element_size_m};
Point(2) = {0, 0, 0, axis_element_size_m};
Point(3) = {x_right, 0, 0, element_size_m};
Point(4) = {0, height_m, 0, axis_element_size_m};

Line(1) = {1, 2};   // base, left half
Line(2) = {2, 3};   // base, right half
Line(3) = {3, 4};   // right flank
Line(4) = {4, 1};   // left flank
Line(5) = {2, 4};   // axis (embedded)

Curve Loop(1) = {1, 5, 4};
Curve Loop(2) = {2, 3, -5};
Plane Surface(1) = {1};
Plane Surface(2) = {2};

Physical Curve("BoundaryID:1", 1) = {1, 2};
Physical Curve("BoundaryID:2", 2) = {4};
Physical Curve("BoundaryID:3", 3) = {3};
Physical Surface("MaterialID:0", 100) = {1, 2};
