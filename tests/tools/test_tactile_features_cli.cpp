// tactile_features CLI: JSON per frame, malformed lines reported and skipped,
// exit codes.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace {

struct CliRun {
  int code;
  std::string out, err;
};

CliRun run(const std::string& args) {
  const std::string errFile = testing::TempDir() + "cli_stderr.txt";
  const std::string cmd = std::string(TACTILE_FEATURES_BIN) + " " + args + " 2>" + errFile;
  CliRun r{};
  FILE* p = popen(cmd.c_str(), "r");
  char buf[4096];
  std::size_t n;
  while ((n = fread(buf, 1, sizeof buf, p)) > 0) r.out.append(buf, n);
  const int st = pclose(p);
  r.code = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  std::ifstream e(errFile);
  std::stringstream ss;
  ss << e.rdbuf();
  r.err = ss.str();
  return r;
}

std::string frameLine(double peak, int row, int col) {
  std::string s;
  for (int r = 0; r < 6; ++r)
    for (int c = 0; c < 14; ++c) {
      if (!s.empty()) s += ",";
      s += (r == row && c == col) ? std::to_string(peak) : (r == row && (c == col + 1 || c == col - 1) ? "0.5" : "0");
    }
  return s;
}

std::vector<std::string> lines(const std::string& s) {
  std::vector<std::string> v;
  std::stringstream ss(s);
  std::string l;
  while (std::getline(ss, l)) v.push_back(l);
  return v;
}

}  // namespace

TEST(TactileFeaturesCli, WritesOneJsonObjectPerFrameWithAllKeys) {
  const std::string file = testing::TempDir() + "frames_ok.csv";
  std::ofstream(file) << "# comment\n" << frameLine(2.0, 2, 6) << "\n\n" << frameLine(1.0, 4, 10) << "\n";
  const CliRun r = run(file);
  EXPECT_EQ(r.code, 0) << r.err;
  const auto out = lines(r.out);
  ASSERT_EQ(out.size(), 2u);
  for (const char* key : {"\"cop_x\":", "\"cop_y\":", "\"coc_x\":", "\"coc_y\":", "\"dzmp_x\":", "\"dzmp_y\":",
                          "\"alpha_z\":", "\"force\":", "\"d_z\":", "\"lambda1\":", "\"lambda2\":", "\"area\":",
                          "\"max_taxel\":", "\"contact\":", "\"status\":"})
    EXPECT_NE(out[0].find(key), std::string::npos) << key;
  // Row 2, col 6 with equal neighbours: CoP exactly at that taxel (x = -0.5 pitch).
  EXPECT_NE(out[0].find("\"cop_x\":-0.0017,"), std::string::npos) << out[0];
  EXPECT_NE(out[0].find("\"force\":3,"), std::string::npos) << out[0];
  // Three taxels in a row are a blob, not an edge (edge_min_length = 2.5 pitches).
  EXPECT_NE(out[0].find("\"contact\":\"point\""), std::string::npos) << out[0];
}

TEST(TactileFeaturesCli, MalformedLinesAreNamedSkippedAndFailTheExitCode) {
  const std::string file = testing::TempDir() + "frames_bad.csv";
  std::string shortLine = frameLine(2.0, 2, 6);
  shortLine = shortLine.substr(0, shortLine.rfind(','));  // 83 values
  std::ofstream(file) << frameLine(2.0, 2, 6) << "\n"
                      << shortLine << "\n"
                      << "1,2,abc\n"
                      << "nan," << frameLine(2.0, 2, 6).substr(2) << "\n"
                      << frameLine(1.0, 1, 3) << "\n";
  const CliRun r = run(file);
  EXPECT_EQ(r.code, 1);
  EXPECT_EQ(lines(r.out).size(), 2u) << "good lines before and after the bad ones are processed";
  EXPECT_NE(r.err.find(":2: expected 84 values, got 83"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(":3: value 3 is not a number"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(":4: frame rejected: invalid_input"), std::string::npos) << r.err;
}

TEST(TactileFeaturesCli, OptionsAndUsageErrors) {
  const std::string file = testing::TempDir() + "frames_small.csv";
  std::ofstream(file) << "0,1,0,0\n";
  CliRun r = run("--rows 2 --cols 2 --pitch 0.01 --threshold otsu " + file);
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("\"cop_x\":0.005,"), std::string::npos) << r.out;
  r = run("--pitch -1 " + file);
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("features.pitch"), std::string::npos) << r.err;
  r = run("--bogus " + file);
  EXPECT_EQ(r.code, 2);
  r = run("/nonexistent/file.csv");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("cannot open"), std::string::npos);
}

TEST(TactileFeaturesCli, ShippedSampleRecordingIsClean) {
  const CliRun r = run(TACTILE_SAMPLE_CSV);
  EXPECT_EQ(r.code, 0) << r.err;
  const auto out = lines(r.out);
  EXPECT_GE(out.size(), 200u);
  int edges = 0, points = 0;
  for (const auto& l : out) {
    edges += l.find("\"contact\":\"edge\"") != std::string::npos;
    points += l.find("\"contact\":\"point\"") != std::string::npos;
  }
  EXPECT_GT(edges, 50);
  EXPECT_GT(points, 50);
}
