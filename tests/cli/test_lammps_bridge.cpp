// The LAMMPS bridge as a user meets it: a small deposited bed exported, settled by LAMMPS
// (`lmp`, Debian's lammps, installed by the README's test command) on one rank and on two
// (`mpirun`, openmpi-bin), imported back, and compared with aggpack settling the same bed.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <iterator>
#include <map>
#include <numbers>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "run_cli.hpp"

namespace {

namespace fs = std::filesystem;
using aggpack::testing::run_cli;
using aggpack::testing::run_command;
using aggpack::testing::slurp;

// 300 spheres of 1 cm, deposited, then settled until quiet (about 0.45 s simulated).
constexpr const char* kSmallBed =
    "title = \"LAMMPS cross-check\"\nseed = 5\n[container]\nside = 0.06\nheight = 0.3\n[particles]\n"
    "diameter = 0.01\ncount = 300\n[material]\nyoungs_modulus = 1e8\nwall_youngs_modulus = 1e8\n[deposition]\n"
    "[dynamics]\nmax_time = 1.0\n[analysis]\nbox_sides = [0.03]\n";

double mean_density(const fs::path& dir) {
  return nlohmann::json::parse(std::ifstream(dir / "summary.json")).at("density").at("mean").get<double>();
}

// A box from `lo` to `hi` (m) as analyze's --box takes it, every digit kept, a hair wider.
std::string fmt_box(const double lo[3], const double hi[3]) {
  std::ostringstream s;
  s.precision(17);
  s << lo[0] - 1e-12 << ',' << lo[1] - 1e-12 << ',' << lo[2] - 1e-12 << ',' << hi[0] + 1e-12 << ',' << hi[1] + 1e-12
    << ',' << hi[2] + 1e-12;
  return s.str();
}
fs::path copy_of(const fs::path& dir, const std::string& ranks) { return dir / ("lammps_" + ranks); }

// The rows of a CSV file as numbers by column name (an empty cell is NaN).
std::vector<std::map<std::string, double>> csv_rows(const fs::path& file) {
  std::ifstream in(file);
  std::string line;
  std::vector<std::string> names;
  std::getline(in, line);
  for (std::istringstream header(line); std::getline(header, line, ',');) names.push_back(line);
  std::vector<std::map<std::string, double>> rows;
  while (std::getline(in, line)) {
    std::istringstream cells(line + ",");
    std::map<std::string, double>& row = rows.emplace_back();
    std::string cell;
    for (std::size_t c = 0; c < names.size() && std::getline(cells, cell, ','); ++c)
      row[names[c]] = cell.empty() ? std::nan("") : std::stod(cell);
  }
  return rows;
}

// Issue 34: LAMMPS rows of timeseries.csv had translational_energy_j = 0 beside a nonzero
// energy per m g d. On every row of a run whose spheres are all free, the two are one energy:
// their ratio is the bed's sum of m g d (from particles.csv and the scenario's density and g).
void expect_energies_agree(const fs::path& run) {
  const auto summary = nlohmann::json::parse(std::ifstream(run / "summary.json"));
  const double density = summary.at("scenario").at("material").at("density_kg_m3").get<double>();
  const double g = summary.at("scenario").at("dynamics").at("gravity_m_s2").get<double>();
  double weight = 0.0;
  for (const auto& sphere : csv_rows(run / "particles.csv")) {
    const double r = sphere.at("r");
    weight += density * 4.0 / 3.0 * std::numbers::pi * r * r * r * g * 2.0 * r;
  }
  const auto rows = csv_rows(run / "timeseries.csv");
  ASSERT_FALSE(rows.empty());
  for (const auto& row : rows) {
    const double joules = row.at("translational_energy_j"), per_mgd = row.at("translational_energy_per_particle_mgd");
    ASSERT_GT(per_mgd, 0.0) << "at " << row.at("time_s") << " s";
    EXPECT_NEAR(joules / per_mgd / weight, 1.0, 1e-9) << "at " << row.at("time_s") << " s: " << joules << " J, "
                                                      << per_mgd << " m g d";
  }
}

class LammpsBridge : public ::testing::Test {
 protected:
  aggpack::testing::ScratchDir scratch_{"aggpack_lammps_test_"};
  const fs::path& dir_ = scratch_.path();
};

TEST_F(LammpsBridge, LammpsSettlesTheExportedBedToAggpacksDensityOnOneRankAndOnTwo) {
  const fs::path scenario = dir_ / "small.toml";
  std::ofstream(scenario) << kSmallBed;
  const fs::path exported = dir_ / "exported";
  const auto e = run_cli("export-lammps " + scenario.string() + " --out " + exported.string());
  ASSERT_EQ(e.exit_code, 0) << e.output;
  EXPECT_NE(e.output.find("exported step 3 of 3 of " + scenario.string() + " (settle, layer 1)"), std::string::npos)
      << e.output;

  // The import reproduces aggpack's own analysis of the same positions exactly: the exported
  // data file is the deposited bed.
  const auto deposited = run_cli("run " + scenario.string() + " --stop-after deposition --quiet --out " +
                                 (dir_ / "deposited").string());
  ASSERT_EQ(deposited.exit_code, 0) << deposited.output;
  const auto data = run_cli("import-lammps " + (exported / "bed.data").string() + " --scenario " + scenario.string() +
                            " --quiet --out " + (dir_ / "data_imported").string());
  ASSERT_EQ(data.exit_code, 0) << data.output;
  EXPECT_EQ(mean_density(dir_ / "data_imported"), mean_density(dir_ / "deposited"));

  // LAMMPS on one rank and on two, from the same files, unchanged.
  for (const std::string ranks : {"1", "2"}) {
    const fs::path copy = dir_ / ("lammps_" + ranks);
    fs::create_directories(copy);
    for (const char* f : {"bed.data", "settle.in"}) fs::copy_file(exported / f, copy / f);
    const std::string lmp = ranks == "1" ? std::string("lmp") : "mpirun --allow-run-as-root --oversubscribe -np 2 lmp";
    const auto r = run_command("cd " + copy.string() + " && " + lmp + " -in settle.in -log lammps.log > /dev/null");
    ASSERT_EQ(r.exit_code, 0) << "LAMMPS failed (is the Debian package lammps installed?) " << r.output;
    ASSERT_TRUE(fs::exists(copy / "settled.dump"));
    const auto i = run_cli("import-lammps " + (copy / "settled.dump").string() + " --scenario " + scenario.string() +
                           " --quiet --out " + (dir_ / ("imported_" + ranks)).string());
    ASSERT_EQ(i.exit_code, 0) << i.output;
  }
  const auto summary = nlohmann::json::parse(std::ifstream(dir_ / "imported_1" / "summary.json"));
  EXPECT_EQ(summary.at("particle_count"), 300);
  EXPECT_NE(summary.at("input").at("format").get<std::string>().find("LAMMPS dump, timestep"), std::string::npos);
  EXPECT_NE(summary.at("modelling_notes")[0].get<std::string>().find("LAMMPS dump"), std::string::npos);

  // aggpack's own DEM on the same deposited bed.
  const auto own = run_cli("run " + scenario.string() + " --quiet --out " + (dir_ / "aggpack").string());
  ASSERT_EQ(own.exit_code, 0) << own.output;
  // Two engines, the same law and start: within 0.003 (measured: 5.2e-4), and two ranks as one.
  const double aggpack = mean_density(dir_ / "aggpack"), one = mean_density(dir_ / "imported_1"),
               two = mean_density(dir_ / "imported_2");
  EXPECT_NEAR(one, aggpack, 0.003);
  EXPECT_NEAR(two, one, 0.003);
  // Both engines moved the bed (0.5934 deposited): the agreement is not of two unmoved copies.
  EXPECT_GT(std::abs(one - mean_density(dir_ / "deposited")), 2e-3);
  EXPECT_GT(std::abs(aggpack - mean_density(dir_ / "deposited")), 2e-3);

  // LAMMPS's `compute contact/atom` counts the settled bed's contacts as aggpack's analysis
  // does (docs/validation.md: the same count sphere by sphere on Example 2): the sum over every
  // sphere, in a box around all the centres.
  const fs::path counted = dir_ / "counted";
  ASSERT_EQ(run_cli("export-lammps " + (dir_ / "imported_1").string() + " --out " + counted.string()).exit_code, 0);
  std::ifstream settle(counted / "settle.in");
  std::string deck, line;
  while (std::getline(settle, line) && line.rfind("fix ", 0) != 0)
    if (line[0] != '#') deck += line + "\n";
  deck += "neighbor 0.001 bin\ncompute contacts all contact/atom\ncompute total all reduce sum c_contacts\n"
          "thermo_style custom step c_total\nrun 0\nprint \"contacts: $(c_total)\"\n";
  std::ofstream(counted / "contacts.in") << deck;
  const auto c = run_command("cd " + counted.string() + " && lmp -in contacts.in -log none");
  ASSERT_EQ(c.exit_code, 0) << c.output;
  const std::size_t at = c.output.find("\ncontacts: ");
  ASSERT_NE(at, std::string::npos) << c.output;
  const double lammps_contacts = std::stod(c.output.substr(at + 11));
  std::ifstream csv(dir_ / "imported_1" / "particles.csv");
  std::getline(csv, line);  // id,x,y,z,r
  double lo[3] = {1e9, 1e9, 1e9}, hi[3] = {-1e9, -1e9, -1e9};
  while (std::getline(csv, line)) {
    std::stringstream fields(line);
    std::string field;
    std::getline(fields, field, ',');
    for (int a = 0; a < 3; ++a) {
      std::getline(fields, field, ',');
      lo[a] = std::min(lo[a], std::stod(field));
      hi[a] = std::max(hi[a], std::stod(field));
    }
  }
  const std::string box = fmt_box(lo, hi);
  const auto a = run_cli("analyze " + (copy_of(dir_, "1") / "settled.dump").string() + " --box " + box +
                         " --tolerance 1e-12 --json");
  ASSERT_EQ(a.exit_code, 0) << a.output;
  const auto analysed = nlohmann::json::parse(a.output.substr(a.output.find('{')));
  EXPECT_EQ(analysed.at("coordination").at("particles_counted"), 300);
  EXPECT_GT(lammps_contacts, 3.0 * 300);  // a settled bed: more than three contacts a sphere
  EXPECT_DOUBLE_EQ(analysed.at("coordination").at("mean").get<double>() * 300.0, lammps_contacts);
}

// dynamics.engine = "lammps": aggpack run hands the settle step to LAMMPS (on two ranks here)
// and goes on with the protocol; the same deck as export-lammps writes, so the same bed.
TEST_F(LammpsBridge, ARunHandsItsSettleStepToLammpsAndGoesOn) {
  const auto with_dynamics = [](const std::string& keys) {
    std::string text = kSmallBed;
    return text.replace(text.find("max_time = 1.0\n"), 15, "max_time = 1.0\n" + keys);
  };
  const std::string handed = with_dynamics("engine = \"lammps\"\nlammps_ranks = 2\n");
  std::ofstream(dir_ / "handed.toml") << handed;
  const fs::path out = dir_ / "handed";
  const auto r = run_cli("run " + (dir_ / "handed.toml").string() + " --quiet --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto summary = nlohmann::json::parse(std::ifstream(out / "summary.json"));
  EXPECT_EQ(summary.at("stages").at("dynamics").at("engine"), "lammps");
  EXPECT_EQ(summary.at("stages").at("dynamics").at("lammps_ranks"), 2);
  EXPECT_EQ(summary.at("stages").at("dynamics").at("ended_by"), "quiet");
  for (const char* f : {"bed.data", "settle.in", "lammps.log", "settled.dump"})
    EXPECT_TRUE(fs::exists(out / "lammps" / "settle_layer_1" / f)) << f;
  bool noted = false;
  for (const auto& n : summary.at("modelling_notes")) noted |= n.get<std::string>().find("ran in LAMMPS") != std::string::npos;
  EXPECT_TRUE(noted);
  // The import of LAMMPS's own dump of the same run gives the same density, bit for bit.
  const auto i = run_cli("import-lammps " + (out / "lammps" / "settle_layer_1" / "settled.dump").string() +
                         " --scenario " + (dir_ / "handed.toml").string() + " --quiet --out " +
                         (dir_ / "reimported").string());
  ASSERT_EQ(i.exit_code, 0) << i.output;
  EXPECT_EQ(mean_density(out), mean_density(dir_ / "reimported"));
  expect_energies_agree(out);
  // A LAMMPS that is not there is refused before any work, naming the packages.
  std::ofstream(dir_ / "missing.toml") << with_dynamics("engine = \"lammps\"\nlammps_binary = \"no-such-lmp\"\n");
  const auto m = run_cli("run " + (dir_ / "missing.toml").string() + " --out " + (dir_ / "missing").string());
  EXPECT_EQ(m.exit_code, 2) << m.output;
  EXPECT_NE(m.output.find("apt-get install lammps openmpi-bin"), std::string::npos) << m.output;
  EXPECT_FALSE(fs::exists(dir_ / "missing"));
}

// 300 spheres of 1 cm poured in two batches, then tapped three times.
constexpr const char* kPourAndTap =
    "title = \"LAMMPS pour and tap\"\nseed = 3\n[container]\nside = 0.06\nheight = 0.4\n[particles]\n"
    "diameter = 0.01\ncount = 300\n[material]\nyoungs_modulus = 1e8\nwall_youngs_modulus = 1e8\n[pour]\n"
    "batches = 2\n[tapping]\ntaps = 3\nrest_time = 0.1\n[dynamics]\nmax_time = 1.5\n[analysis]\n"
    "box_sides = [0.03]\n";

nlohmann::json run_summary(const fs::path& scenario, const fs::path& out, const std::string& sets) {
  const auto r = run_cli("run " + scenario.string() + " --quiet --out " + out.string() + " " + sets);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  return r.exit_code == 0 ? nlohmann::json::parse(std::ifstream(out / "summary.json")) : nlohmann::json();
}

// The scenario run by aggpack's DEM into dir/own and handed to LAMMPS into dir/handed: their
// summaries (null for a run that failed).
std::pair<nlohmann::json, nlohmann::json> run_own_and_handed(const fs::path& scenario, const fs::path& dir) {
  return {run_summary(scenario, dir / "own", ""), run_summary(scenario, dir / "handed", "--set dynamics.engine='\"lammps\"'")};
}

// A pour and a tapping handed to LAMMPS: the same batches of the same gas as aggpack's pour,
// the container moved as aggpack's taps move it.
TEST_F(LammpsBridge, APourAndATappingRunInLammpsAsInAggpack) {
  const fs::path scenario = dir_ / "pour_tap.toml";
  std::ofstream(scenario) << kPourAndTap;
  const auto [own, handed] = run_own_and_handed(scenario, dir_);
  ASSERT_FALSE(own.is_null());
  ASSERT_FALSE(handed.is_null());
  const auto &own_pour = own.at("stages").at("pour"), &lmp_pour = handed.at("stages").at("pour");
  expect_energies_agree(dir_ / "handed");
  EXPECT_EQ(handed.at("stages").at("dynamics").at("engine"), "lammps");
  EXPECT_EQ(handed.at("stages").at("tapping").at("engine"), "lammps");
  EXPECT_EQ(handed.at("particle_count"), 300);
  for (const char* f : {"pour.in", "pour_batch_1.data", "pour_batch_2.data", "settled.dump"})
    EXPECT_TRUE(fs::exists(dir_ / "handed" / "lammps" / "pour_part_1" / f)) << f;
  for (const char* f : {"tap.in", "tap_1.dump", "tap_3.dump", "settled.dump"})
    EXPECT_TRUE(fs::exists(dir_ / "handed" / "lammps" / "tap_1" / f)) << f;
  // The first batch comes onto the empty floor in both: the same slab, to the last bit.
  EXPECT_EQ(lmp_pour.at("lowest_slab_bottom_m"), own_pour.at("lowest_slab_bottom_m"));
  // The second comes onto the first as it fell: the same within the fall's chaos.
  EXPECT_NEAR(lmp_pour.at("highest_slab_top_m").get<double>(), own_pour.at("highest_slab_top_m").get<double>(), 0.005);
  // Poured beds of two engines, one seed, 30 spheres in the box: a single bed's density there
  // scatters by 0.015 (sd) from seed to seed (aggpack, seeds 1-5: 0.577-0.614), so two engines'
  // single beds differ by 0.021 (sd) by chance alone; within two of those. (Measured: 0.6132
  // and 0.6216 before issue 55's contact lever arm, 0.5768 and 0.6154 after; whether the two
  // engines pack alike on average is the forty-seed comparison's, docs/validation.md.)
  const double own_poured = own.at("stages").at("tapping").at("density_before").get<double>();
  const double lmp_poured = handed.at("stages").at("tapping").at("density_before").get<double>();
  EXPECT_NEAR(lmp_poured, own_poured, 0.045);
  // Every tap moved the bed in LAMMPS; with no acceleration the same taps leave it as it was.
  const auto taps = handed.at("stages").at("tapping").at("density_after_each_tap");
  ASSERT_EQ(taps.size(), 3u);
  EXPECT_GT(std::abs(taps[2].get<double>() - lmp_poured), 2e-3);
  const auto still = run_summary(scenario, dir_ / "still",
                                 "--set dynamics.engine='\"lammps\"' --set tapping.intensity=1e-9");
  ASSERT_FALSE(still.is_null());
  EXPECT_NEAR(still.at("stages").at("tapping").at("density_after_each_tap")[2].get<double>(),
              still.at("stages").at("tapping").at("density_before").get<double>(), 1e-4);
  // Both decks under mpirun -np 2: the same poured bed as on one rank within 0.003, and taps.
  const auto two = run_summary(scenario, dir_ / "two", "--set dynamics.engine='\"lammps\"' --set dynamics.lammps_ranks=2");
  ASSERT_FALSE(two.is_null());
  EXPECT_EQ(two.at("stages").at("tapping").at("lammps_ranks"), 2);
  EXPECT_NEAR(two.at("stages").at("tapping").at("density_before").get<double>(), lmp_poured, 0.003);
  EXPECT_EQ(two.at("stages").at("tapping").at("density_after_each_tap").size(), 3u);
}

// export_lammps and import_lammps as protocol steps: a run exports its deposited bed for a
// cluster, LAMMPS settles it, a second run takes the settled positions and goes on.
// 800 spheres of 1 cm poured in two batches, friction 0.5, with the spring-dashpot rolling law.
constexpr const char* kRollingPour =
    "title = \"LAMMPS rolling sds\"\nseed = 3\n[container]\nside = 0.09\nheight = 0.4\n[particles]\n"
    "diameter = 0.01\ncount = 800\n[material]\nyoungs_modulus = 1e8\nwall_youngs_modulus = 1e8\n"
    "friction_particle = 0.5\nfriction_wall = 0.5\nrolling_friction = 0.1\nrolling_model = \"spring_dashpot\"\n"
    "rolling_stiffness = 1000\nrolling_damping = 0.1\n[pour]\nbatches = 2\n[dynamics]\nmax_time = 1.5\n"
    "[analysis]\nbox_sides = [0.05]\n";

// The spring-dashpot rolling law is LAMMPS's `rolling sds` itself: a pour handed to LAMMPS
// from the same start (the same batches of the same gas) ends as dense as aggpack's. A pour
// is chaotic: the two engines' last bits differ, so they make two different random beds of the
// same law. Over forty seeds of this scenario (scripts/validate_lammps_rolling.sh) LAMMPS's beds
// were denser by +0.0048 on average with the law (sd 0.0093, standard error 0.0015), +0.0032
// without it; the law's own share, +0.005 before the tangential force's lever arm became LAMMPS's
// R - d/2 (issue 55), is +0.0016 (standard error 0.0019) (docs/validation.md). This seed:
// measured 0.5719 (aggpack) and 0.5815 (LAMMPS). The law's own agreement, on one contact, is in
// the closed-form tests (tests/dynamics/test_rolling_resistance.cpp), in a crowd step by step
// in tests/cli/test_lammps_crowd.cpp, and LAMMPS's wall gives the same stopping distance
// (0.1784 m for 0.5 m/s at mu_r = 0.1).
TEST_F(LammpsBridge, APourWithSpringDashpotRollingEndsAsDenseInLammps) {
  const fs::path scenario = dir_ / "rolling.toml";
  std::ofstream(scenario) << kRollingPour;
  const auto [own, handed] = run_own_and_handed(scenario, dir_);
  ASSERT_FALSE(own.is_null());
  ASSERT_FALSE(handed.is_null());
  std::ifstream deck(dir_ / "handed" / "lammps" / "pour_part_1" / "pour.in");
  const std::string text((std::istreambuf_iterator<char>(deck)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("limit_damping tangential mindlin NULL"), std::string::npos);
  EXPECT_NE(text.find(" rolling sds 1000 0.1 0.1\n"), std::string::npos) << "the particles' law";
  EXPECT_NE(text.find(" rolling sds 1000 0.1 0.1 zplane"), std::string::npos) << "the floor's";
  EXPECT_EQ(own.at("scenario").at("material").at("rolling_model"), "spring_dashpot");
  const double own_density = own.at("density").at("mean").get<double>();
  const double lammps_density = handed.at("density").at("mean").get<double>();
  std::cout << "poured with rolling sds: aggpack " << own_density << ", LAMMPS " << lammps_density << "\n";
  EXPECT_NEAR(lammps_density, own_density, 0.02);
  // Rolling resistance holds both beds looser than the same pour without it (measured 0.5932
  // and 0.5968): the law acts in both engines.
  for (const auto& [summary, without] : {std::pair{&own, 0.5932}, std::pair{&handed, 0.5968}})
    EXPECT_LT(summary->at("density").at("mean").get<double>(), without - 0.005);
}

TEST_F(LammpsBridge, ProtocolStepsHandABedOverAndTakeItBack) {
  std::string base = kSmallBed;
  const fs::path first = dir_ / "first.toml";
  std::ofstream(first) << base << "[[protocol]]\nstep = \"deposit\"\n[[protocol]]\nstep = \"export_lammps\"\n"
                                  "name = \"cluster\"\n[[protocol]]\nstep = \"settle\"\n";
  const auto e = run_cli("run " + first.string() + " --stop-after deposition --out " + (dir_ / "first").string());
  ASSERT_EQ(e.exit_code, 0) << e.output;
  EXPECT_NE(e.output.find("export_lammps: 300 spheres and a deck (settle, layer 1)"), std::string::npos) << e.output;
  const fs::path deck = dir_ / "first" / "lammps" / "cluster";
  const auto l = run_command("cd " + deck.string() + " && lmp -in settle.in -log lammps.log > /dev/null");
  ASSERT_EQ(l.exit_code, 0) << l.output;

  const fs::path second = dir_ / "second.toml";
  std::ofstream(second) << base << "[[protocol]]\nstep = \"deposit\"\n[[protocol]]\nstep = \"import_lammps\"\n"
                                   "file = \"first/lammps/cluster/settled.dump\"\n[[protocol]]\nstep = \"analyse\"\n"
                                   "name = \"from_lammps\"\n[[protocol]]\nstep = \"settle\"\n";
  const auto s = run_summary(second, dir_ / "second", "");
  ASSERT_FALSE(s.is_null());
  ASSERT_EQ(s.at("lammps_exchanges").size(), 1u);
  EXPECT_EQ(s.at("lammps_exchanges")[0].at("direction"), "import");
  EXPECT_EQ(s.at("lammps_exchanges")[0].at("spheres"), 300);
  // The imported bed is analysed as import-lammps analyses the same dump: exactly.
  const auto i = run_cli("import-lammps " + (deck / "settled.dump").string() + " --scenario " + first.string() +
                         " --quiet --out " + (dir_ / "imported").string());
  ASSERT_EQ(i.exit_code, 0) << i.output;
  EXPECT_EQ(s.at("stages").at("from_lammps").at("density").at("mean").get<double>(), mean_density(dir_ / "imported"));
  // The settle step after it started from LAMMPS's quiet bed: quiet again at once.
  EXPECT_LT(s.at("stages").at("dynamics").at("simulated_time_s").get<double>(), 0.2);

  // Another bed's dump is refused, naming the file and what differs.
  std::string other = base;
  other.replace(other.find("count = 300"), 11, "count = 299");
  std::ofstream(dir_ / "other.toml") << other << "[[protocol]]\nstep = \"deposit\"\n[[protocol]]\nstep = "
                                               "\"import_lammps\"\nfile = \"first/lammps/cluster/settled.dump\"\n"
                                               "[[protocol]]\nstep = \"settle\"\n";
  // Before any work, by `run` and by `check` alike (the import step's file is read then).
  for (const std::string& command : {"run " + (dir_ / "other.toml").string() + " --out " + (dir_ / "other").string(),
                                    "check " + (dir_ / "other.toml").string()}) {
    const auto o = run_cli(command);
    EXPECT_EQ(o.exit_code, 2) << o.output;
    EXPECT_NE(o.output.find("settled.dump holds 300 spheres, the bed at this step 299"), std::string::npos) << o.output;
  }
  EXPECT_FALSE(fs::exists(dir_ / "other"));
  // Scenario errors, before any work: no DEM step after an export, no file to import.
  std::ofstream(dir_ / "no_dem.toml") << base << "[[protocol]]\nstep = \"deposit\"\n[[protocol]]\nstep = \"settle\"\n"
                                                 "[[protocol]]\nstep = \"export_lammps\"\nname = \"late\"\n";
  const auto n = run_cli("run " + (dir_ / "no_dem.toml").string() + " --out " + (dir_ / "no_dem").string());
  EXPECT_EQ(n.exit_code, 2) << n.output;
  EXPECT_NE(n.output.find("protocol[2].step: an export_lammps step writes a deck of the DEM step after it"),
            std::string::npos)
      << n.output;
  std::ofstream(dir_ / "no_file.toml") << base << "[[protocol]]\nstep = \"deposit\"\n[[protocol]]\nstep = "
                                                  "\"import_lammps\"\nfile = \"missing.dump\"\n[[protocol]]\nstep = "
                                                  "\"settle\"\n";
  const auto f = run_cli("run " + (dir_ / "no_file.toml").string() + " --out " + (dir_ / "no_file").string());
  EXPECT_EQ(f.exit_code, 2) << f.output;
  EXPECT_NE(f.output.find("protocol[1].file: the LAMMPS file \"missing.dump\" is not a file: looked for at " +
                          (dir_ / "missing.dump").lexically_normal().string()),
            std::string::npos)
      << f.output;
  EXPECT_FALSE(fs::exists(dir_ / "no_dem"));
  EXPECT_FALSE(fs::exists(dir_ / "no_file"));
}

// export-lammps RUN_DIR: the final bed of a finished run, with the overrides it ran with.
TEST_F(LammpsBridge, ARunsFinalBedIsExportedWithItsScenarioAndOverrides) {
  const fs::path scenario = dir_ / "small.toml";
  std::ofstream(scenario) << kSmallBed;
  const auto r = run_cli("run " + scenario.string() + " --stop-after deposition --quiet --out " +
                         (dir_ / "run").string() + " --set material.youngs_modulus=2e8");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto e = run_cli("export-lammps " + (dir_ / "run").string() + " --out " + (dir_ / "deck").string());
  ASSERT_EQ(e.exit_code, 0) << e.output;
  std::stringstream deck;
  deck << std::ifstream(dir_ / "deck" / "settle.in").rdbuf();
  EXPECT_NE(deck.str().find("hertz/material 200000000 "), std::string::npos) << deck.str();
  // The data file is the run's final bed: imported, the same density as the run's.
  const auto i = run_cli("import-lammps " + (dir_ / "deck" / "bed.data").string() + " --scenario " +
                         scenario.string() + " --quiet --out " + (dir_ / "imported").string());
  ASSERT_EQ(i.exit_code, 0) << i.output;
  EXPECT_EQ(mean_density(dir_ / "imported"), mean_density(dir_ / "run"));
  // --tap needs a [tapping] table.
  const auto t = run_cli("export-lammps " + (dir_ / "run").string() + " --tap --out " + (dir_ / "tap").string());
  EXPECT_EQ(t.exit_code, 2) << t.output;
  EXPECT_NE(t.output.find("--tap: the scenario has no [tapping] table"), std::string::npos) << t.output;
}

// A run given its scenario by a relative path: export-lammps RUN_DIR finds the scenario from
// the folder the run was started in, whatever the folder the export is started in.
TEST_F(LammpsBridge, ARunsRelativeScenarioPathIsTakenFromWhereTheRunStarted) {
  fs::create_directories(dir_ / "project" / "elsewhere");
  std::ofstream(dir_ / "project" / "small.toml") << kSmallBed;
  const fs::path run = dir_ / "run";
  const auto r = run_command("cd " + (dir_ / "project").string() + " && " + AGGPACK_EXE +
                             " run small.toml --stop-after deposition --quiet --out " + run.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto e = run_command("cd " + (dir_ / "project" / "elsewhere").string() + " && " + AGGPACK_EXE +
                             " export-lammps " + run.string() + " --out " + (dir_ / "deck").string());
  ASSERT_EQ(e.exit_code, 0) << e.output;
  std::stringstream deck;
  deck << std::ifstream(dir_ / "deck" / "settle.in").rdbuf();
  EXPECT_NE(deck.str().find("the settle, layer 1 step of " + (dir_ / "project" / "small.toml").string()),
            std::string::npos)
      << deck.str();
}

// summary.json's seed is read as the scenario's seed is, 0 to 2^63 - 1: an edited -1 is
// refused, naming the file and the key, not wrapped to 2^64 - 1 in the exported deck.
TEST_F(LammpsBridge, ARunsSeedOutsideTheSeedsRangeIsRefused) {
  const fs::path scenario = dir_ / "small.toml";
  std::ofstream(scenario) << kSmallBed;
  const fs::path run = dir_ / "run";
  ASSERT_EQ(run_cli("run " + scenario.string() + " --stop-after deposition --quiet --out " + run.string()).exit_code, 0);
  auto summary = nlohmann::json::parse(std::ifstream(run / "summary.json"));
  for (const nlohmann::json& seed : {nlohmann::json(-1), nlohmann::json(18446744073709551615ull), nlohmann::json(2.5)}) {
    SCOPED_TRACE(seed.dump());
    summary["seed"] = seed;
    std::ofstream(run / "summary.json") << summary.dump(2);
    const auto e = run_cli("export-lammps " + run.string() + " --out " + (dir_ / "deck").string());
    EXPECT_EQ(e.exit_code, 2) << e.output;
    EXPECT_NE(e.output.find((run / "summary.json").string() + ": seed " + seed.dump() +
                            ": expected an integer from 0 to 9223372036854775807"),
              std::string::npos)
        << e.output;
    EXPECT_FALSE(fs::exists(dir_ / "deck"));
  }
}

TEST_F(LammpsBridge, ExportRefusesWhatItCannotHandOver) {
  const fs::path loose = dir_ / "loose.toml";
  std::ofstream(loose) << "[container]\nside = 0.06\nheight = 0.3\n[particles]\ndiameter = 0.01\ncount = 30\n"
                          "[deposition]\n[analysis]\nbox_sides = [0.01]\n";
  const auto n = run_cli("export-lammps " + loose.string() + " --out " + (dir_ / "y").string());
  EXPECT_EQ(n.exit_code, 2) << n.output;
  EXPECT_NE(n.output.find("no DEM step to export"), std::string::npos) << n.output;
  const auto t = run_cli("export-lammps " + loose.string() + " --tap --out " + (dir_ / "z").string());
  EXPECT_EQ(t.exit_code, 2) << t.output;
  EXPECT_NE(t.output.find("--tap applies to a run's folder"), std::string::npos) << t.output;
  fs::create_directories(dir_ / "not_a_run");
  const auto f = run_cli("export-lammps " + (dir_ / "not_a_run").string() + " --out " + (dir_ / "w").string());
  EXPECT_EQ(f.exit_code, 2) << f.output;
  EXPECT_NE(f.output.find("a run's folder holds summary.json"), std::string::npos) << f.output;
  for (const char* d : {"y", "z", "w"}) EXPECT_FALSE(fs::exists(dir_ / d)) << d;
}

// Three materials (the default's 1 cm spheres, sand and stone) poured in two batches.
constexpr const char* kThreeMaterialPour =
    "title = \"LAMMPS materials\"\nseed = 6\n[container]\nside = 0.03\nheight = 0.3\n[particles]\n"
    "classes = [{ diameter = 0.01, count = 20 }, { diameter = 0.008, count = 20, material = \"stone\" }, "
    "{ diameter = 0.006, count = 40, material = \"sand\" }]\n[material]\nyoungs_modulus = 1e8\n"
    "wall_youngs_modulus = 1e8\n[materials.stone]\ndensity = 3000\nyoungs_modulus = 2e8\nfriction_wall = 0.6\n"
    "[materials.sand]\ndensity = 1500\nrestitution = 0.3\n[[material_pairs]]\nmaterials = [\"sand\", \"stone\"]\n"
    "friction = 0.3\n[pour]\nbatches = 2\n[dynamics]\nmax_time = 0.3\n[analysis]\nbox_sides = [0.005]\n";

std::size_t count_lines_starting(const std::string& text, const std::string& start) {
  std::size_t n = 0;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) n += line.rfind(start, 0) == 0 ? 1 : 0;
  return n;
}

// Each `pair_coeff I J hertz/material E e nu ... mindlin NULL x mu` of the three materials'
// deck gives LAMMPS's E* = E / (2 (1 - nu^2)) (one E and nu for both sides) equal to Hertz's
// E* of the two materials, the geometric mean of their restitutions and the pair's friction.
void expect_pair_coefficients_of_the_materials(const std::string& deck) {
  struct M {
    double e, nu, restitution;
  };
  const M materials[] = {{1e8, 0.25, 0.5}, {1e8, 0.25, 0.3}, {2e8, 0.25, 0.5}};  // default, sand, stone
  std::istringstream in(deck);
  std::size_t seen = 0;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("pair_coeff ", 0) != 0) continue;
    std::istringstream words(line);
    std::string word, law;
    std::size_t i = 0, j = 0;
    double e = 0, restitution = 0, nu = 0;
    words >> word >> i >> j >> law >> e >> restitution >> nu;
    ASSERT_EQ(law, "hertz/material") << line;
    std::vector<std::string> rest;
    while (words >> word) rest.push_back(word);
    const M &a = materials[(i - 1) % 3], &b = materials[(j - 1) % 3];
    const double e_star = 1.0 / ((1 - a.nu * a.nu) / a.e + (1 - b.nu * b.nu) / b.e);
    EXPECT_NEAR(e / (2 * (1 - nu * nu)) / e_star, 1.0, 1e-7) << line;
    EXPECT_NEAR(restitution, std::sqrt(a.restitution * b.restitution), 1e-8) << line;
    const bool sand_stone = ((i - 1) % 3) + ((j - 1) % 3) == 3;
    EXPECT_EQ(std::stod(rest.back()), sand_stone ? 0.3 : 0.17) << line;
    ++seen;
  }
  EXPECT_EQ(seen, 21u);
}

// M = 3 materials: 2M = 6 atom types (each material free and held), a pair_coeff for every
// pair of types (21), a group per material and a set of wall fixes per material's group. LAMMPS
// runs the deck to its end.
TEST_F(LammpsBridge, APourOfThreeMaterialsIsADeckOfTypesGroupsAndWallsPerMaterial) {
  const fs::path scenario = dir_ / "materials.toml";
  std::ofstream(scenario) << kThreeMaterialPour;
  const fs::path exported = dir_ / "exported";
  const auto e = run_cli("export-lammps " + scenario.string() + " --out " + exported.string());
  ASSERT_EQ(e.exit_code, 0) << e.output;
  const std::string deck = aggpack::testing::slurp(exported / "pour.in");
  constexpr std::size_t m = 3;
  EXPECT_EQ(count_lines_starting(deck, "pair_coeff "), 2 * m * (2 * m + 1) / 2) << deck;
  EXPECT_EQ(count_lines_starting(deck, "pair_coeff * *"), 0u);
  for (std::size_t i = 1; i <= 2 * m; ++i)
    for (std::size_t j = i; j <= 2 * m; ++j)
      EXPECT_EQ(count_lines_starting(deck, "pair_coeff " + std::to_string(i) + " " + std::to_string(j) + " "), 1u)
          << i << " " << j;
  EXPECT_EQ(count_lines_starting(deck, "group mobile type "), 1u);
  EXPECT_NE(deck.find("\ngroup mobile type 1 2 3\n"), std::string::npos);
  const char* names[] = {"default", "sand", "stone"};
  for (std::size_t k = 0; k < m; ++k) {
    const std::string name = names[k];
    // Made with the system, then renewed after each of the two batches.
    EXPECT_GE(count_lines_starting(deck, "group mobile_" + name + " type " + std::to_string(k + 1)), 1u) << name;
    for (const char* wall : {"fix wall_x_", "fix wall_y_", "fix floor_"})
      EXPECT_EQ(count_lines_starting(deck, wall + name + " mobile_" + name + " wall/gran granular "), 1u)
          << wall << name << "\n" << deck;
  }
  expect_pair_coefficients_of_the_materials(deck);
  for (const char* f : {"bed.data", "pour_batch_1.data", "pour_batch_2.data"}) {
    const std::string data = aggpack::testing::slurp(exported / f);
    EXPECT_NE(data.find("\n6 atom types\n"), std::string::npos) << f;
  }
  const auto r = run_command("cd " + exported.string() + " && lmp -in pour.in -log lammps.log > /dev/null");
  ASSERT_EQ(r.exit_code, 0) << "LAMMPS failed " << r.output << aggpack::testing::slurp(exported / "lammps.log");
  const std::string log = aggpack::testing::slurp(exported / "lammps.log");
  EXPECT_NE(log.find("Total wall time"), std::string::npos);
  // Every sphere of both batches is still in LAMMPS at the end (none lost through a wall).
  EXPECT_NE(log.find("with 80 atoms", log.rfind("Loop time")), std::string::npos) << log.substr(log.rfind("Loop time"));
  EXPECT_TRUE(fs::exists(exported / "settled.dump"));
}

}  // namespace

