#include "tactile_lab/krc_schedule.hpp"

#include <cmath>

namespace tactile {
namespace lab {

namespace {
std::string wordOf(const fri::KrcEvent& e) {
  switch (e.kind) {
    case fri::KrcEvent::Kind::FriOpen: return "friOpen";
    case fri::KrcEvent::Kind::FriStart: return "friStart";
    case fri::KrcEvent::Kind::FriStop: return "friStop";
    case fri::KrcEvent::Kind::FriClose: return "friClose";
    case fri::KrcEvent::Kind::Quality: return std::string("quality=") + fri::toString(e.quality);
    case fri::KrcEvent::Kind::Power: return e.power ? "power=on" : "power=off";
  }
  return "?";
}
}  // namespace

fri::StateEvent stateEventOf(const fri::KrcScript::At& at, uint64_t cycle) {
  fri::StateEvent e;
  e.cycle = cycle;
  e.open = at.open;
  e.state = at.open ? at.state : fri::State::Off;
  e.quality = at.quality;
  e.power = at.power ? 0x7F : 0x00;  // the seven drives
  return e;
}

void scheduleFromScript(const fri::KrcScript& script, double period_s, fri::StateEvent& initial,
                        std::vector<fri::StateEvent>& schedule, std::vector<ScheduledWord>& words) {
  schedule.clear();
  words.clear();
  initial = stateEventOf(script.at(0.0), 0);
  for (const fri::KrcEvent& e : script.events()) {
    const uint64_t cycle = static_cast<uint64_t>(std::llround(e.t_s / period_s));
    words.push_back({cycle, wordOf(e)});
    if (!schedule.empty() && schedule.back().cycle == cycle) schedule.pop_back();  // the later state of that cycle
    schedule.push_back(stateEventOf(script.at(e.t_s), cycle));
  }
}

}  // namespace lab
}  // namespace tactile
