// The timed-phase state machine (deployments/timed_phase_experiment.osd: edge
// exploration, bent bar, sphere on a table, co-manipulation)
// runs in the servo's real-time thread: its `run` programs and `transitions`
// execute every cycle, so they must not build strings (string literals, `+` on
// strings, operations returning strings such as phaseName()) or print. Only
// entry actions may. Checked on the file's text, block by block.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace {

const std::string kOsd = TACTILE_DEPLOYMENTS_DIR "/timed_phase_experiment.osd";

// The file without // comments (they may quote anything).
std::string code(const std::string& path) {
  std::ifstream in(path);
  EXPECT_TRUE(in.good()) << path;
  std::string line, out;
  while (std::getline(in, line)) {
    const std::size_t c = line.find("//");
    out += (c == std::string::npos ? line : line.substr(0, c)) + "\n";
  }
  return out;
}

struct Block {
  std::string kind, body;
  std::size_t line;
};

// Every `<kind> { ... }` block (braces matched).
std::vector<Block> blocks(const std::string& text, const std::string& kind) {
  std::vector<Block> out;
  std::size_t pos = 0;
  while ((pos = text.find(kind, pos)) != std::string::npos) {
    const bool word_start = pos == 0 || !(std::isalnum(static_cast<unsigned char>(text[pos - 1])) || text[pos - 1] == '_');
    std::size_t b = text.find_first_not_of(" \t\n", pos + kind.size());
    if (!word_start || b == std::string::npos || text[b] != '{') {
      pos += kind.size();
      continue;
    }
    int depth = 0;
    std::size_t e = b;
    for (; e < text.size(); ++e) {
      if (text[e] == '{') ++depth;
      if (text[e] == '}' && --depth == 0) break;
    }
    const std::size_t line = static_cast<std::size_t>(std::count(text.begin(), text.begin() + static_cast<long>(pos), '\n')) + 1;
    out.push_back({kind, text.substr(b, e - b + 1), line});
    pos = e;
  }
  return out;
}

void expectNoStrings(const std::vector<Block>& bs) {
  for (const Block& b : bs) {
    const std::string where = b.kind + " block at line " + std::to_string(b.line);
    EXPECT_EQ(b.body.find('"'), std::string::npos) << where << ": string literal\n" << b.body;
    EXPECT_EQ(b.body.find("print"), std::string::npos) << where << ": printing\n" << b.body;
    EXPECT_EQ(b.body.find("phaseName"), std::string::npos) << where << ": phaseName() returns a string\n" << b.body;
    EXPECT_EQ(b.body.find("result"), std::string::npos) << where << ": the `result` string\n" << b.body;
  }
}

TEST(TimedPhaseExperimentOsd, RunAndTransitionsBuildNoStringsAndDoNotPrint) {
  const std::string text = code(kOsd);
  const std::vector<Block> run = blocks(text, "run"), tr = blocks(text, "transitions");
  EXPECT_GE(run.size(), 3u);  // WAIT_PHASE, IN_PHASE, STOP_MOTION
  EXPECT_GE(tr.size(), 3u);
  expectNoStrings(run);
  expectNoStrings(tr);
  // and the strings are still reported, from entry actions
  const std::vector<Block> entry = blocks(text, "entry");
  EXPECT_GE(entry.size(), 5u);
  bool prints = false;
  for (const Block& b : entry) prints = prints || b.body.find("print.") != std::string::npos;
  EXPECT_TRUE(prints);
}

}  // namespace

namespace {
// The closed-contour state machine (deployments/closed_contour_experiment.osd), the same rule.
TEST(ContourExperimentOsd, RunAndTransitionsBuildNoStringsAndDoNotPrint) {
  const std::string text = code(TACTILE_DEPLOYMENTS_DIR "/closed_contour_experiment.osd");
  const std::vector<Block> run = blocks(text, "run"), tr = blocks(text, "transitions");
  EXPECT_GE(run.size(), 4u);  // WAIT_EXPLORE, EXPLORE, UNWIND, REACQUIRE
  EXPECT_GE(tr.size(), 4u);
  expectNoStrings(run);
  expectNoStrings(tr);
}
}  // namespace
