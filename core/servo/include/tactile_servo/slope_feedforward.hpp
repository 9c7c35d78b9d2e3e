// The slope of the path the pad slides along, fed forward along z_s (beyond
// the paper).
//
// On a bar that rises or falls along the slide, holding the force asks the
// pad to move along z_s by the slope times the slide. The force PI alone
// carries that motion in its integral, so every change of the slide speed (a
// speed law's, a fixed gain's as the CoP_x error changes) and every change of
// the slope (a wave, a dip, a step) is a force disturbance: while the speed
// rises at a, the force error is about slope * a / K_I,z (0.4 N on a 7 %
// slope at 0.05 m/s^2 with K_I,z = 16 1/s^2 and C_z = 0.56 mm/N). The servo
// adds slope() times the slide's increment to the z_s increment instead, in
// the phases the program's slope_feedforward block lists.
//
// The slope is measured, never known: over each `window_m` of slide along the
// slide axis, the measured sensor origin's displacement along z_s over its
// displacement along that axis, both in {s} of the window's end (so the pad's
// pitch is accounted for), clamped to +-kMaxSlope. The window is short
// (0.5 mm: at 30 mm/s, 1-2 servo cycles) so that the slope follows a wave. The
// path also holds the force PI's own corrections (the penetration C_z f
// changing), which the slope then repeats for a window; subtracting C_z f
// removes them in a plant whose compliance is C_z exactly, but on the
// simulated pad the force's noise (0.13 N, 0.07 mm of C_z f per 0.5 mm
// window) made the family of bars worse (docs/design.md), so the slope is the
// path's. The servo resets it when the contact is lost or a phase begins:
// the slope 0, the next window afresh.
// Real-time: step() does not allocate, throw, log or block.
#pragma once

#include "tactile_types/config_result.hpp"

#include <kdl/frames.hpp>

namespace tactile {

class SlopeFeedforward {
 public:
  static constexpr double kMaxSlope = 1.0;  ///< 45 deg: steeper is no bar the pad slides along

  /// window_m in [0, 0.05] m (0: off, slope() stays 0); axis 0 (x_s) or 1
  /// (y_s). `where` prefixes the key in messages.
  ConfigResult configure(double window_m, int axis, const char* where = "slope_feedforward");
  /// The slope to 0 and the next window from the next pose (a new phase, a
  /// contact lost: the servo calls it).
  void reset();
  /// One cycle in contact: T_gs the measured sensor pose in {g}. Returns slope().
  double step(const KDL::Frame& T_gs);
  double slope() const { return slope_; }  ///< dz_s / d(slide), clamped

 private:
  double window_ = 0.0;
  int axis_ = 0;
  bool anchored_ = false;
  KDL::Vector anchor_;  ///< where the current window began, in {g}
  double slope_ = 0.0;
};

}  // namespace tactile
