#include <sstream>

#include <gtest/gtest.h>

#include "aggpack/pipeline/progress.hpp"

namespace aggpack {
namespace {

TEST(Progress, RewritesOneLineAndClearsIt) {
  std::ostringstream terminal;
  Progress progress(terminal);
  progress.set_run("[2/9] Example 1 seed 2");
  progress.start_stage("deposition");
  progress.update("500 of 1733 particles placed", 0.29);
  const std::string line = terminal.str();
  EXPECT_EQ(line, "\r[2/9] Example 1 seed 2 | deposition: 500 of 1733 particles placed");
  progress.update("600 of 1733 particles placed", 0.35);  // within 0.2 s of the last: not printed
  EXPECT_EQ(terminal.str(), line);
  progress.clear();
  const std::string cleared = terminal.str().substr(line.size());
  std::string blank(1, '\r');
  blank.append(line.size() - 1, ' ');
  blank.push_back('\r');
  EXPECT_EQ(cleared, blank);
}

}  // namespace
}  // namespace aggpack
