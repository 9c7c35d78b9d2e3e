// Conventions of the whole project, written down once.
//
// UNITS. SI everywhere: metres, radians, newtons, newton-metres, seconds.
// Raw sensor counts are the only exception and are typed as uint16_t.
//
// FRAMES (named as in Kappassov, Corrales & Perdereau, RAS 123 (2020), Fig. 5):
//   {g}  global / robot base frame (the LWR's base).
//   {e}  end-effector (flange) frame of the LWR; {g}T{e} comes from forward
//        kinematics (or from FRI's measured Cartesian pose).
//   {s}  tactile sensing frame: origin at the geometric centre of the sensing
//        surface, x along the 14-taxel (long) side, y along the 6-taxel side,
//        z out of the surface (pointing at the touched object). {e}T{s} is a
//        fixed, configured mounting transform.
//   {c}  contact frame, located in {s} by the tactile features (Eq. 2, Eq. 4).
//   A transform written aTb maps coordinates in {b} to coordinates in {a}.
//
// TAXEL LAYOUT. A frame has `rows` x `cols` taxels stored row-major, row 0
// first. Taxel (row r, col c) has its centre in {s} at
//     x = (c - (cols-1)/2) * pitch,   y = (r - (rows-1)/2) * pitch,  z = 0.
// Default WTS0614: rows = 6, cols = 14, pitch = 3.4 mm. In code:
// tactile::SensorGeometry (sensor_geometry.hpp), x(c) and y(r).
//
// POSES. A pose is a position (m) and a unit quaternion (x, y, z, w).
// A twist/increment is ordered [vx vy vz wx wy wz] (translation first), as in
// the paper's feature and task vectors (Eq. 4, Eq. 9).
//
// TIME. Every core receives time (and dt) as an argument; no core reads a clock.
#pragma once

namespace tactile {

constexpr double kPi = 3.14159265358979323846;

}  // namespace tactile
