#include <sstream>

#include <gtest/gtest.h>

#include "aggpack/run/progress.hpp"

namespace aggpack {
namespace {

// Characters, as a terminal shows them (a UTF-8 continuation byte takes no column).
std::size_t characters(const std::string& s) {
  std::size_t n = 0;
  for (const unsigned char c : s) n += (c & 0xC0) != 0x80;
  return n;
}

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
  const std::string run = "[12/42] mix 3 sensitivity: number sampling (the paper's Eq. 11) at a sand cut-off of 0.02 in seed 2";
  const std::vector<std::string> fields = {"0.413 s simulated", "density 0.6021",
                                           "kinetic energy 3.2e-04 m g d (quiet below 1e-05)", "max_time 2 s"};
  for (const int columns : {80, 100, 40, 12}) {
    const std::string line = Progress::fit_line(run, "dynamics, layer 2", fields, "about 1 min 20 s left", columns);
    EXPECT_LE(characters(line), static_cast<std::size_t>(columns - 1)) << line;
  }
  // At 80 columns the fields go first, then the middle of the run's name: which run it is (its
  // counter and name, its time left in all), the stage and the time left stay (the run's name
  // went first, and a campaign's line never said which run it was).
  const std::string at80 = Progress::fit_line(run, "dynamics", fields, "about 1 min 20 s left, 14 min in all", 80);
  EXPECT_EQ(at80, "[12/42] mix 3 … 0.02 in seed 2 | dynamics: about 1 min 20 s left, 14 min in all");
  // A campaign's usual run name stays whole at 80 columns; the details make room for it.
  const std::string sweep = Progress::fit_line("[3/14] Fa 25 %, cut 2.54 mm seed 1", "dynamics", fields,
                                               "about 20 s left, 3 min in all", 80);
  EXPECT_EQ(sweep, "[3/14] Fa 25 %, cut 2.54 mm seed 1 | dynamics: about 20 s left, 3 min in all");
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
  for (const std::string& l : refreshes(terminal.str())) EXPECT_LE(characters(l), 79u) << l;
}

// The time left shown moves two fifths of the way to each new estimate, from the last one
// counted down: an estimate 4.5 times too long (a DEM's quiet forecast jumping) moves it by a
// fraction, and estimates that agree are followed.
TEST(Progress, TheTimeLeftDoesNotJumpWithOneEstimate) {
  EXPECT_EQ(Progress::smoothed_time_left(std::nullopt, 0.0, 60.0), 60.0);  // the first is shown as it is
  const double after_spike = Progress::smoothed_time_left(60.0, 1.0, 4.5 * 59.0);
  EXPECT_NEAR(after_spike, 59.0 + Progress::kTimeLeftWeight * (4.5 * 59.0 - 59.0), 1e-9);
  EXPECT_LT(after_spike, 2.5 * 59.0);  // not 4.5 times
  // A steady estimate is followed: counted down, it stays on it.
  double shown = 60.0;
  for (int k = 1; k <= 20; ++k) shown = Progress::smoothed_time_left(shown, 1.0, 60.0 - k);
  EXPECT_NEAR(shown, 40.0, 1e-9);
  // It never goes below zero however long since.
  EXPECT_GE(Progress::smoothed_time_left(5.0, 30.0, 0.0), 0.0);
}

}  // namespace
}  // namespace aggpack
