// example003.ref.off (3D, 7 leaves, 6 operators) as OpenSCAD, written by fuzzycsg convert.
// IoU 1.0000 against the mesh, Chamfer distance 0.167; settings and measures in report.json.
// Domain [-21.0526316, 21.0526316] x [-21.0526316, 21.0526316] x [-21.0526316, 21.0526316]; the model is not clipped to it.
$fn = 64;

difference() {
  union() {
    cube([30, 30, 30], center = true);
    cube([40, 15, 15], center = true);
    cube([15, 40, 15], center = true);
    cube([15, 15, 40], center = true);
  }
  translate([0, 0, -1]) cube([10, 10, 46], center = true);
  translate([0, -1, 0]) cube([10, 46, 10], center = true);
  translate([-1, 0, 0]) cube([46, 10, 10], center = true);
}
