// What the simulated KRCs (fri_sim_krc, lab_sim) take from the KRL program
// they stand in for: krc/TactileServo.src and its .dat, the files the KRC
// runs and krc/check_krc_config.py reads. Read once at start (allocates);
// nothing here is on a per-cycle path.
//
//   $STIFFNESS.FRAMETYPE (the last assignment before friStart): #BASE -> the
//       wrench in base axes, #TOOL -> in the tool's (flange) axes
//       (protocol.hpp WrenchFrame);
//   $LOAD = NAME (the last assignment before friOpen) and DECL LOAD NAME =
//       {M kg, CM {X mm, Y mm, Z mm, ...}, ...} in the .dat: the load the
//       KRC's model compensates;
//   $STIFFNESS.MAXFORCE and $STIFFNESS.CPMAXDELTA = {X .., Y .., Z .., A ..,
//       B .., C ..} (the last assignments before friOpen): the limits beyond
//       which the KRC stops the arm (KrcStiffnessLimits; MAXFORCE in N / N m,
//       kept; CPMAXDELTA in mm / deg, converted to m / rad).
// KRL is read without its comments (`;` to the end of the line, outside
// strings) and case-insensitively, as check_krc_config.py reads it.
#pragma once

#include <array>
#include <string>

#include "tactile_fri/krc_model.hpp"
#include "tactile_fri/protocol.hpp"
#include "tactile_types/config_result.hpp"

namespace tactile {
namespace fri {

struct KrlSettings {
  WrenchFrame wrench_frame = WrenchFrame::Base;  ///< $STIFFNESS.FRAMETYPE
  double load_mass_kg = 0.0;                     ///< $LOAD's M (kg)
  std::array<double, 3> load_com_m{};            ///< $LOAD's CM X, Y, Z (m, flange axes)
  KrcStiffnessLimits limits{};                   ///< $STIFFNESS.MAXFORCE, CPMAXDELTA (every component > 0)
};

/// Reads `src` (TactileServo.src) and the .dat beside it (same name, .dat).
/// Errors name the file, line and key, and what is valid (a missing
/// assignment, a FRAMETYPE other than #BASE / #TOOL, a load the .dat does not
/// declare, a MAXFORCE / CPMAXDELTA without all of X..C or with one <= 0).
ConfigResult readKrlSettings(const std::string& src, KrlSettings& out);

}  // namespace fri
}  // namespace tactile
