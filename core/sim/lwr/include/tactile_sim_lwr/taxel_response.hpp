// The simulated WTS0614's electronics: true taxel forces (N) -> raw 12-bit
// counts, by inverting the calibration the real sensor is read with (App. A,
// Fig. A.15: the per-taxel polynomial f(n) = c0 + c1 n + c2 n^2 + c3 n^3 of
// params/sensors/wts0614.yaml's `calibration:` block, border and
// per-taxel coefficients included). So tactile::Calibration configured from
// the same file maps the counts back to the forces (up to noise and
// quantisation), exactly as on the robot.
//
// Per taxel: n = p^-1(f) (Newton, monotone: c1 > 0, c2, c3 >= 0), Gaussian
// noise (noise_counts, 1 sigma, seeded), rounding (12-bit quantisation),
// clamping to [0, full_scale] (saturation), and 0 below the device's firing
// threshold (counts of `threshold` N). A taxel more than 10 sigma below its
// threshold reads 0 without a noise draw (deterministic for a seed).
//
// SENSOR EFFECTS (SensorEffects, the scene's `effects:` map; each off by
// default, and off costs nothing per frame: the path above is unchanged).
// Per acquisition, in this order (core/sim/lwr/README.md, "Sensor effects"):
//  1. crosstalk c: load spreading in the rubber; each taxel passes c of its
//     load to each existing 4-neighbour (total conserved).
//  2. hysteresis h: rate-independent play on the layer's load x, relative
//     band: y = clamp(y_prev, (1 - h) x, (1 + h) x). Loading reads (1 - h) x,
//     unloading (1 + h) x, the signal holds after a reversal until it meets
//     the other bound; the loop's width at load x is 2 h x.
//  3. creep (fraction a, tau_s): first-order viscoelastic creep of the signal,
//     s = y + z, dz/dt = (a y - z) / tau, integrated exactly for y held
//     between acquisitions: under a constant load s -> (1 + a) y with time
//     constant tau.
//  4. dead taxels: read 0.
//  5. calibration error e_i (seeded, relative, 1 sigma): the sensor's true
//     response is (1 + e_i) times the reader's calibration polynomial, so
//     n = p_i^-1(s / (1 + e_i)) and the reader gets s / (1 + e_i).
//  6. gain spread g_i (seeded, relative, 1 sigma): the cell's sensitivity,
//     counts n -> g_i n (before noise; the firing threshold stays in counts).
//  7. noise (device_noise: the WTS's level, kDeviceNoiseZ below), rounding,
//     saturation, threshold as above.
//  8. transfer delay d: the frame sampled at t reaches the reader at t + d
//     (serial transfer): acquire() queues it in a ring allocated by
//     configure(), deliver(now) hands over the frames whose transfer ended.
// FAULTS (TaxelResponseParams::faults, the scene's `faults:` list; the
// schedule of tactile_sim_faults/sensor_faults.hpp, none by default, nothing done
// without one): `calibration` scales the load after 3 (the reader's force =
// scale x the true force), `tare_creep` adds its zero's drift to the counts
// before 7's noise and threshold, `stuck`, `dead` and `saturated` overwrite
// the counts after 7, and the stream's faults (`stale`, `disconnect`,
// `repeat`, `nan`) act on each frame as it reaches the reader, at its
// acquisition time.
// The seeded per-taxel draws (gains, calibration errors, dead positions) use
// their own generator (seed-derived), so turning them on does not change the
// noise sequence.
//
// RTT-free; respond(), acquire() and deliver() do not allocate or throw.
#pragma once

#include <array>
#include <cstdint>
#include <random>
#include <vector>

#include "tactile_features/calibration.hpp"
#include "tactile_sim_faults/sensor_faults.hpp"
#include "tactile_types/config_result.hpp"
#include "tactile_types/types.hpp"

namespace tactile {
namespace sim {

/// The sensor's effects (the scene's `effects:` keys of the same names). All
/// off by default. Ranges are checked by TaxelResponse::configure().
struct SensorEffects {
  double wts_transfer_delay_s = 0.0;  ///< s, [0, 1]: frame reaches the reader this long after its acquisition
  double gain_spread = 0.0;           ///< 1 sigma relative per-taxel sensitivity spread, [0, 0.5] (gains clamped >= 0.05)
  int dead_taxels = 0;                ///< number of dead taxels at seeded positions, [0, rows*cols]
  std::vector<std::array<int, 2>> dead_list;  ///< or explicit [row, col] (used when not empty)
  double calibration_error = 0.0;     ///< 1 sigma relative error of the reader's calibration, [0, 0.5] (clamped |e| <= 0.9)
  double crosstalk = 0.0;             ///< fraction of a taxel's load to each 4-neighbour, [0, 0.25]
  double creep_fraction = 0.0;        ///< creep: final extra fraction of the signal, [0, 1]
  double creep_tau_s = 1.0;           ///< creep time constant (s), (0, 1000]
  double hysteresis = 0.0;            ///< relative half-width h of the loading/unloading band, [0, 0.5]
  bool device_noise = false;          ///< noise_counts := deviceNoiseCounts() (the WTS's level)
  double max_frame_rate_hz = 1000.0;  ///< sizes the transfer ring (frames in flight), (0, 1e5]

