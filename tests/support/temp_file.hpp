// A scratch file for a test: gtest's TempDir(), the name made unique per
// process and call (ctest runs test cases of one binary in parallel, and a
// binary may run several times at once).
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <fstream>
#include <string>

namespace tactile {
namespace test {

inline std::string writeTempFile(const std::string& name, const std::string& text) {
  static std::atomic<int> counter{0};
  const std::string path = ::testing::TempDir() + "tactile_" + std::to_string(::getpid()) + "_" +
                           std::to_string(counter++) + "_" + name;
  std::ofstream(path) << text;
  return path;
}

}  // namespace test
}  // namespace tactile
