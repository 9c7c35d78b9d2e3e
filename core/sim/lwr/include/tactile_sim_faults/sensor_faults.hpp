// Fault schedule of the simulated sensors: the WTS0614 pad (its electronics
// and its frame stream) and the arm's estimated wrench (estExtTcpFT), each
// fault from a start time in simulated time, for a duration or to the end of
// the run. One schedule type for every host of the simulated sensors: the
// headless runner and lab_sim (through tactile::sim::TaxelResponse and
// tactile::sim::EstimatedWrench), tactile::WtsSimComponent and the simulated
// arm component (the same two classes), configured from a scene's `faults:`
// list (tactile_sim_runner/scene.hpp, docs/formats.md; tactile_sim_faults/sensor_faults_io.hpp
// reads an entry) or, for the RTT sensor's `fault` properties, one fault by
// name; the bench tool wts_sim plays the counts' and the stream's faults in
// its device time (`--fault`). Off by default: no fault, nothing is done and
// every acquisition is delivered.
//
// Pad faults (taxel indices from 0 in {s}; `rows: [r0, r1]`, `cols: [c0, c1]`
// inclusive, default the whole pad):
//   stuck        the region reads a constant load from `start_s`: `counts` per
//                taxel, or `force_n` N over the region (force_n / taxels on
//                each, converted by the reader's calibration); no noise; the
//                device's firing threshold still applies
//   dead         the region reads 0 from `start_s` (a broken trace)
//   tare_creep   every taxel's zero drifts by `counts_per_min` counts per
//                minute from `start_s` (added before noise and threshold: an
//                unloaded taxel fires once its zero passes the threshold)
//   calibration  the reader's calibration is `scale` x the true response from
//                `start_s`: the reader's force = scale x the true force
//                (0.5: it reads half; 2: double)
//   saturated    the first acquisition at or after `start_s` has every taxel
//                at full scale
//   stale        no frame in [start_s, start_s + duration_s): the stream stalls
//                and the reader's last frame stays the newest
//   repeat       in the same window every frame carries the counts of the last
//                frame delivered before it: the same content re-sent with a
//                new sequence number and time stamp
//   disconnect   the window of stale with the link reported down: link() is
//                Disconnected during it, Reconnected at the first frame after
//                it (tactile::WtsComponent's read_status names); lab_sim
//                unplugs its PTY device for the window
//   nan          the RTT sensor only: the first acquisition at or after
//                `start_s` goes out as a calibrated frame with a NaN taxel
//                (raw counts cannot carry a NaN)
// Wrench faults (the estimated wrench's force part in {g} at the flange):
//   wrench_bias  + `bias_n` [3] N ({g}) from `start_s`
//   wrench_drift + `drift_n_per_min` [3] N/min x (t - start_s) ({g})
//   wrench_frame the wrench reported in the wrong axes: `axes: flange` ({e})
//                or `sensor` ({s}) components given as {g}'s
//   wrench_sign  the wrench reported with the wrong sign (force and moment)
//   pad_mass     the load model's pad mass off by `mass_kg` (true - modelled):
//                the unexplained gravity mass_kg * g along -z_g, fixed in {g}
//                (so it turns in the flange's and sensor's axes as the arm
//                reorients), its moment about the flange from the pad's
//                centre of mass (half-way to the sensing surface)
// The wrench's axes and sign apply last, to the whole reported wrench.
//
// Per-cycle calls (loadScale, zeroOffsetCounts, applyCounts, stream,
// wrenchAt) do not allocate, throw or read a clock (time passed in).
// configure() validates: errors name the fault's index and key and the
// valid range ("faults[1].rows = [2, 9]: ...").
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "tactile_types/config_result.hpp"
#include "tactile_types/types.hpp"

