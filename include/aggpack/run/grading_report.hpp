#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "aggpack/core/option_names.hpp"
#include "aggpack/grains/grain_library.hpp"
#include "aggpack/sizes/grading.hpp"
#include "aggpack/sizes/grading_sampler.hpp"

namespace aggpack {

// What `aggpack grading` prints: a grading (a shipped name or a CSV file), its cut-offs, its
// band check, and optionally its blend with a fine grading at a coarse/fine volume ratio.
struct GradingQuery {
  std::string grading;                  // a shipped name or a CSV file
  std::optional<std::string> fine;      // a second grading, for a mix
  std::optional<double> ca_fa;          // coarse/fine volume ratio of the mix: given with `fine`, never guessed
  std::optional<std::string> band;      // a shipped band to check the grading (or the mix) against
  std::optional<double> d_min, d_max;   // cut-offs, m
  std::optional<double> length_unit;    // metres per unit of a bare `opening` column in files
  std::optional<GrainShapeSpec> shape;  // --shape: the grading's (the coarse one's) grains
  std::uint64_t seed = 1;               // of the sizes and templates --shape draws
  OptionStyle named = OptionStyle::Cli;  // the options in messages: the CLI's flags or Python's keywords
  LibraryWatch watch;                    // told of --shape's templates as they are made (a stop honoured there)
};

// A shipped grading by name, or a CSV sieve analysis (`length_unit` metres per unit of a bare
// `opening` column, see read_grading_csv). InputError naming both when it is neither.
Grading load_grading(const std::string& name_or_file, std::optional<double> length_unit = std::nullopt);

// The band check as JSON: { name, all_inside, sieves[] { sieve, opening_m, min_percent,
// max_percent, percent, inside } } (summary.json and `aggpack grading --json`).
nlohmann::json band_check_json(const Band& band, const BandCheck& check);

// The openings make_grading moved to the standard sieve series: [{ sieve, given_m,
// standard_m }], and that list in words for the output (empty when none moved).
nlohmann::json snapped_sieves_json(const Grading& grading);
std::string snapped_sieves_text(const std::vector<SnappedSieve>& snapped);

// With --shape: grains as a run of the grading makes them (drawn and fitted as its first
// component's, from the same seed), and what they measure. The sizes are the command's own
// sample of the grading (cut at --d-min and --d-max), drawn by mass: a run fits on its own
// sample, so its templates may differ slightly.
struct GradingShape {
  GrainLibrary library;
  std::uint64_t seed = 1;
  std::size_t sampled = 0;         // sizes drawn
  std::vector<double> fit_sizes;   // the intermediate sizes fitted on and measured at, m
  ShapeStatistics templates;       // every template at every one of those sizes (percentages by mass)
};

// What `aggpack grading` found: the grading, the fine one and their blend, the cut-offs and
// the band check.
struct GradingDescription {
  Grading grading;
  std::optional<Grading> fine, mix;  // with --mix: the fine grading and the blend at ca_fa
  double ca_fa = 1.0;
  std::optional<GradingCut> cut;     // with --d-min or --d-max, of the checked curve
  std::optional<Band> band;          // with --band
  BandCheck band_check;
  std::optional<GradingShape> shape;  // with --shape
  // The curve the cut-offs and the band apply to: the blend with --mix, else the grading.
  [[nodiscard]] const Grading& checked() const { return mix ? *mix : grading; }
};

// Throws InputError for unknown names, bad files and cut-offs that leave nothing.
GradingDescription describe_grading(const GradingQuery& query);
nlohmann::json to_json(const GradingDescription& description);  // `aggpack grading --json`
std::string format_grading(const GradingDescription& description);

}  // namespace aggpack
