// fri_check's offline modes on recordings of fri_check --monitor --record
// (the day-one checks of the estimated wrench, docs/bringup.md):
//
//   fri_check --wrench-check --mass KG --tare FILE --loaded FILE [--params fri.yaml]
//             [--direction base:X,Y,Z | tool:X,Y,Z]
//     a known weight: the KRC's frame and sign of estExtTcpFT against
//     fri.wrench_frame (tactile_fri/wrench_checks.hpp checkKnownWeight).
//     --direction: the weight's force on the pad (default base:0,0,-1, a
//     weight hanging along gravity; tool:0,0,-1 a push against the pad's
//     normal, when the pad's surface faces +z of the flange).
//   fri_check --load-data --sensor-params wts0614.yaml [--params fri.yaml]
//             [--mass-tol KG] [--com-tol M] REST1 REST2 REST3 [...]
//     the pad's load data from the arm at rest in 3 or more orientations,
//     against the sensor file's pad: pad_mass_kg / pad_com_m (fitLoad).
//
// Exit: 0 the check passed (frame correct / load data OK), 3 any other
// verdict, 1 usage or unreadable input.
#pragma once

namespace tactile {
namespace fri {

int runWrenchCheck(int argc, char** argv);
int runLoadData(int argc, char** argv);

}  // namespace fri
}  // namespace tactile
