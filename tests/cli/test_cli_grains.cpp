// Grains of several spheres as a user meets them: a component's shape in the scenario, the
// pour, grains.csv and particles.csv's grain column, summary.json's grains; and the scenarios
// that cannot take grains refused before any work, with the key and what to do.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "run_cli.hpp"

namespace {

namespace fs = std::filesystem;
using aggpack::testing::run_cli;
using aggpack::testing::slurp;

class CliGrains : public ::testing::Test {
 protected:
  aggpack::testing::ScratchDir scratch_{"aggpack_cli_grains_"};
  const fs::path& dir_ = scratch_.path();
};

// 150 rounded grains of 2 spheres (I = 8 mm) and 40 spheres of 5 mm, poured and settled.
constexpr const char* kGrains =
    "title = \"grains\"\nseed = 2\n[container]\nside = 0.045\nheight = 0.3\n[particles]\n"
    "classes = [{ diameter = 0.008, count = 150, shape = { family = \"rounded\", spheres = 2, templates = 3 } }, "
    "{ diameter = 0.005, count = 40 }]\n[material]\nyoungs_modulus = 1e7\nwall_youngs_modulus = 1e7\n"
    "friction_particle = 0.5\n[pour]\nsolid_fraction = 0.15\n[dynamics]\nmax_time = 0.8\n[analysis]\n"
    "box_sides = [0.006]\n";

std::vector<std::vector<std::string>> csv(const fs::path& file, std::string& header) {
  std::istringstream in(slurp(file));
  std::getline(in, header);
  std::vector<std::vector<std::string>> rows;
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> cells;
    std::istringstream s(line);
    for (std::string cell; std::getline(s, cell, ',');) cells.push_back(cell);
    rows.push_back(cells);
  }
  return rows;
}

