// fri_check end to end: the real executable, bound to an ephemeral port on
// 127.0.0.1, against the simulated KRC in this process.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <chrono>
#include <cstdio>
#include <string>

#include "fri_test_util.hpp"
#include "tactile_fri/sim_krc.hpp"

using namespace tactile::fri;
using namespace fri_test;

namespace {

struct CheckRun {
  std::string output;
  int exit_code = -1;
  SimKrcStats krc;
  double max_displacement = 0.0;  // of the plant from its start pose
};

CheckRun runFriCheck(const std::string& args, const std::vector<StateEvent>& schedule, uint64_t krc_cycles,
                     const FaultParams& faults = FaultParams{}, CartOffset krc_form = CartOffset::None) {
  CheckRun r;
  const std::string cmd = std::string(FRI_CHECK_PATH) + " --port 0 --bind 127.0.0.1 --idle-timeout 3 " + args + " 2>&1";
  FILE* pipe = ::popen(cmd.c_str(), "r");
  if (pipe == nullptr) return r;
  char line[512];
  if (std::fgets(line, sizeof line, pipe) == nullptr) {
    ::pclose(pipe);
    return r;
  }
  r.output = line;
  const std::string first = line;
  const std::size_t colon = first.find("127.0.0.1:");
  EXPECT_NE(colon, std::string::npos) << first;
  const unsigned port = static_cast<unsigned>(std::stoul(first.substr(colon + 10)));

  SimKrcParams kp;
  kp.remote_port = static_cast<uint16_t>(port);
  kp.real_time = false;
  kp.reply_timeout_s = 1.0;
  kp.initial_pose = startPose();
  kp.schedule = schedule;
  kp.faults = faults;
  kp.cart_offset = krc_form;
  FirstOrderPlant plant(0.02);
  SimKrc krc;
  EXPECT_TRUE(krc.configure(kp, plant).ok());
  for (uint64_t i = 0; i < krc_cycles; ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    krc.runCycle();
    r.max_displacement = std::max(r.max_displacement, (krc.plantState().pose.p - startPose().p).Norm());
    // A full reply timeout on loopback means fri_check has exited (it stops after --cycles).
    if (std::chrono::steady_clock::now() - t0 > std::chrono::milliseconds(900)) break;
  }
  r.krc = krc.stats();
  while (std::fgets(line, sizeof line, pipe) != nullptr) r.output += line;
  const int status = ::pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

bool contains(const std::string& s, const std::string& what) { return s.find(what) != std::string::npos; }

const std::vector<StateEvent> kSchedule = {{0, State::Mon, Quality::Perfect, 0x7F},
                                           {100, State::Cmd, Quality::Perfect, 0x7F},
                                           {400, State::Cmd, Quality::Bad, 0x7F},
                                           {450, State::Cmd, Quality::Ok, 0x7F},
                                           {700, State::Mon, Quality::Perfect, 0x7F}};

}  // namespace

TEST(FriCheckTool, CircleMotionPrintsTransitionsAndStatistics) {
  const CheckRun r = runFriCheck("--cycles 800 --motion circle --radius 0.02 --circle-period 1", kSchedule, 800);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "state MON quality PERFECT")) << r.output;
  EXPECT_TRUE(contains(r.output, "state CMD quality PERFECT")) << r.output;
  EXPECT_TRUE(contains(r.output, "state CMD quality BAD")) << r.output;
  EXPECT_TRUE(contains(r.output, "bridge quality_low")) << r.output;
  EXPECT_TRUE(contains(r.output, "bridge left_cmd")) << r.output;
  EXPECT_TRUE(contains(r.output, "summary: cycles 800 received 800 replies 800 lost 0")) << r.output;
  EXPECT_TRUE(contains(r.output, "latency: processing mean")) << r.output;
  EXPECT_EQ(r.krc.replies, 800u);
  EXPECT_EQ(r.krc.mon_echo_errors, 0u);
  EXPECT_EQ(r.krc.remote_seq_errors, 0u);
  EXPECT_EQ(r.krc.applied, 550u);
  EXPECT_LE(r.krc.max_cmd_step_m, 0.05 * 0.001 + 2e-7);  // fri_check's default 0.05 m/s limit
  EXPECT_LE(r.krc.max_entry_offset_m, 0.05 * 0.001 + 2e-7);
  EXPECT_GT(r.max_displacement, 0.001);  // the circle moved the robot
}

