#pragma once
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "aggpack/sizes/grading.hpp"

namespace aggpack {

// What `aggpack grading` prints: a grading (a shipped name or a CSV file), its cut-offs, its
// band check, and optionally its blend with a fine grading at a coarse/fine volume ratio.
struct GradingQuery {
  std::string grading;                  // a shipped name or a CSV file
  std::optional<std::string> fine;      // a second grading, for a mix
  double ca_fa = 1.0;                   // coarse/fine volume ratio of the mix
  std::optional<std::string> band;      // a shipped band to check the grading (or the mix) against
  std::optional<double> d_min, d_max;   // cut-offs, m
  double length_unit = 0.0254;          // metres per unit of an `opening` column in files
};

// The band check as JSON: { name, all_inside, sieves[] { sieve, opening_m, min_percent,
// max_percent, percent, inside } } (summary.json and `aggpack grading --json`).
nlohmann::json band_check_json(const Band& band, const BandCheck& check);

// The openings make_grading moved to the standard sieve series: [{ sieve, given_m,
// standard_m }], and that list in words for the output (empty when none moved).
nlohmann::json snapped_sieves_json(const Grading& grading);
std::string snapped_sieves_text(const nlohmann::json& snapped_sieves);

// Throws InputError for unknown names, bad files and cut-offs that leave nothing.
nlohmann::json describe_grading(const GradingQuery& query);
std::string format_grading(const nlohmann::json& description);

}  // namespace aggpack