TEST_F(CliGrains, APourOfGrainsWritesEachGrainAndItsSpheres) {
  std::ofstream(dir_ / "grains.toml") << kGrains;
  const auto r =
      run_cli("run " + (dir_ / "grains.toml").string() + " --quiet --threads 1 --out " + (dir_ / "out").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::string header;
  const auto grains = csv(dir_ / "out" / "grains.csv", header);
  EXPECT_EQ(header,
            "id,x,y,z,qw,qx,qy,qz,volume_diameter,length,width,thickness,mass,template,first_sphere,spheres,"
            "sieve_retained,sieve_passing,coordination");
  ASSERT_EQ(grains.size(), 150u);
  const auto spheres = csv(dir_ / "out" / "particles.csv", header);
  EXPECT_EQ(header, "id,x,y,z,r,grain");
  ASSERT_EQ(spheres.size(), 150u * 2 + 40u);
  // Each grain's spheres name it, from its first sphere on; the others are spheres of their own.
  std::map<std::string, int> members;
  for (const auto& row : spheres) ++members[row.at(5)];
  EXPECT_EQ(members["0"], 40);
  for (const auto& g : grains) {
    EXPECT_EQ(members[g.at(0)], 2) << g.at(0);
    EXPECT_EQ(spheres.at(std::stoul(g.at(14)) - 1).at(5), g.at(0));
    EXPECT_NEAR(std::stod(g.at(10)), 0.008, 1e-12);  // I: the size the grading gave
    EXPECT_GE(std::stod(g.at(9)), std::stod(g.at(10)));
    EXPECT_GE(std::stod(g.at(10)), std::stod(g.at(11)));
    ASSERT_EQ(g.size(), 19u);
    EXPECT_TRUE(g.at(16).empty() && g.at(17).empty());  // size classes: no sieve interval
    EXPECT_LE(std::stoi(g.at(18)), 12);                 // its grains and spheres touched, each once
  }
  const auto summary = nlohmann::json::parse(std::ifstream(dir_ / "out" / "summary.json"));
  const auto& g = summary.at("grains");
  EXPECT_EQ(g.at("count"), 150);
  EXPECT_EQ(g.at("components").at(0).at("family"), "rounded");
  EXPECT_EQ(g.at("components").at(0).at("bed").at("grains"), 150);
  // The VTP carries each sphere's grain, as particles.csv does.
  EXPECT_NE(slurp(dir_ / "out" / "particles.vtp").find("Name=\"grain\""), std::string::npos);
  // Coordination by grain (unit-tested in test_analysis): counted over grains and spheres, a
  // grain's own overlapping spheres never in contact, so no count is inflated by them.
  const auto& coordination = summary.at("coordination");
  std::size_t counted = 0;
  for (const auto& n : coordination.at("histogram")) counted += n.get<std::size_t>();
  EXPECT_EQ(counted, coordination.at("particles_counted").get<std::size_t>());
  EXPECT_LT(coordination.at("mean").get<double>(), 12.0);
  const double density = summary.at("density").at("mean").get<double>();
  EXPECT_GT(density, 0.3);
  EXPECT_LT(density, 0.9);
}

// The paper's layer-by-layer method with grains: each half poured, then settled with the half
// below held still (a pour moves the bed it falls on; the settle of the upper half does not).
// The lower half's spheres end where the pour of the upper half left them, to the byte (a
// snapshot taken then against the final particles.csv), and the second settle counts them as
// frozen.
TEST_F(CliGrains, ALayeredPourOfGrainsSettlesEachHalfWithTheOneBelowHeldStill) {
  std::string layered = kGrains;
  layered += "[[protocol]]\nstep = \"pour\"\nlayers = 2\nlayer = 0\n[[protocol]]\nstep = \"settle\"\n"
             "[[protocol]]\nstep = \"pour\"\nlayers = 2\nlayer = 1\n[[protocol]]\nstep = \"snapshot\"\n"
             "name = \"poured\"\n[[protocol]]\nstep = \"settle\"\nlayer = 1\n";
  std::ofstream(dir_ / "layered.toml") << layered;
  const auto r =
      run_cli("run " + (dir_ / "layered.toml").string() + " --quiet --threads 1 --out " + (dir_ / "out").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto summary = nlohmann::json::parse(std::ifstream(dir_ / "out" / "summary.json"));
  const auto& runs = summary.at("stages").at("dynamics").at("runs");
  ASSERT_EQ(runs.size(), 4u);  // each pour's DEM and each settle
  for (std::size_t k = 0; k < 3; ++k) EXPECT_EQ(runs[k].at("particles_frozen"), 0) << k;
  const std::size_t lower = runs[3].at("particles_frozen");
  std::string header;
  const auto poured = csv(dir_ / "out" / "particles_poured.csv", header);
  const auto all = csv(dir_ / "out" / "particles.csv", header);
  ASSERT_EQ(all.size(), 150u * 2 + 40u);
  ASSERT_EQ(poured.size(), all.size());
  EXPECT_EQ(runs[3].at("particles_settled"), all.size() - lower);
  EXPECT_GT(lower, 100u);
  EXPECT_LT(lower, all.size() - 100u);
  std::size_t members = 0, moved = 0;
  for (std::size_t i = 0; i < all.size(); ++i) {
    if (i < lower) {
      EXPECT_EQ(all[i], poured[i]) << "sphere " << i + 1 << " of the lower half moved in the upper half's settle";
      members += all[i].at(5) != "0" ? 1 : 0;
    } else {
      moved += all[i] != poured[i] ? 1 : 0;
    }
  }
  EXPECT_GT(members, 50u) << "the lower half has grains";
  EXPECT_GT(moved, (all.size() - lower) / 2) << "the upper half settled";
  EXPECT_EQ(summary.at("grains").at("count"), 150);
}

// Refused before any work, exit 2, naming what to change.
TEST_F(CliGrains, ScenariosThatCannotTakeGrainsAreRefused) {
  std::string in_batches_to_lammps = kGrains;
  in_batches_to_lammps.replace(in_batches_to_lammps.find("[pour]\n"), 7, "[pour]\nbatches = 2\n");
  in_batches_to_lammps.replace(in_batches_to_lammps.find("[dynamics]\n"), 11, "[dynamics]\nengine = \"lammps\"\n");
  std::string layered_in_lammps = kGrains;
  layered_in_lammps.replace(layered_in_lammps.find("[dynamics]\n"), 11, "[dynamics]\nengine = \"lammps\"\n");
  layered_in_lammps += "[[protocol]]\nstep = \"pour\"\nlayers = 2\nlayer = 0\n[[protocol]]\nstep = \"settle\"\n"
                       "[[protocol]]\nstep = \"pour\"\nlayers = 2\nlayer = 1\n[[protocol]]\nstep = \"settle\"\n"
                       "layer = 1\n";
  std::string deposited = kGrains;
  deposited.replace(deposited.find("[pour]\nsolid_fraction = 0.15\n"), 29, "[deposition]\n");
  const std::map<std::string, std::pair<std::string, std::string>> cases{
      {"deposited", {deposited, "pour grains"}},
      {"unreachable",
       {"title = \"t\"\n[container]\nside = 0.05\nheight = 0.3\n[particles]\nclasses = [{ diameter = 0.009, count = 100, "
        "shape = { family = \"rounded\", spheres = 2, templates = 1, spread = 0, flakiness_index = 50 } }]\n"
        "[pour]\n[dynamics]\n[analysis]\nbox_sides = [0.005]\n",
        "cannot be had"}},
      {"two_measures",
       {"title = \"t\"\n[container]\nside = 0.05\nheight = 0.3\n[particles]\ndiameter = 0.009\ncount = 10\nshape = { family = "
        "\"angular\", flakiness_index = 10, shape_index = 20 }\n",
        "at most one lab measure"}},
      {"lammps_pour_in_batches", {in_batches_to_lammps, "expected pour.batches = 1"}},
      {"lammps_layered_settle", {layered_in_lammps, "settle it in aggpack's DEM"}},
      {"corners_of_a_rounded",
       {"title = \"t\"\n[container]\nside = 0.05\nheight = 0.3\n[particles]\ndiameter = 0.009\ncount = 10\nshape = { family = "
        "\"rounded\", corners = 10 }\n",
        "angular grains"}},
  };
  for (const auto& [name, what] : cases) {
    std::ofstream(dir_ / (name + ".toml")) << what.first;
    const auto r = run_cli("run " + (dir_ / (name + ".toml")).string() + " --quiet --out " + (dir_ / name).string());
    EXPECT_EQ(r.exit_code, 2) << name << ": " << r.output;
    EXPECT_NE(r.output.find(what.second), std::string::npos) << name << ": " << r.output;
    EXPECT_FALSE(fs::exists(dir_ / name / "summary.json")) << name;
  }
  // A LAMMPS dump or a finished run's particles.csv holds spheres, not grains: the bridge's
  // commands outside a run refuse a scenario with grains, saying how to hand the bed over.
  std::ofstream(dir_ / "grains.toml") << kGrains;
  std::ofstream(dir_ / "some.dump") << "ITEM: TIMESTEP\n0\n";
  const auto i = run_cli("import-lammps " + (dir_ / "some.dump").string() + " --scenario " +
                         (dir_ / "grains.toml").string() + " --quiet --out " + (dir_ / "imported").string());
  EXPECT_EQ(i.exit_code, 2) << i.output;
  EXPECT_NE(i.output.find("import-lammps reads spheres only"), std::string::npos) << i.output;
  fs::create_directories(dir_ / "finished");
  std::ofstream(dir_ / "finished" / "summary.json") << "{\"scenario_file\": \"" << (dir_ / "grains.toml").string()
                                                    << "\"}";
  std::ofstream(dir_ / "finished" / "particles.csv") << "id,x,y,z,r,grain\n";
  const auto e = run_cli("export-lammps " + (dir_ / "finished").string() + " --out " + (dir_ / "exported").string());
  EXPECT_EQ(e.exit_code, 2) << e.output;
  EXPECT_NE(e.output.find("its particles.csv holds their spheres, not the grains"), std::string::npos) << e.output;
}

// `aggpack grading --shape`: what the grains of a grading would measure, beside the target, in
// words and in JSON; a shape the scenario reader refuses is refused the same way (exit 2).
TEST_F(CliGrains, GradingShowsWhatItsGrainsMeasureBesideTheTarget) {
  const std::string stone = "grading fu2003_table1_coarse --d-min '0.1 in' --shape 'family=\"angular\", spheres=4, ";
  auto r = run_cli(stone + "flakiness_index=18' --json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto shape = nlohmann::json::parse(r.output).at("shape");
  EXPECT_EQ(shape["target"]["measure"], "flakiness index (EN 933-3)");
  EXPECT_NEAR(shape["measured"]["flakiness_index_percent"].get<double>(), 18.0, 1.0);
  EXPECT_EQ(shape["fitted"], "flatness mean");
  EXPECT_EQ(shape["sizes_measured"], 256);
  EXPECT_NEAR(shape["templates_percent"].get<double>(), 18.0, 1.0);
  r = run_cli(stone + "templates=24, spread=0.2, flat_elongated=10, flat_elongated_ratio=2.5'");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // The target's ratio gets its own row, the target beside it.
  const auto row = r.output.find("flat and elongated 2.5:1 (D4791)");
  ASSERT_NE(row, std::string::npos) << r.output;
  const std::string line = r.output.substr(row, r.output.find('\n', row) - row);
  EXPECT_EQ(line.substr(line.size() - 5), " 10.0") << line;
  r = run_cli(stone + "flakiness_index=18, shape_index=5'");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--shape 'family="), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("at most one lab measure"), std::string::npos) << r.output;
}

}  // namespace

namespace {

// Issue 55, items 3, 4 and 5: what a grains scenario costs is known before the work. Angular
// grains of one sphere are spheres (they ran for minutes, 0.9 GB, printing nothing); a grain
// counts as its member spheres in limits.max_particles and the memory limit (2e6 grains of 64
// spheres passed as "2e+06 particles"); templates that would take minutes are refused by their
// estimate, naming the limit.
TEST_F(CliGrains, WhatGrainsCostIsKnownBeforeTheWork) {
  const auto one = run_cli("grading fu2003_table1_coarse --d-min \"0.187 in\" --d-max \"1 in\" --shape "
                           "'family=\"angular\", spheres=1' --json");
  ASSERT_EQ(one.exit_code, 0) << one.output;
  const auto shape = nlohmann::json::parse(one.output.substr(one.output.find('{'))).at("shape");
  EXPECT_NEAR(shape.at("measured").at("mean_elongation").get<double>(), 1.0, 1e-9) << shape.dump();

  std::ofstream(dir_ / "many.toml")
      << "title = \"many\"\n[container]\nside = \"2 m\"\nheight = \"4 m\"\n[particles]\ndiameter = 0.01\ncount = 2000000\n"
         "shape = { family = \"rounded\", spheres = 64 }\n[pour]\n[dynamics]\n[analysis]\nbox_sides = [0.1]\n";
  const auto many = run_cli("check " + (dir_ / "many.toml").string());
  EXPECT_EQ(many.exit_code, 2) << many.output;
  for (const char* word : {"1.28e+08 spheres: the grains' members counted", "limits.max_particles"})
    EXPECT_NE(many.output.find(word), std::string::npos) << word << " missing in\n" << many.output;
  const auto memory = run_cli("check " + (dir_ / "many.toml").string() +
                              " --set limits.max_particles=200000000 --set limits.max_memory_gib=100");
  EXPECT_EQ(memory.exit_code, 2) << memory.output;
  for (const char* word : {"GiB", "a grain's body", "limits.max_memory_gib"})
    EXPECT_NE(memory.output.find(word), std::string::npos) << word << " missing in\n" << memory.output;

  const auto costly = run_cli("grading fu2003_table1_coarse --d-min \"0.187 in\" --d-max \"1 in\" --shape "
                              "'family=\"angular\", templates=1000, spheres=64'");
  EXPECT_EQ(costly.exit_code, 2) << costly.output;
  EXPECT_NE(costly.output.find("minutes to make"), std::string::npos) << costly.output;
  std::ofstream(dir_ / "costly.toml")
      << "title = \"costly\"\n[container]\nside = 0.05\nheight = 0.3\n[particles]\ndiameter = 0.009\ncount = 300\n"
         "shape = { family = \"angular\", templates = 1000, spheres = 64, flakiness_index = 20 }\n[pour]\n"
         "[dynamics]\n[analysis]\nbox_sides = [0.005]\n";
  const auto refused = run_cli("check " + (dir_ / "costly.toml").string());
  EXPECT_EQ(refused.exit_code, 2) << refused.output;
  EXPECT_NE(refused.output.find("limits.max_template_minutes"), std::string::npos) << refused.output;
}

// Issue 55, item 5: SIGINT while the templates are made stops the run there: exit 130, the
// folder left as it was (nothing written), within a few seconds, not at the fit's end.
TEST_F(CliGrains, ARunStoppedWhileItsTemplatesAreMadeStopsThere) {
  std::ofstream(dir_ / "slow.toml")
      << "title = \"slow\"\n[container]\nside = 0.05\nheight = 0.3\n[particles]\ndiameter = 0.009\ncount = 300\n"
         "shape = { family = \"angular\", templates = 400, spheres = 40 }\n[pour]\n[dynamics]\n"
         "[analysis]\nbox_sides = [0.005]\n[limits]\nmax_template_minutes = 100\n";
  const std::string command = std::string("timeout --preserve-status -s INT 2 ") + AGGPACK_EXE + " run " +
                              (dir_ / "slow.toml").string() + " --threads 1 --out " + (dir_ / "slow").string();
  const auto start = std::chrono::steady_clock::now();
  const auto r = aggpack::testing::run_command(command);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_EQ(r.exit_code, 130) << r.output;
  EXPECT_NE(r.output.find("while making grain templates"), std::string::npos) << r.output;
  EXPECT_LT(seconds, 30.0);  // the fit of 400 templates of 40 spheres takes minutes
  EXPECT_FALSE(fs::exists(dir_ / "slow" / "summary.json"));
}

// Issue 55, items 20, 21 and 24: a bed of grains in words and files. The pour counts grains
// (tested in test_resume.cpp), coordination is "over N grains", the
// console shows each component's measured shape beside what was asked, particles.vtp has each
// sphere's component.
TEST_F(CliGrains, ABedOfGrainsIsToldAsGrains) {
  std::string grains_only = kGrains;
  grains_only.replace(grains_only.find(", {"), grains_only.find("}]\n") - grains_only.find(", {") + 1, "");
  std::ofstream(dir_ / "only.toml") << grains_only << "[output]\nvtp_encoding = \"ascii\"\n";
  const auto r = run_cli("run " + (dir_ / "only.toml").string() + " --threads 1 --out " + (dir_ / "only").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find(" grains\n"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("grains and spheres"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("elongation I/L"), std::string::npos) << r.output;
  const std::string vtp = slurp(dir_ / "only" / "particles.vtp");
  EXPECT_NE(vtp.find("Name=\"component\""), std::string::npos);

  std::ofstream(dir_ / "mixed.toml") << kGrains << "[output]\nvtp_encoding = \"ascii\"\n";
  const auto mixed = run_cli("run " + (dir_ / "mixed.toml").string() + " --threads 1 --out " +
                             (dir_ / "mixed2").string());
  ASSERT_EQ(mixed.exit_code, 0) << mixed.output;
  EXPECT_NE(mixed.output.find("grains and spheres"), std::string::npos) << mixed.output;
  const std::string mixed_vtp = slurp(dir_ / "mixed2" / "particles.vtp");
  const std::size_t array = mixed_vtp.find("Name=\"component\"");
  ASSERT_NE(array, std::string::npos);
  std::istringstream values(mixed_vtp.substr(mixed_vtp.find('>', array) + 1));
  std::set<int> components;
  for (int c = 0; values >> c;) components.insert(c);
  EXPECT_EQ(components, (std::set<int>{0, 1}));  // the grains' class and the spheres'
}

// Issue 55, item 21: `check` estimates the bed's depth from the grains' own volume, not the
// spheres of their reach: a cube the bed of flat grains cannot hold is refused before the DEM
// (the sieve sizes' spheres, 3.8 times the grains' volume, would leave room for it).
TEST_F(CliGrains, CheckRefusesACubeTheGrainsBedCannotHold) {
  std::ofstream(dir_ / "flakes.toml")
      << "title = \"flakes\"\n[container]\nside = 0.06\nheight = 0.3\n[particles]\ndiameter = 0.006\ncount = 600\n"
         "shape = { family = \"rounded\", spheres = 4, elongation = 0.8, flatness = 0.3, spread = 0 }\n[pour]\n"
         "[dynamics]\n[analysis]\nbox_sides = [0.012]\n";
  const auto r = run_cli("check " + (dir_ / "flakes.toml").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("leaves no room for a virtual cube"), std::string::npos) << r.output;
}

}  // namespace