TEST(FriCheckTool, HoldKeepsTheRobotStillAndReportsLoss) {
  FaultParams f;
  f.loss = 0.05;
  f.seed = 7;
  const CheckRun r = runFriCheck("--cycles 500 --motion hold", kSchedule, 600, f);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_LT(r.max_displacement, 1e-6);  // hold: float rounding only
  EXPECT_TRUE(contains(r.output, "packet(s) lost")) << r.output;
  EXPECT_TRUE(contains(r.output, "summary: cycles 500")) << r.output;
  EXPECT_GT(r.krc.inj_lost, 10u);
  EXPECT_EQ(r.krc.mon_echo_errors, 0u);
}

TEST(FriCheckTool, UsageErrorsExitWithStatusOne) {
  for (const char* args : {"", "--port 70000", "--port 0 --motion zigzag", "--port 0 --cycles 0"}) {
    const std::string cmd = std::string(FRI_CHECK_PATH) + " " + args + " 2>&1";
    FILE* pipe = ::popen(cmd.c_str(), "r");
    ASSERT_NE(pipe, nullptr);
    std::string out;
    char line[512];
    while (std::fgets(line, sizeof line, pipe) != nullptr) out += line;
    const int status = ::pclose(pipe);
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 1) << args << ": " << out;
    EXPECT_TRUE(contains(out, "usage: fri_check")) << out;
  }
}

namespace {
std::string runCapture(const std::string& cmd, int& exit_code) {
  FILE* pipe = ::popen((cmd + " 2>&1").c_str(), "r");
  std::string out;
  if (pipe == nullptr) return out;
  char line[1024];
  while (std::fgets(line, sizeof line, pipe) != nullptr) out += line;
  const int status = ::pclose(pipe);
  exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return out;
}

/// fri_check (listening on an ephemeral loopback port, `check_args` added)
/// and fri_sim_krc (sending to that port, `sim_args` added) as users run
/// them: both outputs and exit statuses.
struct ToolPair {
  std::string check_out, sim_out;
  int check_status = -1, sim_exit = -1;
};
ToolPair runToolsOnLoopback(const std::string& check_args, const std::string& sim_args) {
  ToolPair r;
  FILE* check = ::popen((std::string(FRI_CHECK_PATH) + " --port 0 --bind 127.0.0.1 --idle-timeout 3 " + check_args +
                         " 2>&1").c_str(),
                        "r");
  if (check == nullptr) return r;
  char line[512];
  if (std::fgets(line, sizeof line, check) == nullptr) {
    r.check_status = ::pclose(check);
    return r;
  }
  r.check_out = line;
  const std::size_t colon = r.check_out.find("127.0.0.1:");
  if (colon != std::string::npos) {
    const std::string port = std::to_string(std::stoul(r.check_out.substr(colon + 10)));
    r.sim_out = runCapture(std::string(FRI_SIM_KRC_PATH) + " --port " + port + " " + sim_args, r.sim_exit);
  }
  while (std::fgets(line, sizeof line, check) != nullptr) r.check_out += line;
  r.check_status = ::pclose(check);
  return r;
}

}  // namespace

TEST(FriCheckTool, AgainstTheSimKrcExecutable) {
  // Both bench tools as users run them, on loopback.
  const ToolPair t = runToolsOnLoopback("--cycles 400 --motion circle",
                                        "--cycles 400 --fast --schedule 0:MON:PERFECT,100:CMD:PERFECT,300:MON:OK");
  const std::string &out = t.check_out, &sim = t.sim_out;
  const int status = t.check_status, sim_exit = t.sim_exit;
  ASSERT_NE(out.find("127.0.0.1:"), std::string::npos) << out;
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << out;
  EXPECT_EQ(sim_exit, 0) << sim;
  EXPECT_TRUE(contains(sim, "cycles 400 sent 400 replies 400")) << sim;
  EXPECT_TRUE(contains(sim, "applied 200 ")) << sim;
  EXPECT_TRUE(contains(sim, "mon_echo_errors 0 ")) << sim;
  EXPECT_TRUE(contains(out, "summary: cycles 400")) << out;
  EXPECT_TRUE(contains(out, "bridge left_cmd")) << out;
  // usage errors of the simulator
  int bad_exit = -1;
  const std::string bad = runCapture(std::string(FRI_SIM_KRC_PATH) + " --port 1 --schedule 5:FOO:OK", bad_exit);
  EXPECT_EQ(bad_exit, 1) << bad;
  EXPECT_TRUE(contains(bad, "bad --schedule event '5:FOO:OK'")) << bad;
}

