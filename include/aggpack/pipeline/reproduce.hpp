#pragma once
#include <filesystem>
#include <ostream>
#include <string>

#include <nlohmann/json.hpp>

namespace aggpack {

struct ReproduceOptions {
  bool quick = false;                      // one seed, short DEM and pours, three sensitivity rows: minutes
  int seeds = 0;                           // seeds per case; 0: 3 (1 with quick)
  bool settle_table2 = false;              // also settle seed 1 of every Table 2 mix by DEM (hours)
  bool whole_grading = false;              // also run every Table 2 mix at more sand cut-offs, for its whole grading
  bool resume = false;                     // continue the runs an interrupted reproduce into `out` left checkpoints of
  std::filesystem::path out = "out/reproduce";
  std::filesystem::path examples;          // the shipped scenarios and fu2003_table2.csv
  int threads = 0;
  bool quiet = false;
  std::string command_line;                // as typed, for the report
};

// Runs the paper's Examples 1 and 2 and the eight Table 2 mixes (and a sensitivity study of
// the Table 2 choices the paper does not give) over several seeds, and writes report.md,
// report.html (self-contained), reproduce.json and the figures under `out`. Returns
// reproduce.json's content.
nlohmann::json reproduce(const ReproduceOptions& options, std::ostream& log);

}  // namespace aggpack
