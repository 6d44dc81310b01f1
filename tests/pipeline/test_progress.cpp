#include <sstream>

#include <gtest/gtest.h>

#include "aggpack/pipeline/progress.hpp"

namespace aggpack {
namespace {

// The pieces written between carriage returns, with the erase-to-end-of-line code removed.
std::vector<std::string> refreshes(const std::string& terminal) {
  std::vector<std::string> lines;
  std::size_t start = 0;
  while ((start = terminal.find('\r', start)) != std::string::npos) {
    const std::size_t end = terminal.find('\r', start + 1);
    std::string line = terminal.substr(start + 1, end == std::string::npos ? std::string::npos : end - start - 1);
    const auto erase = line.find("\033[K");
    EXPECT_NE(erase, std::string::npos) << "every refresh erases what an older, longer line left";
    lines.push_back(line.substr(0, erase));
    start = start + 1;
  }
  return lines;
}

TEST(Progress, RewritesOneLineAndClearsIt) {
  std::ostringstream terminal;
  Progress progress(terminal, 120);
  progress.set_run("[2/9] Example 1 seed 2");
  progress.start_stage("deposition");
  progress.update({"500 of 1733 particles placed"}, 0.29);
  const std::string line = terminal.str();
  EXPECT_EQ(line, "\r[2/9] Example 1 seed 2 | deposition: 500 of 1733 particles placed\033[K");
  progress.update({"600 of 1733 particles placed"}, 0.35);  // within 0.2 s of the last: not printed
  EXPECT_EQ(terminal.str(), line);
  progress.clear();
  EXPECT_EQ(terminal.str().substr(line.size()), "\r\033[K");
}

// A 113-character line in a 100-column terminal wrapped at every refresh and left a stale
// line behind each time (318 in one Example 2 run).
TEST(Progress, EveryLineFitsAnEightyColumnTerminal) {
  const std::string run = "[12/42] mix 3 sensitivity: number sampling (the paper's Eq. 11) seed 2 (about 14 min left in all)";
  const std::vector<std::string> fields = {"0.413 s simulated", "density 0.6021",
                                           "kinetic energy 3.2e-04 m g d (quiet below 1e-05)", "max_time 2 s"};
  for (const int columns : {80, 100, 40, 12}) {
    const std::string line = Progress::fit_line(run, "dynamics, layer 2", fields, "about 1 min 20 s left", columns);
    EXPECT_LE(line.size(), static_cast<std::size_t>(columns - 1)) << line;
  }
  // At 80 columns the least important fields go first; the stage, the time and the time left stay.
  const std::string at80 = Progress::fit_line(run, "dynamics", fields, "about 1 min 20 s left", 80);
  EXPECT_EQ(at80, "dynamics: 0.413 s simulated, density 0.6021, about 1 min 20 s left");
  // Wide enough: everything.
  const std::string wide = Progress::fit_line("[1/2] x", "dynamics", fields, "about 5 s left", 200);
  EXPECT_EQ(wide, "[1/2] x | dynamics: 0.413 s simulated, density 0.6021, kinetic energy 3.2e-04 m g d (quiet "
                  "below 1e-05), max_time 2 s, about 5 s left");
  // Characters, not bytes: a ± takes one column.
  EXPECT_EQ(Progress::fit_line("", "s", {"0.70 ± 0.01"}, "", 15), "s: 0.70 ± 0.01");

  // Through the object, at a fixed width of 80 columns.
  std::ostringstream terminal;
  Progress progress(terminal, 80);
  progress.set_run(run);
  progress.start_stage("dynamics");
  progress.update(fields, 0.5);
  for (const std::string& l : refreshes(terminal.str())) EXPECT_LE(l.size(), 79u) << l;
}

}  // namespace
}  // namespace aggpack