namespace {

// 300 rounded grains of one template (3 spheres; I = 8 mm, L:I:S = 1 : 0.6 : 0.48), poured in
// one batch into a box with walls and settled.
constexpr const char* kGrainPour =
    "title = \"grains to LAMMPS\"\nseed = 4\n[container]\nside = 0.05\nheight = 0.3\n[particles]\ndiameter = 0.008\n"
    "count = 300\nshape = { family = \"rounded\", spheres = 3, templates = 1, elongation = 0.6, flatness = 0.8, "
    "spread = 0 }\n[material]\nyoungs_modulus = 1e7\nwall_youngs_modulus = 1e7\nfriction_particle = 0.5\n[pour]\n"
    "batches = 1\nsolid_fraction = 0.15\n[dynamics]\nmax_time = 1.0\n[analysis]\nbox_sides = [0.008]\n";

// The bed's density between one d_max above the floor and one below its surface: the mean of
// the vertical profile's slices there, each the whole footprint (one small virtual box is a
// sample of a few grains, the slices of the bed's whole width).
double interior_density(const nlohmann::json& summary) {
  const auto& bed = summary.at("bed");
  const auto& profile = summary.at("profiles").at("vertical");
  const double lo = bed.at("floor_m").get<double>() + bed.at("d_max_m").get<double>();
  const double hi = bed.at("surface_m").get<double>() - bed.at("d_max_m").get<double>();
  double sum = 0.0;
  int slices = 0;
  for (std::size_t k = 0; k < profile.at("z_m").size(); ++k) {
    const double z = profile.at("z_m")[k].get<double>();
    if (z < lo || z > hi) continue;
    sum += profile.at("solid_fraction")[k].get<double>();
    ++slices;
  }
  EXPECT_GE(slices, 5);
  return slices > 0 ? sum / slices : 0.0;
}

}  // namespace

