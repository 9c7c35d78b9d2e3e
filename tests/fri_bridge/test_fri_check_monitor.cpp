// fri_check --monitor end to end: the real executable against the
// fri_sim_krc executable on 127.0.0.1, both as users run them. Each test has
// its own ports in 49959..49969 (no other test uses them; ctest may run the
// cases in parallel). Runs are bounded by packet counts (--cycles), not time;
// the two timing items get generous bands here (--period-tolerance 0.9,
// --max-jitter-ms 1000: this machine is shared, and the host's timing is not
// what these tests check), so they cannot fail a test on a loaded machine.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

#include "temp_file.hpp"

namespace {

const std::string kCheck = FRI_CHECK_PATH;
const std::string kSim = FRI_SIM_KRC_PATH;
const std::string kParams = FRI_PARAMS_FILE;
const std::string kBands = " --period-tolerance 0.9 --max-jitter-ms 1000";

bool contains(const std::string& s, const std::string& what) { return s.find(what) != std::string::npos; }

struct Outcome {
  std::string check, sim;  ///< the outputs
  int check_exit = -1, sim_exit = -1;
  /// The verdict line of an item ("[loss]", ...), or "".
  std::string item(const std::string& tag) const {
    std::istringstream in(check);
    std::string line;
    while (std::getline(in, line))
      if (line.rfind(tag, 0) == 0) return line;
    return "";
  }
  bool verdict(const std::string& tag, const std::string& v) const {
    const std::string l = item(tag);
    return l.size() > 16 && l.compare(14, v.size(), v) == 0;
  }
};

int closeStatus(FILE* p) {
  const int st = ::pclose(p);
  return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

/// fri_check --monitor on 127.0.0.1:port with `check_args`; once it listens
/// (its first line), fri_sim_krc --port port `sim_args` runs to its end.
Outcome monitor(int port, const std::string& check_args, const std::string& sim_args) {
  Outcome o;
  FILE* check = ::popen((kCheck + " --monitor --bind 127.0.0.1 --port " + std::to_string(port) +
                         " --idle-timeout 5 --seconds 120 " + check_args + " 2>&1")
                            .c_str(),
                        "r");
  if (check == nullptr) return o;
  char line[4096];
  if (std::fgets(line, sizeof line, check) != nullptr) o.check = line;
  if (contains(o.check, "listening on 127.0.0.1:")) {
    FILE* sim = ::popen((kSim + " --port " + std::to_string(port) + " " + sim_args + " 2>&1").c_str(), "r");
    if (sim != nullptr) {
      while (std::fgets(line, sizeof line, sim) != nullptr) o.sim += line;
      o.sim_exit = closeStatus(sim);
    }
  }
  while (std::fgets(line, sizeof line, check) != nullptr) o.check += line;
  o.check_exit = closeStatus(check);
  return o;
}

std::string readFile(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// A parameter file: fri.yaml's cycle time and a fixed KRC port.
std::string paramsWithKrcPort(int krc_port) {
  return tactile::test::writeTempFile("fri_monitor.yaml", "fri:\n  cycle_time_s: 0.001\n  udp:\n    port: 49938\n"
                                                          "    krc_port: " + std::to_string(krc_port) + "\n");
}

}  // namespace

TEST(FriCheckMonitor, HealthyLinkInMonPassesEveryItem) {
  const std::string yaml = paramsWithKrcPort(49961);
  const std::string json = tactile::test::writeTempFile("fri_monitor.json", "");
  const Outcome o = monitor(49960, "--params " + yaml + " --cycles 500 --json " + json + kBands,
                            "--local-port 49961 --cycles 560 --schedule 0:MON:PERFECT");
  EXPECT_EQ(o.check_exit, 0) << o.check;
  EXPECT_EQ(o.sim_exit, 0) << o.sim;
  for (const char* tag : {"[packets]", "[cycle time]", "[krc port]", "[control]", "[period]", "[jitter]", "[loss]",
                          "[order]", "[state]", "[quality]"})
    EXPECT_TRUE(o.verdict(tag, "PASS")) << tag << "\n" << o.check;
  EXPECT_TRUE(contains(o.item("[packets]"), "500 accepted of 500 datagrams")) << o.check;
  EXPECT_TRUE(contains(o.item("[krc port]"), "the KRC sends from UDP port 49961; fri.udp.krc_port = 49961")) << o.check;
  EXPECT_TRUE(contains(o.item("[state]"), "MON 100.0 %")) << o.check;
  EXPECT_TRUE(contains(o.sim, "mon_echo_errors 0 ")) << o.sim;  // MON: every reply echoed the measured pose
  const std::string j = readFile(json);
  EXPECT_TRUE(contains(j, "\"result\": \"pass\"")) << j;
  EXPECT_TRUE(contains(j, "\"lost\": 0, \"sent\": 500")) << j;
  std::remove(yaml.c_str());
  std::remove(json.c_str());
}

TEST(FriCheckMonitor, CmdIsHeldWhereItWasEnteredAndAQualityDropFails) {
  const Outcome o = monitor(49968, "--params " + kParams + " --cycles 500" + kBands,
                            "--cycles 560 --schedule 0:MON:PERFECT,150:CMD:PERFECT,350:CMD:BAD");
  EXPECT_EQ(o.check_exit, 3) << o.check;
  // The KRC applied the bridge's CMD replies; none moved the arm (steps between applied commands: 0).
  EXPECT_TRUE(contains(o.sim, "max_step 0.000000 m 0.000000 rad")) << o.sim;
  EXPECT_FALSE(contains(o.sim, "applied 0 ")) << o.sim;  // CMD replies were taken (those on time: host load)
  EXPECT_TRUE(o.verdict("[state]", "PASS")) << o.check;
  EXPECT_TRUE(contains(o.item("[state]"), "in CMD the bridge held the entry pose (200 dry_run")) << o.check;
  EXPECT_TRUE(o.verdict("[quality]", "FAIL")) << o.check;
  EXPECT_TRUE(contains(o.check, "the quality dropped to BAD")) << o.check;
  EXPECT_TRUE(contains(o.check, "state CMD quality BAD")) << o.check;  // the timeline
}

// A drop below OK that recovers (in MON): FAIL by default, a WARN with
// --quality-drop warn (the rehearsal on a host without a real-time kernel);
// the message names the worst quality either way.
TEST(FriCheckMonitor, AQualityDropThatRecoversFailsUnlessWarned) {
  const std::string krc = "--cycles 560 --schedule 0:MON:PERFECT,200:MON:BAD,260:MON:PERFECT";
  const Outcome fails = monitor(49961, "--params " + kParams + " --cycles 500" + kBands, krc);
  EXPECT_EQ(fails.check_exit, 3) << fails.check;
  EXPECT_TRUE(fails.verdict("[quality]", "FAIL")) << fails.check;
  EXPECT_TRUE(contains(fails.check, "the quality dropped to BAD")) << fails.check;
  const Outcome warns = monitor(49966, "--params " + kParams + " --cycles 500 --quality-drop warn" + kBands, krc);
  EXPECT_TRUE(warns.verdict("[quality]", "WARN")) << warns.check;
  EXPECT_TRUE(contains(warns.check, "the quality dropped to BAD and recovered (a WARN by --quality-drop warn)"))
      << warns.check;
}

TEST(FriCheckMonitor, TwoMillisecondKrcAgainstOneMillisecondYamlFailsTheCycleTime) {
  const Outcome o = monitor(49962, "--params " + kParams + " --cycles 300" + kBands, "--cycles 340 --period-ms 2");
  EXPECT_EQ(o.check_exit, 3) << o.check;
  EXPECT_TRUE(o.verdict("[cycle time]", "FAIL")) << o.check;
  EXPECT_TRUE(contains(o.check, "the KRC sends every 2 ms but " + kParams +
                                    " expects 1 ms: call friOpen(1) in the KRL program or set fri.cycle_time_s: 0.002"))
      << o.check;
  EXPECT_TRUE(contains(o.item("[cycle time]"), "300 packets flagged cycle_mismatch by the bridge")) << o.check;
  EXPECT_TRUE(o.verdict("[control]", "PASS")) << o.check;
  EXPECT_TRUE(o.verdict("[loss]", "PASS")) << o.check;
  // the measured period follows the KRC's own (2 ms), within the +-90 % band
  EXPECT_TRUE(o.verdict("[period]", "PASS")) << o.check;
}

TEST(FriCheckMonitor, WrongControlStrategyFails) {
  const Outcome o = monitor(49963, "--params " + kParams + " --cycles 300" + kBands, "--cycles 340 --control joint");
  EXPECT_EQ(o.check_exit, 3) << o.check;
  EXPECT_TRUE(o.verdict("[control]", "FAIL")) << o.check;
  EXPECT_TRUE(contains(o.item("[control]"), "the KRC runs joint impedance (control 3)")) << o.check;
  EXPECT_TRUE(contains(o.check, "select Cartesian impedance in the KRL program")) << o.check;
  EXPECT_TRUE(o.verdict("[cycle time]", "PASS")) << o.check;
}

TEST(FriCheckMonitor, InducedLossIsCounted) {
  // A burst of 20 measurements not sent (cycles 100..119): exactly 20 sequence gaps.
  const Outcome o = monitor(49964, "--params " + kParams + " --cycles 400" + kBands, "--cycles 440 --burst 100:20");
  EXPECT_EQ(o.check_exit, 3) << o.check;
  EXPECT_TRUE(contains(o.sim, "injected loss 20 ")) << o.sim;
  EXPECT_TRUE(o.verdict("[loss]", "FAIL")) << o.check;
  EXPECT_TRUE(contains(o.item("[loss]"), "20 lost of 400 the KRC sent")) << o.check;
  EXPECT_TRUE(contains(o.item("[packets]"), "380 accepted of 380 datagrams")) << o.check;
  EXPECT_TRUE(o.verdict("[order]", "PASS")) << o.check;
}

TEST(FriCheckMonitor, KrcPortOtherThanConfiguredFails) {
  const std::string yaml = paramsWithKrcPort(49967);
  const Outcome o = monitor(49965, "--params " + yaml + " --cycles 300" + kBands, "--cycles 340 --local-port 49966");
  EXPECT_EQ(o.check_exit, 3) << o.check;
  EXPECT_TRUE(o.verdict("[krc port]", "FAIL")) << o.check;
  EXPECT_TRUE(contains(o.check, "the KRC sends from port 49966 but " + yaml + " expects 49967")) << o.check;
  EXPECT_TRUE(contains(o.check, "bridge port_mismatch")) << o.check;  // the bridge core's own check agrees
  std::remove(yaml.c_str());
}

TEST(FriCheckMonitor, NoKrcExitsTwoWithWhatToCheck) {
  int code = -1;
  FILE* p = ::popen((kCheck + " --monitor --bind 127.0.0.1 --port 49969 --idle-timeout 0.5 --params " + kParams +
                     " 2>&1").c_str(), "r");
  ASSERT_NE(p, nullptr);
  std::string out;
  char line[4096];
  while (std::fgets(line, sizeof line, p) != nullptr) out += line;
  code = closeStatus(p);
  EXPECT_EQ(code, 2) << out;
  EXPECT_TRUE(contains(out, "no packet from the KRC within 0.5 s on 127.0.0.1:49969")) << out;
  EXPECT_TRUE(contains(out, "dlrrc.ini, FRIHOST = this host")) << out;
}

TEST(FriCheckMonitor, UsageErrorsExitOne) {
  for (const char* args : {"--monitor --port 0 --motion circle", "--monitor --port 0 --seconds 0",
                           "--monitor --port 0 --max-loss-rate 2"}) {
    FILE* p = ::popen((kCheck + " " + args + " 2>&1").c_str(), "r");
    ASSERT_NE(p, nullptr);
    std::string out;
    char line[1024];
    while (std::fgets(line, sizeof line, p) != nullptr) out += line;
    EXPECT_EQ(closeStatus(p), 1) << args << ": " << out;
    EXPECT_TRUE(contains(out, "usage: fri_check")) << out;
  }
}

// Day one's cycle check: the share of answers the KRC missed (its miss
// counter; a burst of 25 measurements not sent is 25 answers missed, 4 % of
// 620: more than the 2 % a sustained cycle allows, whatever the host adds)
// and the quality the KRC gave the link from them (the simulated KRC's
// timing rule: 25 of the last 100 missed is BAD, and stays BAD with up to 5
// more that a loaded host may add).
TEST(FriCheckMonitor, MissedAnswersAtOneMillisecondAdviseTwo) {
  const Outcome o = monitor(49959, "--params " + kParams + " --cycles 560" + kBands,
                            "--cycles 620 --quality-rule on --burst 300:25 --schedule 0:MON:PERFECT");
  EXPECT_EQ(o.check_exit, 3) << o.check;  // the quality dropped below OK: [quality] FAILs
  EXPECT_TRUE(contains(o.sim, "quality from timing on: answers missed ")) << o.sim;
  EXPECT_TRUE(o.verdict("[quality]", "FAIL")) << o.check;
  EXPECT_TRUE(contains(o.check, "the quality dropped to BAD")) << o.check;
  EXPECT_TRUE(o.verdict("[cycle]", "WARN")) << o.check;
  EXPECT_TRUE(contains(o.item("[cycle]"), "at the KRC's 1 ms cycle")) << o.check;
  EXPECT_TRUE(contains(o.check, "this PC does not sustain 1 ms: use 2 ms, friOpen(2)")) << o.check;
}

TEST(FriCheckMonitor, MissedAnswersAtTwoMillisecondsFailTheCycle) {
  const std::string yaml = tactile::test::writeTempFile("fri_monitor_2ms.yaml", "fri:\n  cycle_time_s: 0.002\n");
  const Outcome o = monitor(49967, "--params " + yaml + " --cycles 280" + kBands,
                            "--cycles 320 --period-ms 2 --quality-rule on --burst 150:20 --schedule 0:MON:PERFECT");
  EXPECT_EQ(o.check_exit, 3) << o.check;
  EXPECT_TRUE(o.verdict("[cycle time]", "PASS")) << o.check;
  EXPECT_TRUE(o.verdict("[cycle]", "FAIL")) << o.check;
  EXPECT_TRUE(contains(o.item("[cycle]"), "at the KRC's 2 ms cycle")) << o.check;
  EXPECT_TRUE(contains(o.check, "this PC does not sustain even 2 ms")) << o.check;
  std::remove(yaml.c_str());
}
