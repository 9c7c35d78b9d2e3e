// wts_check end to end: the real executable against the simulated WTS0614
// (wts_sim, a separate process serving the protocol on a PTY), one fault per
// test. Every run counts frames (--frames), never seconds; the only rate
// check is wts_check's own, given a band of +-50 % here (--rate-tolerance 0.5:
// the test machine is shared, the rate is not what these tests are about).
// The whole-pad press is started by SIGUSR1 to wts_sim when wts_check prints
// its "Press the whole pad" prompt (an event, not a delay).
#include <gtest/gtest.h>

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

extern char** environ;

namespace {

const std::string kCheck = WTS_CHECK_BIN;
const std::string kSim = WTS_SIM_BIN;
// Frames of the no-load window: 150 frames give a taxel's sample std within
// +-12 % (2 sigma) of its true value, far from k x stated = 3 x 6 counts.
const std::string kCommon = " --frames 150 --periodic-ms 5 --rate-tolerance 0.5 --no-prompt --seconds 60";

std::string tempDir() {
  std::string t = ::testing::TempDir() + "wts_check_XXXXXX";
  std::vector<char> buf(t.begin(), t.end());
  buf.push_back('\0');
  const char* d = ::mkdtemp(buf.data());
  return d ? std::string(d) : std::string();
}

bool contains(const std::string& s, const std::string& what) { return s.find(what) != std::string::npos; }

/// wts_sim as a child process, its device behind `link`.
class SimProcess {
 public:
  SimProcess(const std::string& link, const std::vector<std::string>& args) : link_(link) {
    std::vector<std::string> argv_s = {kSim, "--link", link, "--duration", "120"};
    argv_s.insert(argv_s.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (std::string& s : argv_s) argv.push_back(&s[0]);
    argv.push_back(nullptr);
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, 1, "/dev/null", O_WRONLY, 0);
    if (posix_spawn(&pid_, kSim.c_str(), &fa, nullptr, argv.data(), environ) != 0) pid_ = -1;
    posix_spawn_file_actions_destroy(&fa);
    // Wait for the link (a condition, bounded at 10 s for a machine under load).
    struct stat st {};
    for (int i = 0; i < 400 && pid_ > 0 && ::lstat(link.c_str(), &st) != 0; ++i) ::usleep(25000);
  }
  ~SimProcess() {
    if (pid_ > 0) {
      ::kill(pid_, SIGTERM);
      int status = 0;
      ::waitpid(pid_, &status, 0);
    }
  }
  bool ready() const {
    struct stat st {};
    return pid_ > 0 && ::lstat(link_.c_str(), &st) == 0;
  }
  void press() const { ::kill(pid_, SIGUSR1); }

