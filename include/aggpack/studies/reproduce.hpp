#pragma once
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

namespace aggpack {

// Two materials' blends predicted from their own lab numbers (aggpack blend's lab route, above the
// studies: the caller computes it, blends/materials_curve.hpp), for the report's Table 2 section.
struct MaterialsCurve {
  std::string coarse, fine;  // the materials' names
  std::string process;       // the lab process of CPM's K
  double compaction_index = 0.0;
  std::vector<std::string> betas;  // each material's betas, in a sentence
  std::vector<double> fa_percent;  // the fine's volume percent
  std::vector<double> packing;     // CPM's packing fraction there
};

struct ReproduceOptions {
  bool quick = false;                      // one seed, short DEM and pours, three sensitivity rows: minutes
  int seeds = 0;                           // seeds per case; 0: 3 (1 with quick)
  bool settle_table2 = false;              // also settle seed 1 of every Table 2 mix by DEM (hours)
  bool whole_grading = false;              // also run every Table 2 mix at more sand cut-offs, for its whole grading
  bool calibrated_table2 = false;          // also predict Table 2 from one calibration mix (stone and sand)
  bool shaped_table2 = false;              // also run Table 2 with the stone as rigid grains of a stated shape
  bool resume = false;                     // continue the runs an interrupted reproduce into `out` left checkpoints of
  std::filesystem::path out = "out/reproduce";
  std::filesystem::path examples;          // the shipped scenarios and fu2003_table2.csv
  int threads = 0;
  bool quiet = false;
  std::string command_line;                // as typed, for the report
  std::optional<MaterialsCurve> table2_materials;  // the shipped stone and sand's curve beside Table 2
};

// What `reproduce` would run with these options (`aggpack reproduce --dry-run`): the same
// count its campaign announces, from the same plan.
struct ReproducePlan {
  std::filesystem::path examples;                          // the scenarios' folder, absolute
  int seeds = 0;                                           // per case
  std::vector<std::pair<std::string, std::size_t>> cases;  // each case and its runs over the seeds
  std::size_t runs = 0;                                    // in all
};

// Reads the paper's tables in `options.examples` and checks that every scenario is there, as
// reproduce does before its first run (InputError naming the missing file); runs nothing.
ReproducePlan plan_reproduce(const ReproduceOptions& options);
// The plan in lines: "examples: DIR", one line per case, "runs: N (...)".
std::string describe(const ReproducePlan& plan);

// Runs the paper's Examples 1 and 2 and the eight Table 2 mixes (and a sensitivity study of
// the Table 2 choices the paper does not give) over several seeds, and writes report.md,
// report.html (self-contained), reproduce.json and the figures under `out`. Returns
// reproduce.json's content.
nlohmann::json reproduce(const ReproduceOptions& options, std::ostream& log);

}  // namespace aggpack