namespace tactile {
namespace sim {

enum class SensorFault : uint8_t {
  None = 0,
  Stale = 1,
  Disconnect = 2,
  Nan = 3,
  Saturated = 4,
  Stuck = 5,
  Dead = 6,
  TareCreep = 7,
  Repeat = 8,
  Calibration = 9,
  WrenchBias = 10,
  WrenchDrift = 11,
  WrenchFrame = 12,
  WrenchSign = 13,
  PadMass = 14
};

const char* toString(SensorFault f);
/// '' or none | stale | disconnect | nan | saturated | stuck | dead | tare_creep | repeat |
/// calibration | wrench_bias | wrench_drift | wrench_frame | wrench_sign | pad_mass.
bool parseSensorFault(const std::string& s, SensorFault& out);
/// The names parseSensorFault() takes (for messages).
extern const char* const kSensorFaultNames;
/// A fault of the estimated wrench (else of the pad).
inline bool wrenchFault(SensorFault f) {
  return f == SensorFault::WrenchBias || f == SensorFault::WrenchDrift || f == SensorFault::WrenchFrame ||
         f == SensorFault::WrenchSign || f == SensorFault::PadMass;
}

/// What the simulated sensor does with one acquisition.
enum class FaultAction : uint8_t { Deliver = 0, Withhold = 1, NanFrame = 2, Saturate = 3, Repeat = 4 };

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

/// The axes the estimated wrench is reported in (wrench_frame).
enum class WrenchAxes : uint8_t { Base = 0, Flange = 1, Sensor = 2 };

/// One scheduled fault (the scene's `faults:` entry). Units SI; counts are
/// the WTS's 12-bit counts.
struct FaultSpec {
  SensorFault kind = SensorFault::None;
  double start_s = 0.0;     ///< s, simulated time, >= 0
  double duration_s = 0.0;  ///< s; 0: to the end of the run (stale, repeat, disconnect: (0, 60] required)
  int row0 = 0, row1 = -1;  ///< stuck, dead: rows [row0, row1] (-1: the last)
  int col0 = 0, col1 = -1;  ///< stuck, dead: cols [col0, col1] (-1: the last)
  double counts = -1.0;     ///< stuck: counts per taxel, [0, full scale] (or force_n)
  double force_n = -1.0;    ///< stuck: N over the region, [0, 1000] (or counts)
  double counts_per_min = 0.0;  ///< tare_creep: [-4095, 4095] counts/min
  double scale = 1.0;           ///< calibration: reader / true, [0.1, 10]
  std::array<double, 3> bias_n{0.0, 0.0, 0.0};           ///< wrench_bias: N, {g}, each [-100, 100]
  std::array<double, 3> drift_n_per_min{0.0, 0.0, 0.0};  ///< wrench_drift: N/min, {g}, each [-100, 100]
  WrenchAxes axes = WrenchAxes::Flange;                  ///< wrench_frame: flange or sensor
  double mass_kg = 0.0;                                  ///< pad_mass: true - modelled (kg), [-5, 5]

  /// Active at t: t >= start_s and (no duration or t < start_s + duration_s).
  bool active(double t) const { return t >= start_s && (duration_s <= 0.0 || t < start_s + duration_s); }
};

/// The wrench faults active at one time, combined (EstimatedWrench applies them).
struct WrenchFaultTerms {
  std::array<double, 3> offset_n{0.0, 0.0, 0.0};  ///< bias + drift, N, {g}
  double mass_kg = 0.0;                           ///< pad_mass
  WrenchAxes axes = WrenchAxes::Base;
  bool negate = false;
  bool any = false;
};

/// Standard gravity (m/s^2), the pad_mass fault's.
constexpr double kGravity = 9.80665;

class SensorFaultSchedule {
 public:
  static constexpr int kMaxFaults = 8;

  /// The faults (at most kMaxFaults) on a pad of rows x cols taxels with
  /// this full scale. Errors name "faults[i].key", the value and the range.
  ConfigResult configure(const std::vector<FaultSpec>& faults, int rows = kDefaultRows, int cols = kDefaultCols,
                         uint16_t full_scale = 4095);
  /// One fault by name (tactile::WtsSimComponent's `fault`, `fault_start`,
  /// `fault_duration` properties): '' (none) | stale | disconnect | nan |
  /// saturated; errors name those properties.
  ConfigResult configure(const std::string& kind, double start, double duration);
  /// Appends one fault to the configured ones (validated as by configure()).
  ConfigResult add(const FaultSpec& f);
  /// The stuck faults given in N: each taxel's counts from `countsOf(i,
  /// force)` (the noise-free inverse of the reader's calibration). Call after
  /// configure(); not on the per-cycle path.
  template <typename CountsOf>
  void resolveForces(CountsOf countsOf);

