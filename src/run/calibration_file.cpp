#include "aggpack/run/calibration_file.hpp"

#include <cmath>
#include <cstdint>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "aggpack/core/error.hpp"
#include "aggpack/core/input_file.hpp"
#include "aggpack/io/dem_calibration_file.hpp"

namespace aggpack {

namespace {
// What a JSON value is, for a message: "a string", "an empty array", "an array of 3 elements".
std::string described(const nlohmann::json& v) {
  if (v.is_array())
    return v.empty() ? "an empty array" : fmt::format("an array of {} element{}", v.size(), v.size() == 1 ? "" : "s");
  if (v.is_null()) return "null";
  const std::string type = v.type_name();
  return fmt::format("{} {}", type == "object" || type == "array" ? "an" : "a", type);
}
}  // namespace

ModelParameters parse_calibration(std::string_view text, const std::filesystem::path& file) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(fmt::format("{}: not JSON: {}", file.string(), e.what()));
  }
  // Every value is tested for presence and type before it is read (a file is user input).
  const auto fail = [&](std::string_view key, const std::string& what) {
    return InputError(fmt::format("{}: {}: {}", file.string(), key, what));
  };
  const auto kind = j.is_object() ? j.find("kind") : j.end();
  if (is_dem_calibration_text(text))
    throw InputError(fmt::format("{}: a DEM calibration (aggpack calibrate --dem): it sets contact parameters the DEM "
                                 "uses, which the analytic models do not have; give it to run, sweep or whole-grading "
                                 "(--calibration, or calibrated_by in the scenario); CPM's K and beta come from "
                                 "aggpack calibrate without --dem",
                                 file.string()));
  if (kind == j.end() || !kind->is_string() || kind->get_ref<const std::string&>() != "aggpack CPM calibration")
    throw InputError(fmt::format("{}: not a calibration written by aggpack calibrate (expected \"kind\": \"aggpack CPM "
                                 "calibration\")",
                                 file.string()));
  const auto cpm = j.find("cpm");
  if (cpm == j.end() || !cpm->is_object())
    throw fail("cpm", fmt::format("{}; expected an object of K and beta with their ranges",
                                  cpm == j.end() ? std::string("missing") : described(*cpm)));
  const auto number = [&](const char* key) {
    const auto v = cpm->find(key);
    if (v == cpm->end() || !v->is_number())
      throw fail(fmt::format("cpm.{}", key),
                 fmt::format("{}; expected a number", v == cpm->end() ? std::string("missing") : described(*v)));
    return v->get<double>();
  };
  // A range is [low, high], null where unbounded (what calibrate writes); it is shown with the value.
  const auto range = [&](const char* key) {
    const auto r = cpm->find(key);
    const std::string name = fmt::format("cpm.{}", key);
    if (r == cpm->end() || !r->is_array() || r->size() != 2)
      throw fail(name, fmt::format("{}; expected [low, high], two numbers (null: unbounded)",
                                   r == cpm->end() ? std::string("missing") : described(*r)));
    for (std::size_t i = 0; i < 2; ++i)
      if (!r->at(i).is_null() && !r->at(i).is_number())
        throw fail(fmt::format("{}[{}]", name, i), fmt::format("{}; expected a number or null", described(r->at(i))));
    const auto bound = [&](std::size_t i, const char* none) {
      return r->at(i).is_null() ? std::string(none) : fmt::format("{:.3g}", r->at(i).get<double>());
    };
    return fmt::format("{} to {}", bound(0, "?"), bound(1, "unbounded"));
  };
  // Provenance, shown with the values: optional, but of its type when present.
  const auto text_of = [&](const char* key) {
    const auto v = j.find(key);
    if (v == j.end()) return std::string("?");
    if (!v->is_string()) throw fail(key, fmt::format("{}; expected a string", described(*v)));
    return v->get<std::string>();
  };
  const auto seeds = j.find("seeds");
  if (seeds != j.end() && !seeds->is_number_unsigned())
    throw fail("seeds", fmt::format("{}; expected a count of seeds", described(*seeds)));

  ModelParameters p;
  p.compaction_index = number("compaction_index");
  p.beta = number("residual_packing_density");
  const std::string from = fmt::format("calibrated by aggpack calibrate ({}) from {} ({}; {} seeds)", file.string(),
                                       text_of("scenario_file"), text_of("protocol"),
                                       seeds == j.end() ? std::uint64_t{0} : seeds->get<std::uint64_t>());
  p.compaction_source = fmt::format("{}; range {}", from, range("compaction_index_range"));
  p.beta_source = fmt::format("{}; range {}", from, range("residual_packing_density_range"));
  if (!(p.compaction_index > 0.0 && std::isfinite(p.compaction_index)) || !(p.beta > 0.0 && p.beta < 1.0))
    throw InputError(fmt::format("{}: K = {} and beta = {} are not a calibration (K > 0, 0 < beta < 1)", file.string(),
                                 p.compaction_index, p.beta));
  return p;
}

ModelParameters read_calibration(const std::filesystem::path& file) {
  return parse_calibration(read_input_text(file, "the calibration", kDefaultMaxInputFileBytes), file);
}

}  // namespace aggpack
