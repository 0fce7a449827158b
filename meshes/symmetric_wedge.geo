// A symmetric pile cross-section: wedge.geo with one angle of repose for both flanks.
//
//   gmsh -2 symmetric_wedge.geo -setnumber height_m 0.33 -setnumber repose_angle_deg 28 -o pile.msh
//
// Boundary tags as in wedge.geo: BoundaryID:1 base, BoundaryID:2 left flank, BoundaryID:3 right.
DefineConstant[ repose_angle_deg = 28 ];
left_angle_deg = repose_angle_deg;
right_angle_deg = repose_angle_deg;
Include "wedge.geo";
