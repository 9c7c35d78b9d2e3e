// Geometry of a tactile array in the sensing frame {s}: the TAXEL LAYOUT of
// conventions.hpp, written once as code.
//
//   rows x cols taxels, row-major, row 0 first; a square pitch x pitch cell per
//   taxel; the array centred on the origin of {s}, x along the cols, y along
//   the rows:
//     taxel (r, c) centre:  x = (c - (cols-1)/2) * pitch,  y = (r - (rows-1)/2) * pitch,  z = 0.
//   Default WTS0614: 6 x 14 taxels, 3.4 mm pitch.
//
// The position of a pixel coordinate (a fractional column or row, e.g. a
// moment ratio M10/M00 in taxel units) follows the same line, so x(col) and
// y(row) take doubles.
#pragma once

#include <limits>

#include "tactile_types/types.hpp"

namespace tactile {

struct SensorGeometry {
  int rows = kDefaultRows;
  int cols = kDefaultCols;
  double pitch = kDefaultPitch;  ///< m, centre-to-centre distance of neighbouring taxels

  /// x in {s} (m) of column `col` (a taxel centre for an integer col).
  constexpr double x(double col) const { return (col - (cols - 1) / 2.0) * pitch; }
  /// y in {s} (m) of row `row` (a taxel centre for an integer row).
  constexpr double y(double row) const { return (row - (rows - 1) / 2.0) * pitch; }

  /// x of the j-th of k equally spaced midpoint samples across taxel column
  /// `col` (j = 0..k-1; the samples tile the cell [x(col) - pitch/2, x(col) + pitch/2]).
  constexpr double sampleX(int col, int j, int k) const { return x(col) - 0.5 * pitch + (j + 0.5) * (pitch / k); }
  /// y of the i-th of k midpoint samples across taxel row `row`.
  constexpr double sampleY(int row, int i, int k) const { return y(row) - 0.5 * pitch + (i + 0.5) * (pitch / k); }

  /// Extent of the sensing area (m): along x_s (cols * pitch) and y_s (rows * pitch).
  constexpr double width() const { return cols * pitch; }
  constexpr double height() const { return rows * pitch; }

  constexpr int taxels() const { return rows * cols; }
  /// Row-major index of taxel (r, c) in a frame.
  constexpr int index(int r, int c) const { return r * cols + c; }
  /// Fits the fixed-size frames of types.hpp, with a positive finite pitch.
  constexpr bool valid() const {
    return rows >= 1 && rows <= kMaxRows && cols >= 1 && cols <= kMaxCols && pitch > 0.0 &&
           pitch <= std::numeric_limits<double>::max();
  }
};

}  // namespace tactile
