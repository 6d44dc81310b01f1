// aggpack reproduce: the paper's tables, read from the shipped examples/*.csv.
#include "reproduce_parts.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <stdexcept>

#include <fmt/format.h>

#include "aggpack/core/error.hpp"
#include "aggpack/core/text.hpp"

namespace aggpack::reproduction {

namespace {

// Calls row(fields, line number) for every data row of a shipped CSV table (after its
// header; '#' lines and blank lines skipped).
template <class Row>
void for_each_data_row(const fs::path& file, const std::string& what, Row&& row) {
  std::ifstream in(file);
  if (!in) throw InputError(fmt::format("{}: cannot open {} (give --examples DIR)", file.string(), what));
  std::string line;
  bool header = true;
  for (std::size_t number = 1; std::getline(in, line); ++number) {
    if (line.empty() || line[0] == '#') continue;
    if (std::exchange(header, false)) continue;
    row(split_csv_fields(line), number);
  }
}

std::vector<PaperExample> read_examples(const fs::path& file) {
  std::vector<PaperExample> rows;
  for_each_data_row(file, "the paper's examples", [&](const std::vector<std::string>& f, std::size_t number) {
    const auto optional_number = [](const std::string& cell) { return cell.empty() ? kNaN : std::stod(cell); };
    try {
      if (f.size() != 10) throw std::invalid_argument("columns");
      rows.push_back({f[0], f[1], f[2], f[3], f[4], std::stod(f[5]), std::stod(f[6]), std::stod(f[7]),
                      optional_number(f[8]), optional_number(f[9])});
    } catch (const std::exception&) {
      throw InputError(fmt::format("{}:{}: expected id,short_name,title,scenario,figure,after_deposition,after_dem,"
                                   "experiment,box_spread_min_percent,box_spread_max_percent",
                                   file.string(), number));
    }
  });
  for (const char* id : {"example1", "example2"})
    if (std::none_of(rows.begin(), rows.end(), [&](const PaperExample& e) { return e.id == id; }))
      throw InputError(fmt::format("{}: no row for {}", file.string(), id));
  return rows;
}

std::vector<Table2Row> read_table2(const fs::path& file) {
  std::vector<Table2Row> rows;
  for_each_data_row(file, "the paper's Table 2", [&](const std::vector<std::string>& f, std::size_t number) {
    try {
      if (f.size() < 7) throw std::invalid_argument("too few columns");
      rows.push_back({std::stoi(f[0]), f[1], std::stod(f[2]), std::stod(f[3]), std::stod(f[4]), std::stod(f[5]),
                      std::stod(f[6])});
    } catch (const std::exception&) {
      throw InputError(fmt::format("{}:{}: expected mix_id,state,ca_fa,fa_percent,phi_com_mean,phi_com_sd,phi_exp",
                                   file.string(), number));
    }
    // Every number a run or a fit takes (a NaN would pass as a measurement no fit can reach).
    const Table2Row& r = rows.back();
    const auto density = [](double v) { return v > 0.0 && v < 1.0; };
    if (!(r.ca_fa > 0.0 && std::isfinite(r.ca_fa)) || !(r.fa_percent > 0.0 && r.fa_percent < 100.0) ||
        !density(r.paper_mean) || !(r.paper_sd >= 0.0 && r.paper_sd < 1.0) || !density(r.experiment))
      throw InputError(fmt::format("{}:{}: ca_fa {}, fa_percent {}, phi_com_mean {}, phi_com_sd {}, phi_exp {}: "
                                   "expected a positive finite ca_fa, fa_percent between 0 and 100 and densities "
                                   "between 0 and 1",
                                   file.string(), number, f[2], f[3], f[4], f[5], f[6]));
  });
  if (rows.empty()) throw InputError(fmt::format("{}: no rows", file.string()));
  return rows;
}

}  // namespace

ReproduceInputs read_inputs(const fs::path& examples) {
  ReproduceInputs in{examples, read_table2(examples / "fu2003_table2.csv"),
                     read_examples(examples / "fu2003_examples.csv")};
  for (const PaperExample& ex : in.paper)
    if (!fs::exists(examples / ex.scenario))
      throw InputError(fmt::format("{}: not found (give --examples DIR, the folder of the shipped scenarios)",
                                   (examples / ex.scenario).string()));
  for (const Table2Row& row : in.table2) {
    const fs::path f = examples / fmt::format("table2_mix{}.toml", row.mix);
    if (!fs::exists(f)) throw InputError(fmt::format("{}: not found (one scenario per Table 2 mix)", f.string()));
  }
  return in;
}

}  // namespace aggpack::reproduction
