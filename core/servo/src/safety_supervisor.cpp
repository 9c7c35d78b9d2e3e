#include "tactile_servo/safety_supervisor.hpp"
#include "tactile_servo/servo_schema.hpp"

#include <algorithm>
#include <cmath>

#include "servo_config.hpp"

namespace tactile {

using servo_config::err;

ConfigResult SafetySupervisor::configure(const ServoParams& p) {
  configured_ = false;
  const SafetyParams& s = p.safety;
  const ConfigResult r = schema::checkRanges(safetySchema(), s, servo_config::where(p, "", "safety"));
  if (!r) return r;
  for (int i = 0; i < 3; ++i)
    if (!(s.workspace_min[i] < s.workspace_max[i]))
      return err(p, "", "safety.workspace.min", s.workspace_min[i], "must be < workspace.max on every axis");
  p_ = s;
  configured_ = true;
  reset();
  return ConfigResult::success();
}

void SafetySupervisor::reset() {
  ceiling_latched_ = false;
  ceiling_moved_ = 0.0;
  recovery_moved_ = 0.0;
  have_image_ = false;
  frozen_ = false;
}

bool SafetySupervisor::Image::operator==(const Image& o) const {
  return force == o.force && cop_x == o.cop_x && cop_y == o.cop_y && coc_x == o.coc_x && coc_y == o.coc_y &&
         lambda1 == o.lambda1 && lambda2 == o.lambda2 && max_taxel == o.max_taxel && area == o.area;
}

bool SafetySupervisor::frozenImage(const ContactFeatures& f, const KDL::Vector& flange, double now) {
  if (p_.frozen_image_travel <= 0.0) return false;
  if (f.contact == ContactType::None || f.area == 0 || !usable(f.status)) {  // no image: zeros repeat legitimately
    have_image_ = frozen_ = false;
    return false;
  }
  if (have_image_ && f.seq == image_seq_) return frozen_;  // no new frame this cycle
  image_seq_ = f.seq;
  const Image img{f.force, f.cop_x, f.cop_y, f.coc_x, f.coc_y, f.lambda1, f.lambda2, f.max_taxel, f.area};
  if (!have_image_ || !(img == image_)) {  // a changed image: the stream is live
    image_ = img;
    image_at_ = flange;
    image_since_ = now;
    have_image_ = true;
    frozen_ = false;
    return false;
  }
  if (!frozen_ && now - image_since_ >= p_.frozen_image_s && (flange - image_at_).Norm() > p_.frozen_image_travel)
    frozen_ = true;
  return frozen_;
}

bool SafetySupervisor::featuresFinite(const ContactFeatures& f) {
  const double v[] = {f.time_s, f.cop_x, f.cop_y, f.coc_x, f.coc_y, f.dzmp_x, f.dzmp_y, f.alpha_z, f.force, f.d_z};
  for (double x : v)
    if (!std::isfinite(x)) return false;
  return true;
}

bool SafetySupervisor::forceCeiling(const ContactFeatures& f, bool finite, double dt, double& retreat) {
  retreat = 0.0;
  if (!ceiling_latched_ && finite && usable(f.status) && f.force > p_.force_ceiling) {
    ceiling_latched_ = true;
    ceiling_moved_ = 0.0;
  }
  if (!ceiling_latched_) return false;
  const double d = std::min(maxTransStep(dt), p_.ceiling_retreat - ceiling_moved_);
  if (d > 0.0) {
    ceiling_moved_ += d;
    retreat = d;
  }
  return true;
}

bool SafetySupervisor::stale(const ContactFeatures& f, double now) const {
  return !usable(f.status) || now - f.time_s > p_.stale_timeout || f.time_s - now > p_.stale_timeout;
}

double SafetySupervisor::contactLoss(double dt) {
  switch (p_.contact_loss) {
    case ContactLossMode::Hold: return 0.0;
    case ContactLossMode::Backoff: {
      const double d = std::min(maxTransStep(dt), p_.backoff_distance - recovery_moved_);
      if (d <= 0.0) return 0.0;
      recovery_moved_ += d;
      return -d;
    }
    case ContactLossMode::Search: {
      const double d = std::min(std::min(maxTransStep(dt), p_.search_speed * dt), p_.search_max_distance - recovery_moved_);
      if (d <= 0.0) return 0.0;
      recovery_moved_ += d;
      return d;
    }
  }
  return 0.0;
}

// Speed limits over the cycle: translation and rotation norms of the
// increment at most speed * dt, scaled (direction kept).
bool SafetySupervisor::limitStep(Vec6& u, double dt) const {
  bool limited = false;
  const double max_t = maxTransStep(dt), max_r = maxRotStep(dt);
  const double nt = u.head<3>().norm();
  if (nt > max_t) {
    u.head<3>() *= max_t / nt;
    limited = true;
  }
  const double nr = u.tail<3>().norm();
  if (nr > max_r) {
    u.tail<3>() *= max_r / nr;
    limited = true;
  }
  return limited;
}

// Workspace box on the flange position. A start pose already outside the box
// widens it to include that pose: an increment may only move back towards
// the box, never jump onto it.
bool SafetySupervisor::clipWorkspace(const KDL::Vector& from, KDL::Frame& T_ge) const {
  bool clipped = false;
  for (int i = 0; i < 3; ++i) {
    const double lo = std::min(p_.workspace_min[static_cast<std::size_t>(i)], from(i));
    const double hi = std::max(p_.workspace_max[static_cast<std::size_t>(i)], from(i));
    if (T_ge.p(i) < lo) { T_ge.p(i) = lo; clipped = true; }
    if (T_ge.p(i) > hi) { T_ge.p(i) = hi; clipped = true; }
  }
  return clipped;
}

}  // namespace tactile
