// The KRC's $STIFFNESS.MAXFORCE and $STIFFNESS.CPMAXDELTA as the KRL program
// writes them (krc/TactileServo.src), for the simulated KRC
// (tactile::fri::KrcStiffnessLimits). Configuration time: reads a file.
#pragma once

#include <string>

#include "tactile_fri/krc_model.hpp"
#include "tactile_types/config_result.hpp"

namespace tactile {
namespace lab {

/// The last assignments `$STIFFNESS.MAXFORCE = {X .., Y .., Z .., A .., B .., C ..}`
/// and `$STIFFNESS.CPMAXDELTA = {...}` before the program's friOpen in the
/// KRL file `path` (comments after ';' ignored). MAXFORCE in N / N m, kept;
/// CPMAXDELTA in mm / deg, converted to m / rad. Errors name the file, its
/// line, the field and the valid range (every component > 0).
ConfigResult readKrlStiffnessLimits(const std::string& path, fri::KrcStiffnessLimits& out);

}  // namespace lab
}  // namespace tactile
