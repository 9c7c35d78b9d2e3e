// The day-one checks of the KRC's estimated wrench (estExtTcpFT) that only
// the real arm can confirm, from recordings fri_check writes
// (fri_check --monitor --record FILE: the arm held still, never commanded):
//
//  * checkKnownWeight(): a known weight hung on (or laid on) the pad. The
//    force change between a recording without it (the tare) and one with it
//    is compared with the weight's force m g d, read four ways: in base or in
//    tool axes, with either sign. The hypothesis whose direction fits names
//    the KRC's frame and sign; its magnitude the scale (load data, the
//    weight). A pose in which two readings look alike (the flange pointing
//    straight down or up: tool z is -base z) is refused as undetermined.
//  * fitLoad(): the arm at rest in several orientations with nothing
//    touching the pad. What the KRC reports then is the error of its load
//    data: in flange axes, force dm g_e and moment s x g_e, with g_e the
//    gravity vector (0, 0, -g) turned into the flange's axes, dm the mass
//    error and s = m_true c_true - m_model c_model (first moment of mass).
//    A constant offset (b_f, b_t, flange axes) is fitted with them, linear
//    least squares (Eigen), at least 3 orientations.
//
// Offline analysis (allocates, reads files); not for the per-cycle path.
#pragma once

#include <array>
#include <cstdio>
#include <string>
#include <vector>

#include <kdl/frames.hpp>

#include "tactile_fri/protocol.hpp"
#include "tactile_types/config_result.hpp"

namespace tactile {
namespace fri {

/// Standard gravity (m/s^2).
constexpr double kGravityMps2 = 9.80665;

// ---- recordings ---------------------------------------------------------------

/// The recording's first line (the columns).
void writeRecordingHeader(FILE* f);
/// One measurement: t (s), state, quality, msrCartPos (12, row-major 3x4),
/// estExtTcpFT as sent, reordered to [Fx Fy Fz Tx Ty Tz] (the KRC's axes).
void writeRecordingLine(FILE* f, double t_s, const MsrPacket& m);

struct WrenchSample {
  KDL::Frame pose = KDL::Frame::Identity();  ///< msrCartPos, {g}T{e}
  std::array<double, 6> w{};                 ///< estExtTcpFT as sent, [Fx Fy Fz Tx Ty Tz]
};

/// A recording's mean, taken only when the arm held still.
struct RestMean {
  std::string file;
  KDL::Frame pose = KDL::Frame::Identity();
  std::array<double, 6> w{};  ///< mean wrench, as sent
  std::size_t samples = 0;
  double force_sd_n = 0.0;    ///< RMS of the force's deviation from its mean
};

/// Reads a recording; errors name the file and line.
ConfigResult readRecording(const std::string& file, std::vector<WrenchSample>& out);
/// The mean of a recording whose pose stayed within 2 mm / 0.02 rad of its
/// first sample (kStillM, kStillRad); else an error: the arm moved.
ConfigResult restMean(const std::string& file, const std::vector<WrenchSample>& s, RestMean& out);
constexpr double kStillM = 0.002;
constexpr double kStillRad = 0.02;

// ---- the known weight ---------------------------------------------------------

struct KnownWeight {
  double mass_kg = 1.0;                       ///< (0, 50]
  KDL::Vector dir = KDL::Vector(0, 0, -1);    ///< unit; the force's direction on the pad
  bool dir_in_tool = false;                   ///< dir in the flange's axes (a push along the pad normal)
};

enum class WeightVerdict : uint8_t {
  Correct = 0,        ///< the configured frame, the right sign, the magnitude within tolerance
  WrongFrame = 1,     ///< the KRC's axes are not fri.wrench_frame's
  SignInverted = 2,   ///< the configured frame, the force reversed
  WrongFrameAndSign = 3,
  MagnitudeOff = 4,   ///< frame and sign right, |force| off by more than kMagnitudeTol
  Undetermined = 5    ///< the pose does not separate the readings, or no reading fits, or no force
};
const char* toString(WeightVerdict v);

struct WeightResult {
  WeightVerdict verdict = WeightVerdict::Undetermined;
  WrenchFrame frame = WrenchFrame::Base;  ///< the frame of the best reading
  int sign = 1;                           ///< the sign of the best reading
  KDL::Vector measured;                   ///< the force change, as sent
  KDL::Vector expected_base;              ///< m g d in {g}
  KDL::Vector expected_tool;              ///< m g d in {e}
  double angle_deg[2][2] = {{0, 0}, {0, 0}};  ///< [frame][sign<0]: measured vs each reading
  double separation_deg = 0.0;  ///< the best reading's angle to the nearest other one
  double ratio = 0.0;           ///< |measured| / (m g)
  std::vector<std::string> lines;  ///< the report, ending with the verdict and what to change
};

constexpr double kMaxAngleDeg = 20.0;    ///< a reading fits within this angle (estExtTcpFT's error, a few N on 10 N)
constexpr double kMinSeparationDeg = 45.0;  ///< readings this close cannot be told apart (> 2 kMaxAngleDeg)
constexpr double kMagnitudeTol = 0.10;   ///< |ratio - 1| beyond this: magnitude off
constexpr double kMinForceRatio = 0.25;  ///< a force change below this share of m g: no weight seen

/// `configured`: fri.yaml's wrench_frame (what the bridge reads).
WeightResult checkKnownWeight(const RestMean& tare, const RestMean& loaded, const KnownWeight& kw,
                              WrenchFrame configured);

// ---- the load data ------------------------------------------------------------

struct LoadModel {
  double mass_kg = 0.0;
  KDL::Vector com_m = KDL::Vector::Zero();  ///< flange axes
};

enum class LoadVerdict : uint8_t { Ok = 0, MassOff = 1, ComOff = 2, MassAndComOff = 3, Undetermined = 4 };
const char* toString(LoadVerdict v);

struct LoadResult {
  LoadVerdict verdict = LoadVerdict::Undetermined;
  double dm_kg = 0.0;                      ///< true - modelled mass
  KDL::Vector s = KDL::Vector::Zero();     ///< true - modelled first moment (kg m, flange axes)
  double mass_kg = 0.0;                    ///< fitted true mass
  KDL::Vector com_m = KDL::Vector::Zero(); ///< fitted true centre of mass (flange axes)
  bool com_known = false;                  ///< the fitted mass is large enough to place its centre
  KDL::Vector bias_f = KDL::Vector::Zero(), bias_t = KDL::Vector::Zero();  ///< fitted offsets (flange axes)
  double rms_force_n = 0.0, rms_moment_nm = 0.0;  ///< residual of the fit
  double conditioning = 0.0;  ///< smallest / largest singular value of the (scaled) design matrix
  std::vector<std::string> lines;
};

constexpr double kMassTolKg = 0.05;        ///< |dm| within this: mass OK (0.5 N)
constexpr double kComTolM = 0.01;          ///< |c_true - c_model| within this: CoM OK
constexpr double kMinConditioning = 0.05;  ///< the orientations must differ enough

/// `frame`: the axes the recordings' wrench is in (fri.wrench_frame, checked
/// by the known weight first). At least 3 recordings.
LoadResult fitLoad(const std::vector<RestMean>& rests, WrenchFrame frame, const LoadModel& model,
                   double mass_tol_kg = kMassTolKg, double com_tol_m = kComTolM);

}  // namespace fri
}  // namespace tactile
