// [[protocol]]: the steps in order, each checked against the tables that give its settings.
#include <cstdint>
#include <limits>
#include <set>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include <fmt/format.h>

#include "aggpack/core/overloaded.hpp"
#include "scenario_tables.hpp"

namespace aggpack {

namespace {

// What the steps read so far have settled, for the checks of the steps after them.
struct ProtocolReading {
  const std::vector<TomlSection>& entries;
  const Scenario& sc;
  Protocol protocol{};
  std::optional<std::uint32_t> layers{};  // every deposit step's `layers`
  std::vector<std::size_t> deposited_by{};  // the entry that deposits each part (+1; 0: none yet)
  std::size_t settles = 0, deposits = 0, pours = 0, taps = 0, rods = 0, jigs = 0;
  std::vector<std::size_t> export_entries{};  // the entries of the export_lammps steps, in order
  // The names taken by each kind of step, looked up in a set: a scenario of 16 MiB holds
  // some 3x10^5 steps, and comparing each with all before it took minutes.
  std::set<std::string> export_names{}, snapshot_names{}, analyse_names{};

  // The stage a step belongs to when it has none of its own: the one before it.
  [[nodiscard]] std::string stage_before() const {
    return protocol.steps.empty() ? std::string("input") : protocol.steps.back().stage;
  }
};

// A name that can name a file or a folder as it is.
bool is_file_name(const std::string& name) {
  constexpr std::string_view kAllowed = "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-";
  return !name.empty() && name.find_first_not_of(kAllowed) == std::string::npos;
}

// A deposit or pour step (`kind`): one part of the drop sequence, placed once.
void read_deposit_step(ProtocolReading& r, std::size_t i, const std::string& kind) {
  const TomlSection& e = r.entries[i];
  const Scenario& sc = r.sc;
  e.allow_only({"step", "layer", "layers"});
  if (kind == "deposit" && !sc.deposition)
    e.fail("step", "a deposit step places generated particles with the [deposition] settings; add a "
                   "[deposition] table (it may be empty) and give particles by size");
  if (kind == "pour" && !sc.pour)
    e.fail("step", "a pour step inserts generated particles with the [pour] settings; add a [pour] table "
                   "(it may be empty) and give particles by size");
  if (kind == "pour" && !sc.dynamics)
    e.fail("step", "a pour falls through the DEM with the [dynamics] settings; add a [dynamics] table");
  DepositStep d;
  d.layers = static_cast<std::uint32_t>(e.integer("layers", 1, 10000).value_or(1));
  if (r.layers && *r.layers != d.layers)
    e.fail("layers", fmt::format("every deposit and pour step splits the drop sequence alike; an earlier one has "
                                 "layers = {}, this one {}",
                                 *r.layers, d.layers));
  d.layer = static_cast<std::uint32_t>(e.integer("layer", 0, d.layers - 1).value_or(0));
  r.layers = d.layers;
  r.deposited_by.resize(d.layers, 0);
  if (r.deposited_by[d.layer] != 0)
    e.fail("layer", fmt::format("part {} of {} is already deposited by {}", d.layer, d.layers,
                                r.entries[r.deposited_by[d.layer] - 1].path()));
  r.deposited_by[d.layer] = i + 1;
  if (kind == "pour") {
    r.protocol.steps.push_back({"pour", PourStep{d.layer, d.layers}});
    ++r.pours;
  } else {
    r.protocol.steps.push_back({"deposition", d});
    ++r.deposits;
  }
}

void read_settle_step(ProtocolReading& r, const TomlSection& e) {
  e.allow_only({"step", "layer"});
  if (!r.sc.dynamics) e.fail("step", "a settle step takes its settings from a [dynamics] table; add one");
  SettleStep st;
  st.layer = static_cast<std::uint32_t>(e.integer("layer", 0, r.layers.value_or(1) - 1).value_or(0));
  ++r.settles;
  r.protocol.steps.push_back({"dynamics", st});
}

void read_tap_step(ProtocolReading& r, const TomlSection& e) {
  e.allow_only({"step"});
  if (!r.sc.tapping) e.fail("step", "a tap step takes its settings from a [tapping] table; add one");
  if (!r.sc.dynamics) e.fail("step", "a tap step moves the bed through the DEM of a [dynamics] table; add one");
  ++r.taps;
  r.protocol.steps.push_back({"tapping", TapStep{}});
}

// A rod or jig step (`kind`): aggpack's DEM moves the bed with the settings of its table.
void read_compaction_step(ProtocolReading& r, const TomlSection& e, const std::string& kind) {
  e.allow_only({"step"});
  const bool rod = kind == "rod";
  const char* table = rod ? "rodding" : "jigging";
  if (rod ? !r.sc.rodding : !r.sc.jigging)
    e.fail("step", fmt::format("a {} step takes its settings from a [{}] table; add one", kind, table));
  if (!r.sc.dynamics) e.fail("step", fmt::format("a {} step moves the bed through the DEM of a [dynamics] table; add one", kind));
  if (rod) {
    ++r.rods;
    r.protocol.steps.push_back({"rodding", RodStep{}});
  } else {
    ++r.jigs;
    r.protocol.steps.push_back({"jigging", JigStep{}});
  }
}

void read_export_lammps_step(ProtocolReading& r, std::size_t i) {
  const TomlSection& e = r.entries[i];
  e.allow_only({"step", "name"});
  if (!r.sc.dynamics)
    e.fail("step", "an export_lammps step writes a deck of the DEM step after it, with the [dynamics] settings; "
                   "add a [dynamics] table");
  const std::string name = e.required(e.string("name"), "name", "the name of its folder, <output>/lammps/<name>");
  if (!is_file_name(name)) e.fail("name", "expected letters, digits, '_' or '-' (it names a folder)");
  if (!r.export_names.insert(name).second)
    e.fail("name", fmt::format("another export_lammps step is already named \"{}\"", name));
  // Its deck is of the next DEM step, filled in by link_exports; it belongs to the stage before it.
  r.protocol.steps.push_back({r.stage_before(), ExportLammpsStep{name, {}}});
  r.export_entries.push_back(i);
}

void read_import_lammps_step(ProtocolReading& r, const TomlSection& e) {
  e.allow_only({"step", "file", "timestep"});
  const std::string file =
      e.required(e.string("file"), "file", "the LAMMPS dump or data file to take the positions from");
  const std::filesystem::path path = input_file_at(e, "file", r.sc.file.parent_path(), file, "the LAMMPS file");
  ImportLammpsStep import{path, std::nullopt};
  if (e.has("timestep")) import.timestep = e.integer("timestep", 0, std::numeric_limits<std::int64_t>::max());
  r.protocol.steps.push_back({"import_lammps", import});
}

void read_snapshot_step(ProtocolReading& r, const TomlSection& e) {
  e.allow_only({"step", "name"});
  const std::string name = e.required(e.string("name"), "name", "the name of its file, particles_<name>.csv");
  if (!is_file_name(name)) e.fail("name", "expected letters, digits, '_' or '-' (it names a file)");
  if (!r.snapshot_names.insert(name).second)
    e.fail("name", fmt::format("another snapshot step is already named \"{}\"", name));
  // A snapshot belongs to the stage before it: --stop-after that stage keeps it.
  r.protocol.steps.push_back({r.stage_before(), SnapshotStep{name}});
}

void read_analyse_step(ProtocolReading& r, const TomlSection& e) {
  e.allow_only({"step", "name"});
  const std::string name =
      e.required(e.string("name"), "name", "the name of its results in summary.json (stages.<name>)");
  if (name.empty() || name == "dynamics")
    e.fail("name", "expected a name other than \"dynamics\" (whose density is the final analysis)");
  if (!r.analyse_names.insert(name).second)
    e.fail("name", fmt::format("another analyse step is already named \"{}\"", name));
  r.protocol.steps.push_back({name, AnalyseStep{name}});
}

// Each export_lammps step's deck is of the first DEM step after it: one pass from the last
// step back (a search forward from each export was quadratic in the steps).
void link_exports(ProtocolReading& r) {
  std::optional<DemStep> next;
  std::optional<std::size_t> unfollowed;  // the first export_lammps entry that no DEM step follows
  std::size_t exports_left = r.export_entries.size();
  for (std::size_t j = r.protocol.steps.size(); j-- > 0;)
    std::visit(Overloaded{[&](const SettleStep& s) { next = s; }, [&](const PourStep& s) { next = s; },
                          [&](const TapStep& s) { next = s; },
                          // No deck rods or jigs: an export whose next DEM step is one has none.
                          [&](const RodStep&) { next.reset(); }, [&](const JigStep&) { next.reset(); },
                          [&](ExportLammpsStep& step) {
                            --exports_left;
                            if (next) step.next = *next;
                            else unfollowed = r.export_entries[exports_left];
                          },
                          [](const auto&) {}},
               r.protocol.steps[j].kind);
  if (unfollowed)
    r.entries[*unfollowed].fail("step", "an export_lammps step writes a deck of the DEM step after it (settle, pour "
                                        "or tap), and none follows (a rod or jig step has no LAMMPS deck)");
}

// Every stage's table is used by a step, and every part of the drop sequence is placed.
void check_tables_used(const TomlSection& root, const ProtocolReading& r) {
  const Scenario& sc = r.sc;
  if (sc.deposition && r.deposits == 0)
    root.fail("protocol", "[deposition] is given but no deposit step places the particles");
  if (sc.pour && r.pours == 0) root.fail("protocol", "[pour] is given but no pour step places the particles");
  for (std::size_t k = 0; k < r.deposited_by.size(); ++k)
    if (r.deposited_by[k] == 0)
      root.fail("protocol", fmt::format("no deposit or pour step places part {} of {}: each part is placed once", k,
                                        r.deposited_by.size()));
  if (sc.tapping && r.taps == 0) root.fail("protocol", "[tapping] is given but no tap step uses it");
  if (sc.rodding && r.rods == 0) root.fail("protocol", "[rodding] is given but no rod step uses it");
  if (sc.jigging && r.jigs == 0) root.fail("protocol", "[jigging] is given but no jig step uses it");
  if (sc.dynamics && r.settles == 0 && r.pours == 0 && r.taps == 0 && r.rods == 0 && r.jigs == 0)
    root.fail("protocol", "[dynamics] is given but no settle, pour, tap, rod or jig step uses it");
}

}  // namespace

Protocol read_protocol(const TomlSection& root, const std::vector<TomlSection>& entries, const Scenario& sc) {
  if (entries.empty()) root.fail("protocol", "expected at least one step");
  if (sc.dynamics && sc.dynamics->layers > 1)
    root.table("dynamics")->fail("layers", "with [[protocol]], give the layers on the deposit steps (layer, layers)");
  ProtocolReading r{.entries = entries, .sc = sc};
  for (std::size_t i = 0; i < entries.size(); ++i) {
    const TomlSection& e = entries[i];
    const std::string kind =
        e.required(e.choice("step", {"deposit", "pour", "settle", "tap", "rod", "jig", "analyse", "snapshot",
                                     "export_lammps", "import_lammps"}),
                   "step",
                   "the kind of step: \"deposit\", \"pour\", \"settle\", \"tap\", \"rod\", \"jig\", "
                   "\"analyse\", \"snapshot\", \"export_lammps\" or \"import_lammps\"");
    if (kind == "deposit" || kind == "pour") read_deposit_step(r, i, kind);
    else if (kind == "settle") read_settle_step(r, e);
    else if (kind == "tap") read_tap_step(r, e);
    else if (kind == "rod" || kind == "jig") read_compaction_step(r, e, kind);
    else if (kind == "export_lammps") read_export_lammps_step(r, i);
    else if (kind == "import_lammps") read_import_lammps_step(r, e);
    else if (kind == "snapshot") read_snapshot_step(r, e);
    else read_analyse_step(r, e);
  }
  link_exports(r);
  check_tables_used(root, r);
  return std::move(r.protocol);
}

}  // namespace aggpack
