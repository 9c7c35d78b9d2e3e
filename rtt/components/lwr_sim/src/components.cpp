// The simulator's RTT component library (package tactile): the simulated arm,
// the simulated WTS sensor and the deterministic clock of the sim deployment.
#include <rtt/Component.hpp>

#include "tactile_sim_rtt/lwr_sim_component.hpp"
#include "tactile_sim_rtt/sim_clock.hpp"
#include "tactile_sim_rtt/wts_sim_component.hpp"

ORO_CREATE_COMPONENT_LIBRARY()
ORO_LIST_COMPONENT_TYPE(tactile::LwrSimComponent)
ORO_LIST_COMPONENT_TYPE(tactile::WtsSimComponent)
ORO_LIST_COMPONENT_TYPE(tactile::SimClock)
