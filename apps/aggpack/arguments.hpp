#pragma once
// The command line's own values (lengths, seeds, counts, lists), read with messages that name
// the option and say what it expects; each throws aggpack::InputError (exit code 2).
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "aggpack/core/box.hpp"
#include "aggpack/io/scenario.hpp"

// A length given on the command line; a bare number is in `bare_unit` (metres per unit).
double length_argument(const std::string& text, const std::string& option, long double bare_unit = 1.0L);
// A seed in the range a scenario's `seed` takes, 0 to 2^63 - 1: never wrapped or saturated.
std::uint64_t seed_argument(const std::string& text);
// A number above 0.
double positive_argument(const std::string& text, const std::string& option);
// A count of 1 or more, such as a number of seeds.
int count_argument(const std::string& text, const std::string& option);
// A wall-clock interval in seconds, >= 0, as the TOML value of output.checkpoint_every.
std::string seconds_argument(const std::string& text);
// The parts of "a,b,c", each as typed (without blanks around it).
std::vector<std::string> list_parts(const std::string& text);
// "a,b,c" as finite numbers, naming `option` in errors.
std::vector<double> numbers_argument(const std::string& text, const std::string& option);
// "a,b,c" as lengths (bare numbers in `bare_unit` metres), naming `option` in errors.
std::vector<double> lengths_argument(const std::string& text, const std::string& option, long double bare_unit = 1.0L);
// --box xmin,ymin,zmin,xmax,ymax,zmax (bare numbers in `bare_unit` metres).
aggpack::Box box_argument(const std::string& text, long double bare_unit);

// --calibration FILE, once or more: the DEM calibrations (calibrate --dem) as one
// `calibrated_by = [...]` assignment for the scenario (absolute paths: the scenario's folder does
// not anchor them), and CPM's calibration (calibrate without --dem), at most one.
struct CalibrationArguments {
  std::optional<std::string> calibrated_by;  // "calibrated_by=[\"/abs/a.json\", ...]"
  std::string typed;                         // the options as typed, for messages
  std::optional<std::filesystem::path> cpm;
};
CalibrationArguments calibration_arguments(const std::vector<std::string>& files);
// A file path as a TOML string (absolute), for an assignment made from an option.
std::string toml_path(const std::filesystem::path& file);
// `run --calibration`: DEM calibrations into calibrated_by, CPM's into models.calibration.
void add_run_calibrations(const std::vector<std::string>& files, aggpack::ScenarioOverrides& overrides);
