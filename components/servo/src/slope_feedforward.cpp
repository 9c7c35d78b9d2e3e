#include "tactile_servo/slope_feedforward.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace tactile {

ConfigResult SlopeFeedforward::configure(double window_m, int axis, const char* where) {
  window_ = 0.0;
  if (!(std::isfinite(window_m) && window_m >= 0.0 && window_m <= 0.05))
    return rangeError(std::string(where) + ".window_m", window_m, "must be in [0, 0.05] m (0: off)");
  if (axis != 0 && axis != 1) return ConfigResult::failure(std::string(where) + ".axis: must be x or y");
  window_ = window_m;
  axis_ = axis;
  reset();
  return ConfigResult::success();
}

void SlopeFeedforward::reset() {
  anchored_ = false;
  slope_ = 0.0;
}

double SlopeFeedforward::step(const KDL::Frame& T_gs) {
  if (window_ <= 0.0) return slope_;  // off: 0
  if (!anchored_) {
    anchor_ = T_gs.p;
    anchored_ = true;
    return slope_;
  }
  const KDL::Vector d = T_gs.M.Inverse(T_gs.p - anchor_);  // in {s} of now
  const double along = axis_ == 1 ? d.y() : d.x();
  if (std::fabs(along) >= window_) {
    const double s = d.z() / along;
    if (std::isfinite(s)) slope_ = std::clamp(s, -kMaxSlope, kMaxSlope);
    anchor_ = T_gs.p;
  }
  return slope_;
}

}  // namespace tactile
