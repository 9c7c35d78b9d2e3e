#include "tactile_servo/slope_feedforward.hpp"
#include "tactile_servo/servo_schema.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace tactile {

ConfigResult SlopeFeedforward::configure(double window_m, int axis, const char* where) {
  window_ = 0.0;
  SlopeFeedforwardConfig c;
  c.axis = axis;
  c.window_m = window_m;
  const ConfigResult r = schema::checkRanges(slopeFeedforwardSchema(), c, where);
  if (!r) return r;
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