  /// Start of a run: every fault armed again, the link up, no held frame.
  void reset();

  int count() const { return n_; }
  const FaultSpec& spec(int i) const { return specs_[static_cast<std::size_t>(i)]; }
  bool any() const { return n_ > 0; }
  /// Faults of the sensor's electronics (calibration, tare_creep): respond() asks loadScale() and zeroOffsetCounts().
  bool electronics() const { return electronics_; }
  /// Faults of the counts (stuck, dead, saturated): applyCounts().
  bool counts() const { return counts_on_; }
  /// Faults of the frame stream (stale, repeat, disconnect, nan): stream().
  bool streams() const { return streams_; }
  /// Faults of the estimated wrench: wrenchAt().
  bool wrench() const { return wrench_; }

  /// The product of the active calibration faults' scales at t (1 without).
  double loadScale(double t);
  /// The zero's offset at t (counts): the active tare_creep faults' drift.
  double zeroOffsetCounts(double t);
  /// Stuck, dead and saturated on a frame acquired at t. A stuck count below
  /// the taxel's firing threshold (threshold_counts[i]) reads 0.
  void applyCounts(double t, const double* threshold_counts, RawTactileFrame& raw);
  /// The frame stream at the frame's acquisition time raw.time_s: Withhold
  /// (stale, disconnect), Repeat (its counts replaced by the held frame's),
  /// NanFrame (the nan fault's frame: delivered, the RTT sensor replaces it)
  /// or Deliver. Updates link() and lastAction().
  FaultAction stream(RawTactileFrame& raw);
  /// The wrench faults active at t.
  void wrenchAt(double t, WrenchFaultTerms& out) const;

  /// The kind of the first fault (None without one).
  SensorFault kind() const { return n_ > 0 ? specs_[0].kind : SensorFault::None; }
  /// Some fault has acted (a window entered, a one-shot frame hit, a
  /// persisting fault applied) since reset().
  bool fired() const { return fired_; }
  /// One-shot faults (saturated, nan) that have hit their frame since reset().
  int shots() const { return shots_; }
  SensorLink link() const { return link_; }
  FaultAction lastAction() const { return last_action_; }
  /// A disconnect fault's window holds at t (the link is down): lab_sim unplugs its device.
  bool linkDown(double t) const;
  /// A stale fault's window holds at t (the device sends nothing): lab_sim holds its device.
  bool stalled(double t) const;

 private:
  ConfigResult check(const FaultSpec& f, int index) const;
  void classify();

  std::array<FaultSpec, kMaxFaults> specs_{};
  std::array<std::array<uint16_t, kMaxTaxels>, kMaxFaults> stuck_{};  ///< stuck counts per taxel, per fault
  std::array<uint8_t, kMaxFaults> shot_{};  ///< one-shot faults that hit their frame
  int shots_ = 0;
  int n_ = 0;
  int rows_ = kDefaultRows, cols_ = kDefaultCols;
  uint16_t full_scale_ = 4095;
  bool electronics_ = false, counts_on_ = false, streams_ = false, wrench_ = false, repeat_ = false;
  bool fired_ = false;
  SensorLink link_ = SensorLink::NewFrame;
  FaultAction last_action_ = FaultAction::Deliver;
  bool have_held_ = false;
  std::array<uint16_t, kMaxTaxels> held_{};  ///< the repeat fault's frame
};

template <typename CountsOf>
void SensorFaultSchedule::resolveForces(CountsOf countsOf) {
  for (int k = 0; k < n_; ++k) {
    const FaultSpec& f = specs_[static_cast<std::size_t>(k)];
    if (f.kind != SensorFault::Stuck || f.counts >= 0.0) continue;  // counts: set by configure()
    const int taxels = (f.row1 - f.row0 + 1) * (f.col1 - f.col0 + 1);
    for (int r = f.row0; r <= f.row1; ++r)
      for (int c = f.col0; c <= f.col1; ++c) {
        const int i = r * cols_ + c;
        double n = std::round(countsOf(i, f.force_n / taxels));
        n = n < 0.0 ? 0.0 : (n > full_scale_ ? full_scale_ : n);
        stuck_[static_cast<std::size_t>(k)][static_cast<std::size_t>(i)] = static_cast<uint16_t>(n);
      }
  }
}

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
