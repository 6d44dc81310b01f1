// The LAMMPS bridge as a user meets it: a small deposited bed exported, settled by LAMMPS
// (`lmp`, Debian's lammps, installed by the README's test command) on one rank and on two
// (`mpirun`, openmpi-bin), imported back, and compared with aggpack settling the same bed.
#include <cmath>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "run_cli.hpp"

namespace {

namespace fs = std::filesystem;
using aggpack::testing::run_cli;
using aggpack::testing::run_command;

// 300 spheres of 1 cm, deposited, then settled until quiet (about 0.45 s simulated).
constexpr const char* kSmallBed =
    "title = \"LAMMPS cross-check\"\nseed = 5\n[container]\nside = 0.06\nheight = 0.3\n[particles]\n"
    "diameter = 0.01\ncount = 300\n[material]\nyoungs_modulus = 1e8\nwall_youngs_modulus = 1e8\n[deposition]\n"
    "[dynamics]\nmax_time = 1.0\n[analysis]\nbox_sides = [0.03]\n";

double mean_density(const fs::path& dir) {
  return nlohmann::json::parse(std::ifstream(dir / "summary.json")).at("density").at("mean").get<double>();
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
  EXPECT_NE(e.output.find("exported step 3 of 3 (settle, layer 1)"), std::string::npos) << e.output;

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
  // A LAMMPS that is not there is refused before any work, naming the packages.
  std::ofstream(dir_ / "missing.toml") << with_dynamics("engine = \"lammps\"\nlammps_binary = \"no-such-lmp\"\n");
  const auto m = run_cli("run " + (dir_ / "missing.toml").string() + " --out " + (dir_ / "missing").string());
  EXPECT_EQ(m.exit_code, 2) << m.output;
  EXPECT_NE(m.output.find("apt-get install lammps openmpi-bin"), std::string::npos) << m.output;
  EXPECT_FALSE(fs::exists(dir_ / "missing"));
}

TEST_F(LammpsBridge, ExportRefusesWhatItCannotHandOver) {
  const fs::path pour = dir_ / "pour.toml";
  std::ofstream(pour) << "[container]\nside = 0.06\nheight = 0.3\n[particles]\ndiameter = 0.01\ncount = 30\n"
                         "[dynamics]\n[pour]\n[analysis]\nbox_sides = [0.01]\n";
  const auto r = run_cli("export-lammps " + pour.string() + " --out " + (dir_ / "x").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("is a pour step: export-lammps exports settle steps only"), std::string::npos) << r.output;
  const fs::path loose = dir_ / "loose.toml";
  std::ofstream(loose) << "[container]\nside = 0.06\nheight = 0.3\n[particles]\ndiameter = 0.01\ncount = 30\n"
                          "[deposition]\n[analysis]\nbox_sides = [0.01]\n";
  const auto n = run_cli("export-lammps " + loose.string() + " --out " + (dir_ / "y").string());
  EXPECT_EQ(n.exit_code, 2) << n.output;
  EXPECT_NE(n.output.find("no DEM step to export"), std::string::npos) << n.output;
  EXPECT_FALSE(fs::exists(dir_ / "x"));
  EXPECT_FALSE(fs::exists(dir_ / "y"));
}

}  // namespace
