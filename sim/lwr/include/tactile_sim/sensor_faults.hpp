// Fault schedule of the SIMULATED WTS0614 (tactile::WtsSimComponent, sim
// only; never in the real reader): one fault of the sensor link, injected
// while a deployment runs, to test how the loop reacts at full speed
// (tests/rtt/faults). Off by default (kind None: every acquisition is
// delivered, nothing else is done).
//
//   stale       the acquisitions in [start, start + duration) are not
//               delivered: the reader's last frame stays the newest (the WTS
//               stops sending for `duration` s)
//   disconnect  the same window, the link reported down: `link()` is
//               Disconnected during it and Reconnected at the first frame
//               after it (the names of tactile::WtsComponent's read_status)
//   nan         the first acquisition at or after `start` is replaced by a
//               calibrated frame with a NaN taxel (raw 12-bit counts cannot
//               carry a NaN: it can only reach the features through their
//               calibrated `frame` input)
//   saturated   the first acquisition at or after `start` has every taxel at
//               full scale
//
// RTT-free; action() does not allocate, throw or read a clock (time passed in).
#pragma once

#include <cmath>
#include <cstdint>
#include <string>

#include <limits>

#include "tactile_types/config_result.hpp"
#include "tactile_types/types.hpp"

namespace tactile {
namespace sim {

enum class SensorFault : uint8_t { None = 0, Stale = 1, Disconnect = 2, Nan = 3, Saturated = 4 };

inline const char* toString(SensorFault f) {
  switch (f) {
    case SensorFault::None: return "none";
    case SensorFault::Stale: return "stale";
    case SensorFault::Disconnect: return "disconnect";
    case SensorFault::Nan: return "nan";
    case SensorFault::Saturated: return "saturated";
  }
  return "?";
}

/// What the simulated sensor does with one acquisition.
enum class FaultAction : uint8_t { Deliver = 0, Withhold = 1, NanFrame = 2, Saturate = 3 };

/// The simulated link as tactile::WtsComponent names its read_status.
enum class SensorLink : uint8_t { NewFrame = 0, Disconnected = 5, Reconnected = 4 };

inline const char* toString(SensorLink l) {
  switch (l) {
    case SensorLink::NewFrame: return "NewFrame";
    case SensorLink::Disconnected: return "Disconnected";
    case SensorLink::Reconnected: return "Reconnected";
  }
  return "?";
}

class SensorFaultSchedule {
 public:
  /// `kind`: '' or none | stale | disconnect | nan | saturated; `start` >= 0
  /// (s, simulated time); `duration` in (0, 60] s for stale and disconnect.
  ConfigResult configure(const std::string& kind, double start, double duration) {
    SensorFault k;
    if (kind.empty() || kind == "none") k = SensorFault::None;
    else if (kind == "stale") k = SensorFault::Stale;
    else if (kind == "disconnect") k = SensorFault::Disconnect;
    else if (kind == "nan") k = SensorFault::Nan;
    else if (kind == "saturated") k = SensorFault::Saturated;
    else return ConfigResult::failure("fault = '" + kind + "': must be '' (none), stale, disconnect, nan or saturated");
    if (k != SensorFault::None && !(std::isfinite(start) && start >= 0.0))
      return rangeError("fault_start", start, "must be >= 0 s (simulated time)");
    if ((k == SensorFault::Stale || k == SensorFault::Disconnect) && !(duration > 0.0 && duration <= 60.0))
      return rangeError("fault_duration", duration, "must be in (0, 60] s for stale and disconnect");
    kind_ = k;
    start_ = start;
    duration_ = duration;
    reset();
    return ConfigResult::success();
  }

  /// Start of a run: the fault is armed again.
  void reset() {
    fired_ = false;
    link_ = SensorLink::NewFrame;
  }

  /// The action for an acquisition at simulated time `t` (s).
  FaultAction action(double t) {
    switch (kind_) {
      case SensorFault::None: return FaultAction::Deliver;
      case SensorFault::Stale:
      case SensorFault::Disconnect: {
        const bool inside = t >= start_ && t < start_ + duration_;
        if (kind_ == SensorFault::Disconnect)
          link_ = inside ? SensorLink::Disconnected
                         : link_ == SensorLink::Disconnected ? SensorLink::Reconnected : SensorLink::NewFrame;
        if (inside) fired_ = true;
        return inside ? FaultAction::Withhold : FaultAction::Deliver;
      }
      case SensorFault::Nan:
      case SensorFault::Saturated:
        if (fired_ || t < start_) return FaultAction::Deliver;
        fired_ = true;
        return kind_ == SensorFault::Nan ? FaultAction::NanFrame : FaultAction::Saturate;
    }
    return FaultAction::Deliver;
  }

  SensorFault kind() const { return kind_; }
  bool fired() const { return fired_; }
  SensorLink link() const { return link_; }

 private:
  SensorFault kind_ = SensorFault::None;
  double start_ = 0.0, duration_ = 0.0;
  bool fired_ = false;
  SensorLink link_ = SensorLink::NewFrame;
};

/// The saturated fault's frame: every taxel at `full_scale` counts.
inline void saturateFrame(RawTactileFrame& raw, uint16_t full_scale) {
  const int n = static_cast<int>(raw.rows) * static_cast<int>(raw.cols);
  for (int i = 0; i < n; ++i) raw.counts[static_cast<std::size_t>(i)] = full_scale;
}

/// The nan fault's frame: the forces of `forces` (N) with the middle taxel NaN.
inline void nanFrame(const TactileFrame& forces, double t, uint32_t seq, TactileFrame& out) {
  out.time_s = t;
  out.seq = seq;
  out.force = forces.force;
  out.force[static_cast<std::size_t>(out.size() / 2)] = std::numeric_limits<double>::quiet_NaN();
}

}  // namespace sim
}  // namespace tactile