// Issue 38: a pour of grains handed to LAMMPS (fix rigid/small, each grain's union mass
// properties from bodies.txt) from the same start as aggpack's (the same gas of the same
// grains at the same orientations) ends as dense, and LAMMPS's bed comes back grain by grain.
// A pour is chaotic: two engines make two random beds of one law. Over four seeds of this
// scenario (3 to 6) LAMMPS's interior density was above aggpack's by +0.0045, +0.0027,
// -0.0005 and +0.0021; with periodic sides and 500 grains by +0.0048, +0.0003, +0.0057 and
// +0.0096 (docs/validation.md): the sign of the spheres' pour bias (+0.0018), not found yet.
// This seed: measured 0.5767 (aggpack) and 0.5794 (LAMMPS).
TEST_F(LammpsBridge, APourOfGrainsEndsAsDenseInLammpsAndComesBackGrainByGrain) {
  const fs::path scenario = dir_ / "grains.toml";
  std::ofstream(scenario) << kGrainPour;
  const auto [own, handed] = run_own_and_handed(scenario, dir_);
  ASSERT_FALSE(own.is_null());
  ASSERT_FALSE(handed.is_null());
  const fs::path deck = dir_ / "handed" / "lammps" / "pour_part_1";
  const std::string pour = slurp(deck / "pour.in");
  EXPECT_NE(pour.find("fix rigid grains rigid/small molecule infile bodies.txt reinit no gravity gravity"),
            std::string::npos);
  EXPECT_TRUE(fs::exists(deck / "bodies.txt"));
  EXPECT_EQ(handed.at("grains").at("count"), 300);
  const double aggpack = interior_density(own), lammps = interior_density(handed);
  EXPECT_NEAR(lammps, aggpack, 0.005);
  EXPECT_GT(aggpack, 0.5);  // a bed, not a gas

  // LAMMPS's bed taken back by an import_lammps step after aggpack's own pour of the same
  // grains: each grain's pose fitted to its spheres, the bed analysed as the LAMMPS run's. Soft
  // (E = 1e7 Pa), the bed's contacts are deeper than a file's default tolerances (a grain's
  // sphere bears its grain's weight): the scenario gives them for the file it takes back.
  std::string taking_back = kGrainPour;
  taking_back.replace(taking_back.find("[material]"), 0, "boundary_overlap_tolerance = 0.05\nsoft_contacts = true\n");
  const std::string settled = (deck / "settled.dump").string();
  const fs::path back = dir_ / "back.toml";
  std::ofstream(back) << taking_back << "[[protocol]]\nstep = \"pour\"\n[[protocol]]\nstep = \"import_lammps\"\nfile = \""
                      << settled << "\"\n";
  const auto taken = run_summary(back, dir_ / "back", "");
  ASSERT_FALSE(taken.is_null());
  EXPECT_NEAR(interior_density(taken), lammps, 1e-12);
  EXPECT_EQ(taken.at("grains").at("count"), 300);

  // A dump whose grain's sphere has moved 1 mm off its grain is refused, naming the grain.
  std::string dump = slurp(deck / "settled.dump");
  const std::size_t atoms = dump.find("ITEM: ATOMS");
  const std::size_t row = dump.find('\n', atoms) + 1;  // atom 1: the first sphere of grain 1
  std::istringstream fields(dump.substr(row, dump.find('\n', row) - row));
  std::string id, type;
  double x = 0.0;
  fields >> id >> type >> x;
  const std::size_t x_at = dump.find(' ', dump.find(' ', row) + 1) + 1;
  char moved_x[32];
  std::snprintf(moved_x, sizeof moved_x, "%.17g", x + 1e-3);
  dump.replace(x_at, dump.find(' ', x_at) - x_at, moved_x);
  std::ofstream(dir_ / "moved.dump") << dump;
  const fs::path moved = dir_ / "moved.toml";
  std::ofstream(moved) << taking_back << "[[protocol]]\nstep = \"pour\"\n[[protocol]]\nstep = \"import_lammps\"\nfile = \""
                       << (dir_ / "moved.dump").string() << "\"\n";
  const auto r = run_cli("run " + moved.string() + " --quiet --out " + (dir_ / "moved").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("of grain 1 are not where one rigid grain would hold them"), std::string::npos) << r.output;
}
