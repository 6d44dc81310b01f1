// aggpack specimen as a concrete modeller meets it: the largest virtual box of a run as the
// specimen, whose exact aggregate fraction is that box's density in summary.json; a periodic
// bed's particles across a side; a bed of grains; and bad input refused, nothing written.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "aggpack/analysis/sphere_box_volume.hpp"
#include "run_cli.hpp"

namespace {

namespace fs = std::filesystem;
using aggpack::testing::run_cli;

// 150 grains of two spheres and 40 spheres poured between periodic sides: two seconds.
constexpr const char* kPeriodicBed =
    "seed = 2\n[container]\nside = 0.045\nheight = 0.3\nsides = \"periodic\"\n[particles]\n"
    "classes = [{ diameter = 0.008, count = 150SHAPE }, { diameter = 0.005, count = 40 }]\n"
    "[material]\nyoungs_modulus = 1e7\nwall_youngs_modulus = 1e7\nfriction_particle = 0.5\n"
    "[pour]\nsolid_fraction = 0.15\n[dynamics]\nmax_time = 0.8\n[analysis]\nbox_sides = [0.01, 0.012]\n";

class CliSpecimen : public ::testing::Test {
 protected:
  aggpack::testing::ScratchDir scratch_{"aggpack_cli_specimen_"};
  const fs::path& dir_ = scratch_.path();
  static nlohmann::json json_of(const fs::path& file) { return nlohmann::json::parse(std::ifstream(file)); }
  // The periodic bed run into `name`, its grains of two spheres or, without, spheres.
  fs::path periodic_run(const std::string& name, bool grains) {
    std::string text = kPeriodicBed;
    text.replace(text.find("SHAPE"), 5,
                 grains ? ", shape = { family = \"rounded\", spheres = 2, templates = 3 }" : "");
    std::ofstream(dir_ / (name + ".toml")) << text;
    const auto r = run_cli("run " + (dir_ / (name + ".toml")).string() + " --quiet --threads 1 --out " +
                           (dir_ / name).string());
    EXPECT_EQ(r.exit_code, 0) << r.output;
    return dir_ / name;
  }
};

TEST_F(CliSpecimen, TheRunsLargestVirtualBoxIsTheSpecimenAndItsDensityTheAggregateFraction) {
  const fs::path run = periodic_run("grains", true);
  const auto r = run_cli("specimen " + run.string() + " --formats vti,inp,geo --out " + (dir_ / "s").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("aggregate fraction: exact"), std::string::npos) << r.output;
  const nlohmann::json spec = json_of(dir_ / "s" / "specimen.json");
  const nlohmann::json summary = json_of(run / "summary.json");
  const nlohmann::json& largest = summary["density"]["boxes"][1];
  ASSERT_NEAR(largest["side_m"].get<double>(), 0.012, 1e-15);
  EXPECT_EQ(spec["region"]["lo"], largest["lo"]);
  // The same region measured the same exact way (each grain's union cut by the box's planes).
  EXPECT_NEAR(spec["exact"]["aggregate_fraction"].get<double>(), largest["density"].get<double>(), 1e-9);
  EXPECT_NEAR(spec["voxels"]["aggregate_fraction"].get<double>(), largest["density"].get<double>(), 0.01);
  EXPECT_EQ(spec["files"], (std::vector<std::string>{"specimen.vti", "specimen.inp", "specimen.geo"}));
  for (const char* f : {"specimen.vti", "specimen.inp", "specimen.geo"}) EXPECT_TRUE(fs::exists(dir_ / "s" / f)) << f;
  // Again into the same folder, the voxel image alone: the earlier files go.
  const auto again = run_cli("specimen " + run.string() + " --formats vti --out " + (dir_ / "s").string());
  ASSERT_EQ(again.exit_code, 0) << again.output;
  EXPECT_FALSE(fs::exists(dir_ / "s" / "specimen.inp"));
  EXPECT_TRUE(fs::exists(dir_ / "s" / "specimen.vti"));
  EXPECT_EQ(spec["run"]["seed"], 2);
  bool grain_note = false;
  for (const auto& note : spec["modelling_notes"]) grain_note |= note.get<std::string>().rfind("a grain's size", 0) == 0;
  EXPECT_TRUE(grain_note) << spec["modelling_notes"];
}

// A box at the periodic sides' corner holds the spheres across both sides, by their images:
// against the exact volumes of every sphere and its eight images, summed here.
TEST_F(CliSpecimen, APeriodicBedsSpheresCountAcrossItsSides) {
  const fs::path run = periodic_run("spheres", false);
  const aggpack::Box box{{0.0, 0.0, 0.01}, {0.015, 0.015, 0.025}};
  const auto r = run_cli("specimen " + run.string() + " --box 0,0,0.01,0.015,0.015,0.025 --formats vti --json --out " +
                         (dir_ / "s").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::ifstream csv(run / "particles.csv");
  std::string line;
  std::getline(csv, line);
  double solid = 0.0;
  while (std::getline(csv, line)) {
    std::vector<double> v;
    std::istringstream fields(line);
    for (std::string f; std::getline(fields, f, ',');) v.push_back(std::stod(f));
    for (const int sx : {-1, 0, 1})
      for (const int sy : {-1, 0, 1})
        solid += aggpack::sphere_box_volume({v[1] + 0.045 * sx, v[2] + 0.045 * sy, v[3]}, v[4], box);
  }
  const nlohmann::json spec = json_of(dir_ / "s" / "specimen.json");
  EXPECT_NEAR(spec["exact"]["aggregate_fraction"].get<double>(), solid / box.volume(), 1e-12);
  EXPECT_GT(solid / box.volume(), 0.4);
}

TEST_F(CliSpecimen, BadInputIsRefusedBeforeAnythingIsWritten) {
  const fs::path run = periodic_run("spheres", false);
  const std::string to = " --out " + (dir_ / "bad").string();
  for (const auto& [args, words] : std::vector<std::pair<std::string, std::string>>{
           {"--box 0.01,0.01,0.01,0.03,0.03,0.5", "is not inside the bed"},
           {"--box -0.01,0.01,0.01,0.02,0.02,0.02", "is not inside the bed"},
           {"--box 1,1,1,1.1,1.1,1.1", "is not inside the bed"},
           {"--voxel 1e-6", "more than the limit"},
           {"--voxel -1mm", "--voxel -1mm: expected a positive length, not -0.001 m"},
           {"--gap abc", "--gap abc: expected a positive length ('abc' does not start with a number)"},
           {"--itz 3mm", "thicker than the gaps between the particles"},
           {"--formats vti,stl", "expected vti, inp, geo or msh"},
           {"--box 0,0,0,0.01,0.01,0.01 --cylinder 0.02,0.02,0,0.01,0.005", "give one specimen"},
           {"--cylinder 0.02,0.02,0.01,0.005,0.005", "expected X,Y,ZLO,ZHI,RADIUS"},
           {"--min-size 1", "holds no particle of the bed at or above the minimum size"},
           {"--max-voxels nan", "--max-voxels"},
           {"--voxel 0.00003 --max-voxels 1e12", "format inp"},
           // The image's memory checked before it is allocated (was std::bad_alloc).
           {"--max-voxels 1e30 --voxel 1e-6", "more than the memory limit"},
           // A voxel wider than the specimen (was a silent 1 x 1 x 1 image).
           {"--voxel 1", "wider than the specimen's smallest side"}}) {
    const auto r = run_cli("specimen " + run.string() + " " + args + to);
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.output;
    EXPECT_NE(r.output.find(words), std::string::npos) << args << "\n" << r.output;
    EXPECT_FALSE(fs::exists(dir_ / "bad")) << args;
  }
  // An output folder that cannot be made: an input error naming it (was an internal error).
  for (const auto& [out, words] : std::vector<std::pair<std::string, std::string>>{
           {"/proc/aggpack_specimen_x", "/proc/aggpack_specimen_x: cannot"},
           {(run / "summary.json").string(), "is a file, not a folder"},
           {(run / "summary.json" / "x").string(), "is a file, not a folder"}}) {
    const auto r = run_cli("specimen " + run.string() + " --formats vti --out " + out);
    EXPECT_EQ(r.exit_code, 2) << out << "\n" << r.output;
    EXPECT_NE(r.output.find(words), std::string::npos) << out << "\n" << r.output;
    EXPECT_EQ(r.output.find("internal error"), std::string::npos) << r.output;
  }
  const auto no_run = run_cli("specimen " + dir_.string() + to);
  EXPECT_EQ(no_run.exit_code, 2) << no_run.output;
  EXPECT_NE(no_run.output.find("a run's folder holds summary.json"), std::string::npos) << no_run.output;
  // A packing file has no virtual box to take: the specimen is given.
  const auto file = run_cli("specimen " + (run / "particles.csv").string() + to);
  EXPECT_EQ(file.exit_code, 2) << file.output;
  EXPECT_NE(file.output.find("give the specimen's box or cylinder"), std::string::npos) << file.output;
}

bool gmsh_installed() { return std::system("command -v gmsh > /dev/null 2>&1") == 0; }

// A mesh far beyond a machine is refused before any work, naming the flag (was handed to Gmsh:
// 1e-5 m elements in a 12 mm box, some 1e13 tetrahedra).
TEST_F(CliSpecimen, AnUnboundedMeshIsRefusedBeforeGmshStarts) {
  if (!gmsh_installed()) GTEST_SKIP() << "gmsh is not installed (Debian package gmsh)";
  const fs::path run = periodic_run("spheres", false);
  const auto r = run_cli("specimen " + run.string() + " --formats msh --gap 0.2mm --mesh-size 1e-5 --out " +
                         (dir_ / "mesh").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("format msh"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("--mesh-size"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir_ / "mesh"));
}

// A bed of grains meshed by Gmsh: each grain the union of its spheres (was: overlapping member
// spheres, "Invalid boundary mesh", and an empty specimen.msh left); the mesh in specimen.json.
TEST_F(CliSpecimen, AGrainsSpecimenIsMeshedByGmsh) {
  if (!gmsh_installed()) GTEST_SKIP() << "gmsh is not installed (Debian package gmsh)";
  const fs::path run = periodic_run("grains", true);
  const auto r = run_cli("specimen " + run.string() + " --box 0.01,0.01,0.01,0.02,0.02,0.02 --gap 0.3mm --formats msh "
                         "--mesh-size 1mm,2mm --out " + (dir_ / "g").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json spec = json_of(dir_ / "g" / "specimen.json");
  EXPECT_EQ(spec["files"], (std::vector<std::string>{"specimen.geo", "specimen.msh"}));
  EXPECT_NEAR(spec["gmsh"]["aggregate_fraction"].get<double>(), spec["exact"]["aggregate_fraction"].get<double>(), 0.02);
  EXPECT_NEAR(spec["gmsh"]["meshed_volume_over_region"].get<double>(), 1.0, 1e-6);
  // The console's count is the particles in the geometry; the .inp's size was said before.
  EXPECT_NE(r.output.find(std::to_string(spec["particles"]["kept"].get<std::size_t>()) + " particles in the specimen"),
            std::string::npos) << r.output;
}

// Whether a process whose command line names `word` is running (Gmsh's, by its folder).
bool process_naming(const std::string& word) {
  for (const auto& entry : fs::directory_iterator("/proc")) {
    std::ifstream cmdline(entry.path() / "cmdline");
    const std::string text((std::istreambuf_iterator<char>(cmdline)), std::istreambuf_iterator<char>());
    if (text.find(word) != std::string::npos && text.find("gmsh") != std::string::npos) return true;
  }
  return false;
}

// SIGTERM or SIGINT while Gmsh meshes: Gmsh stopped with aggpack (was: left meshing), its
// partial mesh removed, exit 128 + the signal as an interrupted run (was: SIGINT ignored, or
// "gmsh could not mesh", exit 2).
TEST_F(CliSpecimen, ASignalWhileGmshMeshesStopsGmshAndExits128PlusTheSignal) {
  if (!gmsh_installed()) GTEST_SKIP() << "gmsh is not installed (Debian package gmsh)";
  const fs::path run = periodic_run("spheres", false);
  for (const int signal_number : {SIGTERM, SIGINT}) {
    const fs::path out = dir_ / ("stop" + std::to_string(signal_number));
    // Fine elements: minutes of Gmsh's work, stopped once it has begun (its log is there).
    const auto code = aggpack::testing::signal_aggpack_when(
        {"specimen", run.string(), "--box", "0.01,0.01,0.01,0.022,0.022,0.022", "--gap", "0.3mm", "--formats",
         "geo,msh", "--mesh-size", "0.25mm,0.5mm", "--out", out.string()},
        [&] { return fs::exists(out / "gmsh.log") && process_naming(out.string()); }, signal_number);
    ASSERT_TRUE(code.has_value()) << "aggpack ended before Gmsh began";
    EXPECT_EQ(*code, 128 + signal_number);
    EXPECT_FALSE(fs::exists(out / "specimen.msh"));
    EXPECT_TRUE(fs::exists(out / "specimen.geo"));
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    EXPECT_FALSE(process_naming(out.string())) << "Gmsh still runs";
    const nlohmann::json spec = json_of(out / "specimen.json");
    EXPECT_EQ(spec["files"], (std::vector<std::string>{"specimen.geo"}));
  }
}

}  // namespace