 private:
  std::string link_;
  pid_t pid_ = -1;
};

struct CheckRun {
  std::string out;
  int exit_code = -1;
  /// The verdict line of a stage ("[a]".."[e]"), or "" if absent.
  std::string stage(const std::string& tag) const {
    std::istringstream in(out);
    std::string line;
    while (std::getline(in, line))
      if (line.rfind(tag, 0) == 0) return line;
    return "";
  }
  bool verdict(const std::string& tag, const std::string& v) const {
    const std::string l = stage(tag);
    return l.size() > 20 && l.compare(19, v.size(), v) == 0;
  }
};

/// Runs wts_check with `args`; `on_line` sees each output line as it comes.
CheckRun runCheck(const std::string& args, const std::function<void(const std::string&)>& on_line = nullptr) {
  CheckRun r;
  FILE* p = ::popen((kCheck + " " + args + " 2>&1").c_str(), "r");
  if (p == nullptr) return r;
  char line[4096];
  while (std::fgets(line, sizeof line, p) != nullptr) {
    r.out += line;
    if (on_line) on_line(line);
  }
  const int st = ::pclose(p);
  r.exit_code = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  return r;
}

std::string readFile(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

class WtsCheck : public ::testing::Test {
 protected:
  void SetUp() override {
    dir = tempDir();
    ASSERT_FALSE(dir.empty());
    link = dir + "/wts0";
    json = dir + "/summary.json";
  }
  void TearDown() override {
    ::unlink(json.c_str());
    ::unlink(link.c_str());
    ::rmdir(dir.c_str());
  }
  std::string dir, link, json;
};

}  // namespace

TEST_F(WtsCheck, HealthyDevicePassesEveryStageWithAPress) {
  SimProcess sim(link, {"--pattern", "press", "--press-after", "0", "--seed", "11"});
  ASSERT_TRUE(sim.ready());
  bool prompted = false;
  const CheckRun r = runCheck("--device " + link + kCommon + " --press --press-timeout 60 --json " + json,
                         [&](const std::string& l) {
                           if (contains(l, "Press the whole pad")) {
                             prompted = true;
                             sim.press();
                           }
                         });
  EXPECT_TRUE(prompted) << r.out;
  EXPECT_EQ(r.exit_code, 0) << r.out;
  for (const char* tag : {"[a]", "[b]", "[c]", "[d]", "[e]"}) EXPECT_TRUE(r.verdict(tag, "PASS")) << tag << "\n" << r.out;
  EXPECT_TRUE(contains(r.stage("[a]"), "is a WTS \"WTS0614-34 (simulated)\"")) << r.out;
  EXPECT_TRUE(contains(r.stage("[a]"), "firmware 1.0")) << r.out;
  EXPECT_TRUE(contains(r.stage("[b]"), "150 frames in")) << r.out;
  EXPECT_TRUE(contains(r.stage("[b]"), "0 CRC errors, 0 format errors")) << r.out;
  EXPECT_TRUE(contains(r.stage("[e]"), "84 of 84 taxels rose")) << r.out;
  const std::string j = readFile(json);
  EXPECT_TRUE(contains(j, "\"result\": \"pass\"")) << j;
  EXPECT_TRUE(contains(j, "\"frames\": 150")) << j;
  EXPECT_TRUE(contains(j, "\"dead\": {\"verdict\": \"PASS\"")) << j;
}

TEST_F(WtsCheck, NoisyTaxelFailsTheNoiseStageByName) {
  SimProcess sim(link, {"--pattern", "idle", "--noisy", "4,1=60"});
  ASSERT_TRUE(sim.ready());
  const CheckRun r = runCheck("--device " + link + kCommon + " --json " + json);
  EXPECT_EQ(r.exit_code, 1) << r.out;
  EXPECT_TRUE(r.verdict("[b]", "PASS")) << r.out;
  EXPECT_TRUE(r.verdict("[c]", "FAIL")) << r.out;
  EXPECT_TRUE(r.verdict("[d]", "PASS")) << r.out;
  EXPECT_TRUE(contains(r.out, "noisy taxel(s) above 18 counts: (row 4, col 1) std")) << r.out;
  const std::string j = readFile(json);
  EXPECT_TRUE(contains(j, "\"noisy\": [{\"row\": 4, \"col\": 1,")) << j;
  EXPECT_TRUE(contains(j, "\"result\": \"fail\"")) << j;
}

TEST_F(WtsCheck, StuckTaxelFailsTheStuckStageByName) {
  // 200 counts: below max_tare (409), so only the constant value gives it away
  SimProcess sim(link, {"--pattern", "idle", "--stuck", "0,13=200"});
  ASSERT_TRUE(sim.ready());
  const CheckRun r = runCheck("--device " + link + kCommon + " --json " + json);
  EXPECT_EQ(r.exit_code, 1) << r.out;
  EXPECT_TRUE(r.verdict("[c]", "PASS")) << r.out;
  EXPECT_TRUE(r.verdict("[d]", "FAIL")) << r.out;
  EXPECT_TRUE(contains(r.stage("[d]"), "stuck: (row 0, col 13) constant 200")) << r.out;
  EXPECT_TRUE(contains(readFile(json), "\"stuck\": [{\"row\": 0, \"col\": 13, \"value\": 200.000, \"what\": \"constant\"}]"));
}

TEST_F(WtsCheck, TaxelAtFullScaleFailsStuckAndOffset) {
  SimProcess sim(link, {"--pattern", "idle", "--stuck", "5,0=4095"});
  ASSERT_TRUE(sim.ready());
  const CheckRun r = runCheck("--device " + link + kCommon);
  EXPECT_EQ(r.exit_code, 1) << r.out;
  EXPECT_TRUE(r.verdict("[d]", "FAIL")) << r.out;
  EXPECT_TRUE(contains(r.stage("[d]"), "(row 5, col 0) at full scale 4095")) << r.out;
  EXPECT_TRUE(r.verdict("[c]", "FAIL")) << r.out;  // a tare would be refused
  EXPECT_TRUE(contains(r.out, "no-load offset above max_tare 409 counts: (row 5, col 0) mean 4095")) << r.out;
}

TEST_F(WtsCheck, DeadTaxelIsSilentAtNoLoadAndFailsThePressByName) {
  SimProcess sim(link, {"--pattern", "press", "--press-after", "0", "--dead", "2,5"});
  ASSERT_TRUE(sim.ready());
  const CheckRun r = runCheck("--device " + link + kCommon + " --press --press-timeout 60 --json " + json,
                         [&](const std::string& l) {
                           if (contains(l, "Press the whole pad")) sim.press();
                         });
  EXPECT_EQ(r.exit_code, 1) << r.out;
  EXPECT_TRUE(r.verdict("[c]", "PASS")) << r.out;
  EXPECT_TRUE(r.verdict("[d]", "WARN")) << r.out;
  EXPECT_TRUE(contains(r.stage("[d]"), "silent at no load: (row 2, col 5)")) << r.out;
  EXPECT_TRUE(r.verdict("[e]", "FAIL")) << r.out;
  EXPECT_TRUE(contains(r.stage("[e]"), "83 of 84 taxels rose")) << r.out;
  EXPECT_TRUE(contains(r.stage("[e]"), "dead: (row 2, col 5)")) << r.out;
  EXPECT_TRUE(contains(readFile(json), "\"dead\": [{\"row\": 2, \"col\": 5,"));
}

TEST_F(WtsCheck, NoLoadWithinThePressTimeoutFails) {
  SimProcess sim(link, {"--pattern", "idle"});
  ASSERT_TRUE(sim.ready());
  const CheckRun r = runCheck("--device " + link + kCommon + " --press --press-timeout 0.5");
  EXPECT_EQ(r.exit_code, 1) << r.out;
  EXPECT_TRUE(r.verdict("[d]", "PASS")) << r.out;
  EXPECT_TRUE(r.verdict("[e]", "FAIL")) << r.out;
  EXPECT_TRUE(contains(r.stage("[e]"), "no whole-pad load within")) << r.out;
}

TEST_F(WtsCheck, CrcErrorsFailTheLinkStage) {
  // 5 % of the packets with a wrong CRC: about 8 of 150 frames, against 0.1 %.
  SimProcess sim(link, {"--pattern", "idle", "--bad-crc", "0.05", "--seed", "3"});
  ASSERT_TRUE(sim.ready());
  const CheckRun r = runCheck("--device " + link + kCommon + " --json " + json);
  EXPECT_EQ(r.exit_code, 1) << r.out;
  EXPECT_TRUE(r.verdict("[a]", "PASS")) << r.out;
  EXPECT_TRUE(r.verdict("[b]", "FAIL")) << r.out;
  EXPECT_FALSE(contains(r.stage("[b]"), " 0 CRC errors")) << r.out;
  EXPECT_TRUE(contains(r.out, "bad packets per packet (limit 0.001)")) << r.out;
  EXPECT_TRUE(r.verdict("[c]", "PASS")) << r.out;  // the frames that arrive are intact
  EXPECT_TRUE(contains(readFile(json), "\"link\": {\"verdict\": \"FAIL\""));
}

TEST_F(WtsCheck, ScanFindsTheWtsAmongTheCandidates) {
  SimProcess sim(dir + "/ttyACM7", {"--pattern", "idle"});
  ASSERT_TRUE(sim.ready());
  std::ofstream(dir + "/ttyACM0") << "";  // not a terminal: skipped with its reason
  const CheckRun r = runCheck("--candidates \"" + dir + "/tty*\" --frames 60 --periodic-ms 5 --rate-tolerance 0.5 "
                         "--no-prompt");
  ::unlink((dir + "/ttyACM0").c_str());
  EXPECT_EQ(r.exit_code, 0) << r.out;
  EXPECT_TRUE(contains(r.stage("[a]"), dir + "/ttyACM7 is a WTS")) << r.out;
  EXPECT_TRUE(contains(r.out, dir + "/ttyACM0: cannot open it")) << r.out;
}

TEST_F(WtsCheck, NoDeviceExitsThreeWithWhatToCheck) {
  CheckRun r = runCheck("--device " + dir + "/missing --no-prompt --json " + json);
  EXPECT_EQ(r.exit_code, 3) << r.out;
  EXPECT_TRUE(contains(r.stage("[a]"), "no WTS at " + dir + "/missing")) << r.out;
  EXPECT_TRUE(contains(r.out, "check the USB cable")) << r.out;
  EXPECT_TRUE(contains(readFile(json), "\"result\": \"no_device\"")) << readFile(json);
  r = runCheck("--candidates \"" + dir + "/none*\" --no-prompt");
  EXPECT_EQ(r.exit_code, 3) << r.out;
  EXPECT_TRUE(contains(r.stage("[a]"), "no serial device found")) << r.out;
}

TEST_F(WtsCheck, UsageErrorsExitTwo) {
  for (const char* args : {"--bogus", "--k 0", "--frames", "--seconds -1", "--params /nonexistent.yaml"}) {
    const CheckRun r = runCheck(args);
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.out;
  }
}

TEST(WtsSimTaxelFaults, OutsideThePadIsRefused) {
  const CheckRun r = [] {
    CheckRun x;
    FILE* p = ::popen((kSim + " --dead 6,0 --duration 1 2>&1").c_str(), "r");
    char line[512];
    while (p && std::fgets(line, sizeof line, p) != nullptr) x.out += line;
    const int st = p ? ::pclose(p) : -1;
    x.exit_code = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
    return x;
  }();
  EXPECT_EQ(r.exit_code, 1) << r.out;
  EXPECT_TRUE(contains(r.out, "taxel (6, 0) is outside the 6 x 14 pad")) << r.out;
}
