// The scenario as the Python module keeps it: its text, the file it is (said to be) and its
// overrides, from which a run's checkpoint can make it again, and the scenario as read.
#pragma once
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "aggpack/io/scenario.hpp"

namespace aggpack::python {

struct PyScenario {
  std::string text;
  std::filesystem::path file;
  ScenarioOverrides overrides;
  Scenario parsed;

  static PyScenario from_text(std::string text, const std::filesystem::path& file, const std::vector<std::string>& set,
                              std::optional<std::uint64_t> seed);
  [[nodiscard]] PyScenario with(const std::vector<std::string>& set, std::optional<std::uint64_t> seed) const;
};

}  // namespace aggpack::python
