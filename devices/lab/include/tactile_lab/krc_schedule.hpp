// A KRC script (tactile::fri::KrcScript: times in s, KRL's words) as the
// cycle schedule of the UDP test peer tactile::fri::SimKrc, and the words to
// print when each takes effect (lab_sim). Configuration time: allocates.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "tactile_fri/krc_model.hpp"
#include "tactile_fri/sim_krc.hpp"

namespace tactile {
namespace lab {

/// One script event at its cycle, in the script's words ("friStart", "quality=BAD").
struct ScheduledWord {
  uint64_t cycle = 0;
  std::string word;
};

/// The KRC's state as a schedule event at `cycle`.
fri::StateEvent stateEventOf(const fri::KrcScript::At& at, uint64_t cycle);

/// The schedule of `script` at the measurement period `period_s` (> 0): an
/// event at cycle round(t / period_s) for each event time of the script,
/// holding the KRC's whole state after every event up to that time
/// (KrcScript::at); `initial` is the state at cycle 0 (the empty script:
/// command mode; a script whose first event is later: closed until then).
/// `words` lists every event with its cycle, in order.
void scheduleFromScript(const fri::KrcScript& script, double period_s, fri::StateEvent& initial,
                        std::vector<fri::StateEvent>& schedule, std::vector<ScheduledWord>& words);

}  // namespace lab
}  // namespace tactile