  bool any() const {
    return wts_transfer_delay_s > 0.0 || gain_spread > 0.0 || dead_taxels > 0 || !dead_list.empty() ||
           calibration_error > 0.0 || crosstalk > 0.0 || creep_fraction > 0.0 || hysteresis > 0.0 || device_noise;
  }
};

struct TaxelResponseParams {
  CalibrationParams calibration;  ///< the sensor's calibration (the file's `calibration:` block)
  double noise_counts = 6.0;      ///< 1 sigma (counts), [0, 1000]
  double threshold = 0.2;         ///< N: firing threshold, >= 0
  uint64_t seed = 1;              ///< noise seed
  SensorEffects effects;          ///< all off by default
  std::vector<FaultSpec> faults;  ///< scheduled faults (sensor_faults.hpp); the wrench's are ignored here
};

/// The WTS's noise level used by `device_noise`: App. A gives no noise figure,
/// so it is bounded by the one it does imply, the firing threshold: the largest
/// 1-sigma noise for which an unloaded taxel fires at most once a minute over
/// the 84 taxels at 140 Hz, i.e. threshold counts / z with
/// z = Phi^-1(1 - 1 / (84 * 140 * 60)) = kDeviceNoiseZ, on the most sensitive
/// taxel's threshold (the border's). An upper bound, not a measurement.
constexpr double kDeviceNoiseZ = 4.68;

class TaxelResponse {
 public:
  /// Validates (errors name the key and the range) and tabulates thresholds.
  ConfigResult configure(const TaxelResponseParams& params);
  const TaxelResponseParams& params() const { return params_; }

  /// Noise-free inverse of taxel i's calibration: force (N) -> counts (real, >= 0).
  double countsFor(int i, double force) const;
  /// Taxel i's calibration polynomial at `counts` (N).
  double forceFor(int i, double counts) const;

  /// Forces (the frame's own rows x cols must match the calibration) -> raw
  /// frame stamped `t` (the electronics, effects 1-7, no transfer). Returns the
  /// largest count. Allocation-free. `t` must not decrease between calls (creep).
  int respond(const TactileFrame& forces, double t, RawTactileFrame& raw);

  /// The acquisition at `t`: respond(). Without a transfer delay the frame is
  /// written to `raw` and true returned; with one it is queued (raw untouched,
  /// false) and comes out of deliver(). A full ring drops its oldest frame
  /// (overruns()). Allocation-free.
  bool acquire(const TactileFrame& forces, double t, RawTactileFrame& raw);
  /// The frames whose transfer has ended by `now` (acquisition time + delay
  /// <= now, to 1e-9 s) leave the ring; the newest of them is written to `raw`
  /// (its time_s stays the acquisition time). Returns true if one arrived.
  /// Always false without a delay. Allocation-free.
  bool deliver(double now, RawTactileFrame& raw);
  bool delayed() const { return delay_ > 0.0; }
  double transferDelay() const { return delay_; }
  long overruns() const { return overruns_; }

  /// The noise in use (1 sigma, counts): params().noise_counts, or
  /// deviceNoiseCounts() with effects.device_noise.
  double noiseCounts() const { return noise_; }
  /// The WTS's noise level of `device_noise` for this calibration and threshold.
  double deviceNoiseCounts() const { return device_noise_; }
  /// Per-taxel draws (identity when the effect is off): sensitivity gain,
  /// calibration error (the truth is (1 + e) x the file's polynomial), dead.
  double gain(int i) const { return gain_[static_cast<std::size_t>(i)]; }
  double calibrationError(int i) const { return calib_err_[static_cast<std::size_t>(i)]; }
  bool dead(int i) const { return dead_[static_cast<std::size_t>(i)] != 0; }

  /// Back to the state after configure(): noise reseeded, creep, hysteresis
  /// and the transfer ring cleared, the fault schedule armed again (the
  /// per-taxel draws stay).
  void reseed(uint64_t seed);

  /// The fault schedule (its link(), lastAction(), shots() after each frame).
  const SensorFaultSchedule& faults() const { return faults_; }
  /// Each taxel's firing threshold in counts (the stuck fault's floor).
  double thresholdCounts(int i) const { return threshold_counts_[static_cast<std::size_t>(i)]; }

 private:
  void layer(const TactileFrame& forces, double t);  // effects 1-3 into load_
  /// The frame stream's faults on a frame reaching the reader: false when withheld.
  bool emit(RawTactileFrame& raw) { return faults_.stream(raw) != FaultAction::Withhold; }
  /// respond() and emit() into raw; raw is left untouched when the frame is withheld.
  bool respondAndEmit(const TactileFrame& forces, double t, RawTactileFrame& raw);

  TaxelResponseParams params_;
  int n_ = 0;
  int rows_ = 0, cols_ = 0;
  double noise_ = 0.0, device_noise_ = 0.0;
  std::array<std::array<double, 4>, kMaxTaxels> coeffs_{};
  std::array<double, kMaxTaxels> threshold_counts_{};
  std::array<double, kMaxTaxels> silent_force_{};  ///< below this force a taxel reads 0 (no draw)
  std::mt19937_64 rng_{1};
  std::normal_distribution<double> normal_{0.0, 1.0};
  // Effects: static draws, layer state, transfer ring.
  bool layer_on_ = false, taxel_on_ = false;
  std::array<double, kMaxTaxels> gain_{};
  std::array<double, kMaxTaxels> calib_err_{};
  std::array<uint8_t, kMaxTaxels> dead_{};
  std::array<double, kMaxTaxels> load_{};   ///< the layer's signal after effects 1-3 (N)
  std::array<double, kMaxTaxels> hyst_{};   ///< hysteresis state y
  std::array<double, kMaxTaxels> creep_{};  ///< creep state z
  std::array<double, kMaxTaxels> creep_in_{};  ///< the input held since the last acquisition
  double last_t_ = 0.0;
  bool have_last_ = false;
  double delay_ = 0.0;
  std::vector<RawTactileFrame> ring_;  ///< capacity fixed by configure()
  std::size_t head_ = 0, count_ = 0;
  long overruns_ = 0;
  SensorFaultSchedule faults_;
  RawTactileFrame scratch_;  ///< a frame the stream's faults may withhold
};

}  // namespace sim
}  // namespace tactile