// fri_check finds the form in which the KRC sends its set point (fri.cart_offset)
// from a short circle in CMD: against the simulated KRC sending each form, with
// this run's bridge reading none (the default). A run whose bridge reads
// another form than the KRC sends holds at offset_mismatch after one step and
// says to run again with none.
TEST(FriCheckTool, FindsTheFormOfTheKrcsSetPoint) {
  const std::vector<StateEvent> cmd = {{0, State::Mon, Quality::Perfect, 0x7F}, {100, State::Cmd, Quality::Perfect, 0x7F}};
  struct Case {
    CartOffset krc;
    const char* args;
    const char* verdict;
  };
  for (const Case& c : {Case{CartOffset::None, "", "cart_offset: use none ("},
                        Case{CartOffset::Composed, "", "cart_offset: use composed ("},
                        Case{CartOffset::Elementwise, "", "cart_offset: use elementwise ("},
                        Case{CartOffset::Elementwise, " --cart-offset elementwise", "cart_offset: use elementwise ("},
                        Case{CartOffset::Elementwise, " --cart-offset composed",
                             "cart_offset: undetermined (this run's bridge read composed, the KRC sends another form: it "
                             "held at offset_mismatch after "}}) {
    const CheckRun r = runFriCheck(std::string("--cycles 1200 --motion circle --radius 0.02 --circle-period 1") + c.args,
                                   cmd, 1200, FaultParams{}, c.krc);
    const std::string what = std::string("KRC ") + toString(c.krc) + c.args;
    EXPECT_EQ(r.exit_code, 0) << what << "\n" << r.output;
    EXPECT_TRUE(contains(r.output, c.verdict)) << what << "\n" << r.output;
    EXPECT_LE(r.krc.max_cmd_step_m, 0.05 * 0.001 + 2e-7) << what;
    EXPECT_LE(r.krc.max_entry_offset_m, 0.05 * 0.001 + 2e-7) << what;
    if (std::string(c.args) != " --cart-offset composed") EXPECT_GT(r.max_displacement, 0.002) << what;
    else EXPECT_TRUE(contains(r.output, "bridge offset_mismatch")) << r.output;
  }
  // Without motion there is nothing to tell the forms apart.
  const CheckRun hold = runFriCheck("--cycles 400 --motion hold", cmd, 400, FaultParams{}, CartOffset::Elementwise);
  EXPECT_TRUE(contains(hold.output, "cart_offset: undetermined (the command moved")) << hold.output;
}

TEST(FriCheckTool, FindsTheFormAgainstTheSimKrcExecutable) {
  const ToolPair t = runToolsOnLoopback("--cycles 1000 --motion circle --radius 0.02 --circle-period 1",
                                        "--cycles 1000 --fast --cart-offset composed --schedule 0:MON:PERFECT,100:CMD:PERFECT");
  const std::string &out = t.check_out, &sim = t.sim_out;
  const int sim_exit = t.sim_exit;
  ASSERT_NE(out.find("127.0.0.1:"), std::string::npos) << out;
  EXPECT_EQ(sim_exit, 0) << sim;
  EXPECT_TRUE(contains(out, "cart_offset: use composed (")) << out;
  int bad_exit = -1;
  const std::string bad = runCapture(std::string(FRI_SIM_KRC_PATH) + " --port 1 --cart-offset additive", bad_exit);
  EXPECT_EQ(bad_exit, 1) << bad;
}
