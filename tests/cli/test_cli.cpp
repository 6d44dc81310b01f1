// Runs the aggpack executable as a user would and checks exit codes and files.
#include <gtest/gtest.h>

#include "run_cli.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

using aggpack::testing::slurp;
using Result = aggpack::testing::CliResult;
Result run(const std::string& args) { return aggpack::testing::run_cli(args); }

class Cli : public ::testing::Test {
 protected:
  std::string example(const std::string& name) const { return std::string(AGGPACK_EXAMPLES) + "/" + name; }
  // Writes `text` as <name>.toml, runs it into <name>/ (expecting success) and returns its summary.
  nlohmann::json run_text(const std::string& name, const std::string& text, const std::string& extra = "") const {
    std::ofstream(dir_ / (name + ".toml")) << text;
    const Result r = run("run " + (dir_ / (name + ".toml")).string() + " --quiet --out " + (dir_ / name).string() + extra);
    EXPECT_EQ(r.exit_code, 0) << name << "\n" << r.output;
    return nlohmann::json::parse(std::ifstream(dir_ / name / "summary.json"));
  }
  // Each scenario text is refused with exit code 2, a message holding its expected words, and no output.
  void expect_refused(const std::vector<std::pair<std::string, std::string>>& cases) const {
    for (const auto& [text, expected] : cases) {
      std::ofstream(dir_ / "bad.toml") << text;
      const Result r = run("run " + (dir_ / "bad.toml").string() + " --out " + (dir_ / "bad").string());
      EXPECT_EQ(r.exit_code, 2) << text << "\n" << r.output;
      EXPECT_NE(r.output.find(expected), std::string::npos) << expected << "\n" << r.output;
      EXPECT_FALSE(fs::exists(dir_ / "bad"));
    }
  }
  aggpack::testing::ScratchDir scratch_{"aggpack_cli_"};
  const fs::path& dir_ = scratch_.path();
};

TEST_F(Cli, RunWritesTheThreeFilesAndTheSummaryKeys) {
  const fs::path out = dir_ / "run";
  const Result r = run("run " + example("cubic_lattice.toml") + " --quiet --seed 5 --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(r.output.empty()) << r.output;  // --quiet
  for (auto f : {"particles.csv", "particles.vtp", "summary.json"}) EXPECT_TRUE(fs::exists(out / f)) << f;
  for (const auto& e : fs::directory_iterator(out))
    EXPECT_EQ(e.path().string().find(".aggpack-incomplete."), std::string::npos) << "leftover " << e.path();
  const auto s = nlohmann::json::parse(std::ifstream(out / "summary.json"));
  EXPECT_EQ(s["seed"], 5);
  EXPECT_EQ(s["particle_count"], 1000);
  EXPECT_TRUE(s.contains("aggpack_version"));
  EXPECT_TRUE(s["scenario"].is_object());
  EXPECT_EQ(s["container"]["periodic"], false);
  EXPECT_NEAR(s["container"]["hi"][0].get<double>(), 0.254, 1e-12);
  ASSERT_EQ(s["density"]["boxes"].size(), 3u);
  for (const auto& b : s["density"]["boxes"]) {
    EXPECT_NEAR(b["density"].get<double>(), 0.5235987755982988, 1e-9);
    EXPECT_EQ(b["lo"].size(), 3u);
    EXPECT_TRUE(b.contains("side_m"));
  }
  EXPECT_NEAR(s["density"]["mean"].get<double>(), 0.5235987755982988, 1e-9);
  EXPECT_TRUE(s["stages"].is_object());
  EXPECT_TRUE(s["wall_clock_s"].contains("total"));
  EXPECT_DOUBLE_EQ(s["coordination"]["mean"].get<double>(), 6.0);
  std::ifstream csv(out / "particles.csv");
  std::string header, first;
  std::getline(csv, header);
  std::getline(csv, first);
  EXPECT_EQ(header, "id,x,y,z,r");
  EXPECT_EQ(first.substr(0, 2), "1,");  // one numbering, 1..N, as particles.vtp and LAMMPS
}

// A "--" in the scenario path went into the VTP's provenance comment unescaped: invalid XML,
// which VTK reads as 0 points.
TEST_F(Cli, VtpIsValidXmlWhenThePathHoldsTwoDashes) {
  const fs::path folder = dir_ / "runs--2026-";
  fs::create_directories(folder);
  fs::copy_file(example("cubic_lattice.csv"), folder / "cubic_lattice.csv");
  fs::copy_file(example("cubic_lattice.toml"), folder / "lattice--copy-.toml");
  const fs::path out = dir_ / "vtp";
  const Result r = run("run " + (folder / "lattice--copy-.toml").string() + " --quiet --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const Result xml = aggpack::testing::check_outputs("vtp " + (out / "particles.vtp").string() + " 1000");
  EXPECT_EQ(xml.exit_code, 0) << xml.output;
  const Result csv = aggpack::testing::check_outputs("csv " + (out / "particles.csv").string());
  EXPECT_EQ(csv.exit_code, 0) << csv.output;
}

// Issue 34, item 15: the VTP was ASCII (124 B a sphere). It is now VTK's zlib-compressed
// appended binary, decoded here by Python's zlib and struct (tests/tools/check_outputs.py),
// with each sphere's velocity, coordination and component beside its radius.
TEST_F(Cli, VtpIsZlibBinaryWithVelocityCoordinationAndComponent) {
  const std::string text = "seed = 3\n[container]\nside = 0.04\nheight = 0.3\n[particles]\norder = \"shuffled\"\n"
                           "classes = [{ diameter = 0.01, count = 80 }, { diameter = 0.005, count = 320 }]\n"
                           "[material]\nyoungs_modulus = 1e8\nwall_youngs_modulus = 1e8\n[deposition]\n"
                           "[dynamics]\nmax_time = 0.01\n[analysis]\nbox_sides = [0.02]\n";
  const auto summary = run_text("binary", text);
  const fs::path vtp = dir_ / "binary" / "particles.vtp";
  const std::string bytes = slurp(vtp);
  EXPECT_NE(bytes.find("compressor=\"vtkZLibDataCompressor\""), std::string::npos);
  EXPECT_NE(bytes.find("<AppendedData encoding=\"raw\">"), std::string::npos);
  EXPECT_EQ(bytes.find("format=\"ascii\""), std::string::npos);
  const double tolerance = summary.at("scenario").at("analysis").at("contact_tolerance").get<double>();
  const Result checked = aggpack::testing::check_outputs(
      "vtp " + vtp.string() + " 400 " + (dir_ / "binary" / "particles.csv").string() +
      " --arrays velocity,coordination,component --component-diameters 0.01,0.005 --contact-tolerance " +
      fmt::format("{}", tolerance));
  EXPECT_EQ(checked.exit_code, 0) << checked.output;
  // The same run written as ASCII holds the same arrays, value for value, at several times the size.
  run_text("ascii", text, " --set output.vtp_encoding=ascii");
  const fs::path ascii = dir_ / "ascii" / "particles.vtp";
  EXPECT_NE(slurp(ascii).find("format=\"ascii\""), std::string::npos);
  const Result same = aggpack::testing::check_outputs("vtp-same " + vtp.string() + " " + ascii.string());
  EXPECT_EQ(same.exit_code, 0) << same.output;
  EXPECT_LT(fs::file_size(vtp) * 2, fs::file_size(ascii));
  // The DEM was cut while the bed still moved: the velocities are the bed's, not zeros.
  EXPECT_EQ(summary.at("settled"), false);
  const Result moving = aggpack::testing::check_outputs("vtp " + vtp.string() + " 400 --nonzero velocity");
  EXPECT_EQ(moving.exit_code, 0) << moving.output;
  // Byte for byte the same for any thread count.
  const Result threads = run("run " + (dir_ / "binary.toml").string() + " --quiet --threads 2 --out " +
                             (dir_ / "threads").string());
  ASSERT_EQ(threads.exit_code, 0) << threads.output;
  EXPECT_EQ(slurp(dir_ / "threads" / "particles.vtp"), bytes);
  // 400 spheres are too few to gain from a second thread: every step ran on one, and the
  // summary says so.
  const auto two = nlohmann::json::parse(std::ifstream(dir_ / "threads" / "summary.json")).at("stages").at("dynamics");
  EXPECT_EQ(two.at("threads"), 2);
  EXPECT_GT(two.at("steps").get<std::size_t>(), 0u);
  EXPECT_EQ(two.at("steps_on_fewer_threads"), two.at("steps"));
}

TEST_F(Cli, BadInputExitsWithTwoAndWritesNothing) {
  const fs::path out = dir_ / "bad";
  const std::vector<std::string> bad_runs = {
      "run " + example("cubic_lattice.toml") + " --set analysis.box_sides='[\"9 in\"]'",  // cube does not fit
      "run " + example("cubic_lattice.toml") + " --set material.density=-1",
      "run " + example("cubic_lattice.toml") + " --set container.side='\"5 in\"'",  // particles outside
      "run " + example("cubic_lattice.toml") + " --stop-after deposition",  // no such stage here
      "run " + example("example1.toml") + " --stop-after sieving",
      "run " + example("example1.toml") + " --set analysis.box_sides='[\"11 in\"]'",  // too big for the bed
      "run " + example("table2_mix3.toml") + " --set container.side='\"40 in\"' --set particles.fine.d_min="
                                            "'\"0.15 mm\"'",  // about 10^9 sand grains
      "run " + (dir_ / "missing.toml").string(),
      "run",  // missing argument
      "frobnicate",
  };
  for (const auto& args : bad_runs) {
    const Result r = run(args + " --out " + out.string());
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.output;
    EXPECT_FALSE(fs::exists(out)) << args;
  }
  const Result r = run("run " + example("cubic_lattice.toml") + " --set material.densty=1 --out " + out.string());
  EXPECT_NE(r.output.find("did you mean 'density'"), std::string::npos) << r.output;
}

// "aggpack bogus" said "A subcommand is required".
TEST_F(Cli, AnUnknownSubcommandIsNamedWithTheList) {
  const Result r = run("bogus");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("unknown subcommand 'bogus'; the subcommands are: run, resume, check, analyze, grading, "
                          "predict, material, calibrate, whole-grading, reproduce, sweep, test, blend, export-lammps, "
                          "import-lammps"),
            std::string::npos)
      << r.output;
  EXPECT_EQ(r.output.find("A subcommand is required"), std::string::npos) << r.output;
  EXPECT_EQ(run("").exit_code, 2);  // none at all is still CLI11's own message
}

// The paper's Example 1 end to end: deposition, analysis and every output file.
TEST_F(Cli, RunsExample1ThroughDeposition) {
  const fs::path out = dir_ / "ex1";
  const Result r = run("run " + example("example1.toml") + " --stop-after deposition --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // A scenario written in inches reads its lengths in inches too, beside SI.
  EXPECT_NE(r.output.find("  virtual cube 0.1524 m (6 in): density "), std::string::npos) << r.output;
  const nlohmann::json s = nlohmann::json::parse(std::ifstream(out / "summary.json"));
  const auto& d = s["stages"]["deposition"];
  EXPECT_EQ(d["particles_placed"].get<int>(), 1733);
  EXPECT_EQ(d["end"], "all_placed");
  EXPECT_EQ(d["density"]["boxes"].size(), 3u);
  // Random loose packing by three-point supports: well above random loose (0.55), below 0.62.
  EXPECT_GT(d["density"]["mean"].get<double>(), 0.56);
  EXPECT_LT(d["density"]["mean"].get<double>(), 0.62);
  EXPECT_GT(d["coordination"]["mean"].get<double>(), 5.5);
  EXPECT_EQ(d["redrops"].get<int>(), 0);
  std::ifstream supports(out / "supports.csv");
  std::string header, first;
  std::getline(supports, header);
  std::getline(supports, first);
  // Typed columns (a kind, a sphere id; pandas read the old mixed column as floats) and one
  // numbering 1..N, as particles.csv, particles.vtp and the LAMMPS files.
  EXPECT_EQ(header, "id,support_1_kind,support_1_id,support_2_kind,support_2_id,support_3_kind,support_3_id");
  EXPECT_EQ(first, "1,floor,0,none,0,none,0");
  std::size_t resting_on_spheres = 0;
  for (std::string row; std::getline(supports, row);) {
    std::vector<std::string> cells;
    std::istringstream cells_in(row);
    for (std::string cell; std::getline(cells_in, cell, ',');) cells.push_back(cell);
    ASSERT_EQ(cells.size(), 7u) << row;
    for (std::size_t k = 1; k < 7; k += 2) {
      const long sphere = std::stol(cells[k + 1]);
      if (cells[k] == "sphere") {
        ++resting_on_spheres;
        EXPECT_GE(sphere, 1) << row;
        EXPECT_LT(sphere, std::stol(cells[0])) << row;  // placed earlier
      } else {
        EXPECT_EQ(sphere, 0) << row;
      }
    }
  }
  EXPECT_GT(resting_on_spheres, 1000u);
  // Same seed, same bytes; another seed, another packing.
  const fs::path again = dir_ / "ex1b", other = dir_ / "ex1c";
  ASSERT_EQ(run("run " + example("example1.toml") + " --stop-after deposition --out " + again.string()).exit_code, 0);
  ASSERT_EQ(run("run " + example("example1.toml") + " --stop-after deposition --seed 2 --out " + other.string())
                .exit_code, 0);
  EXPECT_EQ(slurp(out / "particles.csv"), slurp(again / "particles.csv"));
  EXPECT_NE(slurp(out / "particles.csv"), slurp(other / "particles.csv"));
}

// A grading-based run: the sizes report in summary.json and on the terminal.
TEST_F(Cli, RunsFromAGradingAndReportsTheGeneratedCurve) {
  const fs::path scenario = dir_ / "graded.toml";
  std::ofstream(scenario) << "[container]\nside = \"6 in\"\nheight = \"12 in\"\n"
                             "[particles]\ncount = 800\n[particles.grading]\nname = \"astm_c33_57_mid\"\n"
                             "d_min = \"0.3 in\"\nband = \"astm_c33_57\"\n[deposition]\n";
  const fs::path out = dir_ / "graded";
  const Result r = run("run " + scenario.string() + " --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("band astm_c33_57: inside at every sieve"), std::string::npos) << r.output;
  const nlohmann::json s = nlohmann::json::parse(std::ifstream(out / "summary.json"));
  const auto& sizes = s["sizes"];
  EXPECT_EQ(sizes["method"], "grading");
  EXPECT_EQ(sizes["count"].get<int>(), 800);
  EXPECT_GE(sizes["d_min_m"].get<double>(), 0.3 * 0.0254);
  const auto& c = sizes["components"][0];
  EXPECT_GT(c["cut_below_fraction"].get<double>(), 0.0);
  EXPECT_EQ(c["sieves"].size(), 5u);
  EXPECT_TRUE(c["band"]["all_inside"].get<bool>());
  bool noted = false;
  for (const auto& note : s["modelling_notes"]) noted = noted || note.get<std::string>().find("cut off") != std::string::npos;
  EXPECT_TRUE(noted);
  EXPECT_EQ(s["stages"]["deposition"]["particles_placed"].get<int>(), 800);
}

TEST_F(Cli, GradingPrintsAndChecksWithoutARun) {
  Result r = run("grading astm_c33_fine_mid --band astm_c33_fine");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("fineness modulus 2.80"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("inside at every sieve"), std::string::npos) << r.output;
  r = run("grading fu2003_table1_coarse --mix astm_c33_fine_mid --ca-fa 1.52 --d-min '0.1 in' --json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto j = nlohmann::json::parse(r.output);
  // The blend at #4 (4.75 mm, the inch table's 0.185 in taken as it): (1.52 x 6.8 % + 97.5 %) / 2.52.
  bool found = false;
  std::set<std::string> names;
  for (const auto& s : j["mix"]["sieves"]) {
    EXPECT_TRUE(names.insert(s["sieve"].get<std::string>()).second) << "sieve twice: " << s;
    if (s["sieve"] == "#4") {
      found = true;
      EXPECT_NEAR(s["percent_passing"].get<double>(), (1.52 * 6.8 + 97.5) / 2.52, 1e-12);
    }
  }
  EXPECT_TRUE(found);
  EXPECT_EQ(j["grading"]["snapped_sieves"].size(), 11u);
  // The README's own example, with the sand shipped in examples/.
  r = run("grading fu2003_table1_coarse --mix " + example("sand_example.csv") + " --ca-fa 1.52 --d-min '0.1 in'");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("#16 1.245 -> 1.18 mm"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("1.245      "), std::string::npos) << r.output;  // no inch-converted row left
  EXPECT_GT(j["cut"]["cut_below_fraction"].get<double>(), 0.3);
  EXPECT_EQ(run("grading no_such_grading").exit_code, 2);
  EXPECT_EQ(run("grading astm_c33_fine_mid --band astm_c33_99").exit_code, 2);
  EXPECT_EQ(run("grading astm_c33_fine_mid --d-min '20 mm'").exit_code, 2);
  r = run("grading --list");
  EXPECT_NE(r.output.find("band astm_c33_67"), std::string::npos);
}

// Issue 34: the shipped sand under a bare `opening` header was read in inches (fineness
// modulus 7.53, a blend's CPM density 0.6713 for 0.7561). Its unit now comes from the header,
// the values, the scenario's length_unit or --length-unit, and the reading is the same.
TEST_F(Cli, ASieveFileReadsInTheUnitItSaysAndABareOpeningNeedsOne) {
  std::ifstream shipped(example("sand_example.csv"));
  std::string text((std::istreambuf_iterator<char>(shipped)), std::istreambuf_iterator<char>());
  ASSERT_NE(text.find("sieve,opening_mm,"), std::string::npos);
  std::ofstream(dir_ / "mm.csv") << text;
  std::ofstream(dir_ / "bare.csv") << text.replace(text.find("sieve,opening_mm,"), 17, "sieve,opening,");
  const auto fineness = [](const Result& r) {
    EXPECT_EQ(r.exit_code, 0) << r.output;
    return nlohmann::json::parse(r.output).at("grading").at("fineness_modulus").get<double>();
  };
  const double fm = fineness(run("grading " + (dir_ / "mm.csv").string() + " --json"));
  EXPECT_EQ(fineness(run("grading " + (dir_ / "bare.csv").string() + " --length-unit mm --json")), fm);
  Result r = run("grading " + (dir_ / "bare.csv").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("#200 is 0.075 mm"), std::string::npos) << r.output;
  // Read in inches the sieve column contradicts it.
  r = run("grading " + (dir_ / "bare.csv").string() + " --length-unit in");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("'#200'"), std::string::npos) << r.output;

  // A Table 2 mix with this sand: the same blend's CPM density from either file.
  std::ifstream mix3(example("table2_mix3.toml"));
  std::string mix((std::istreambuf_iterator<char>(mix3)), std::istreambuf_iterator<char>());
  const auto with_sand = [&](const std::string& name, const std::string& keys) {
    std::string scenario = mix;
    scenario.replace(scenario.find("name = \"astm_c33_fine_mid\""), 26, "file = \"" + name + "\"" + keys);
    std::ofstream(dir_ / "mix.toml") << scenario;
    return run("predict " + (dir_ / "mix.toml").string() + " --json");
  };
  const auto density = [](const Result& p) {
    EXPECT_EQ(p.exit_code, 0) << p.output;
    return nlohmann::json::parse(p.output.substr(p.output.find('{')))
        .at("whole_grading").at("cpm").at("density").get<double>();
  };
  const double blend = density(with_sand("mm.csv", ""));
  EXPECT_EQ(density(with_sand("bare.csv", "\nlength_unit = \"mm\"")), blend);
  r = with_sand("bare.csv", "");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  const auto header_line = 1 + std::count(text.begin(), text.begin() + text.find("sieve,opening,"), '\n');
  EXPECT_NE(r.output.find("bare.csv:" + std::to_string(header_line) + ": the column 'opening' gives no unit"),
            std::string::npos)
      << r.output;
}

TEST_F(Cli, CheckValidatesWithoutWriting) {
  EXPECT_EQ(run("check " + example("cubic_lattice.toml")).exit_code, 0);
  const Result bad = run("check " + example("cubic_lattice.toml") + " --set analysis.box_sides='[\"9 in\"]'");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.output.find("largest admissible side"), std::string::npos) << bad.output;
}

TEST_F(Cli, AnalyzeMeasuresAFileFromAnotherToolAsJson) {
  const fs::path f = dir_ / "lattice.txt";
  {
    std::ofstream out(f);
    for (int k = 0; k < 6; ++k)
      for (int j = 0; j < 6; ++j)
        for (int i = 0; i < 6; ++i) out << i + 0.5 << " " << j + 0.5 << " " << k + 0.5 << " 0.5\n";
  }
  const Result r = run("analyze " + f.string() + " --length-unit mm --box 1mm,1mm,1mm,5mm,4mm,3mm --cube 2mm --json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto j = nlohmann::json::parse(r.output);
  ASSERT_EQ(j["density"]["boxes"].size(), 2u);
  for (const auto& b : j["density"]["boxes"]) EXPECT_NEAR(b["density"].get<double>(), 0.5235987755982988, 1e-9);
  EXPECT_EQ(j["particle_count"], 216);
  EXPECT_EQ(run("analyze " + f.string() + " --box 1,2,3").exit_code, 2);
}

// Bare numbers in --box and --cube are in the file's --length-unit (they were read as metres,
// giving an empty box and "density 0.000000" with exit 0).
TEST_F(Cli, AnalyzeBoxAndCubeTakeTheFilesLengthUnit) {
  const std::string lattice = example("lattice_mm.txt");  // 10 mm spheres, 0..80 mm
  Result r = run("analyze " + lattice + " --length-unit mm --box 10,10,10,60,60,60 --json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  auto j = nlohmann::json::parse(r.output);
  EXPECT_NEAR(j["density"]["boxes"][0]["hi"][0].get<double>(), 0.06, 1e-15);
  EXPECT_NEAR(j["density"]["mean"].get<double>(), 0.5235987755982988, 1e-9);
  r = run("analyze " + lattice + " --length-unit mm --cube 40 --json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  j = nlohmann::json::parse(r.output);
  EXPECT_NEAR(j["density"]["boxes"][0]["side_m"].get<double>(), 0.04, 1e-15);
  // Explicit units still win over the file's.
  r = run("analyze " + lattice + " --length-unit mm --box \"1 cm,1 cm,1 cm,0.06 m,0.06 m,0.06 m\" --json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NEAR(nlohmann::json::parse(r.output)["density"]["mean"].get<double>(), 0.5235987755982988, 1e-9);
}

TEST_F(Cli, AnalyzeRefusesABoxOutsideThePackingOrWithNoSphere) {
  const std::string lattice = example("lattice_mm.txt");
  // Metres by mistake: the box lies far outside the packing.
  Result r = run("analyze " + lattice + " --length-unit mm --box 10m,10m,10m,60m,60m,60m");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("does not lie inside the packing, which spans [0, 0.08] x [0, 0.08] x [0, 0.08] m"),
            std::string::npos)
      << r.output;
  // Inside the bounding box but in the gap between four spheres along an edge: no solid at all.
  r = run("analyze " + lattice + " --length-unit mm --box 0,0,0,0.5,0.5,80");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("holds no sphere"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("density 0"), std::string::npos) << r.output;
}

// A small bed of 1 cm spheres, deposited then settled; soft contacts keep it quick.
std::string settling_scenario(int layers) {
  return "[container]\nside = 0.06\nheight = 0.5\n"
         "[particles]\ndiameter = 0.01\ncount = 400\n"
         "[material]\nyoungs_modulus = 1e8\nwall_youngs_modulus = 1e8\nfriction_particle = 0.3\n"
         "[deposition]\n"
         "[dynamics]\nmax_time = 0.4\nlayers = " + std::to_string(layers) + "\n"
         "[analysis]\nbox_sides = [0.03]\n";
}

std::vector<std::string> lines_of(const fs::path& file) {
  std::ifstream in(file);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

TEST_F(Cli, RunsDepositionThenDynamicsAndWritesTheTimeSeries) {
  const fs::path scenario = dir_ / "settle.toml", out = dir_ / "settle";
  std::ofstream(scenario) << settling_scenario(1);
  const Result r = run("run " + scenario.string() + " --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("density after deposition"), std::string::npos) << r.output;
  const auto s = nlohmann::json::parse(std::ifstream(out / "summary.json"));
  const auto& d = s["stages"]["dynamics"];
  for (const char* key : {"ended_by", "simulated_time_s", "steps", "time_step_s", "rayleigh_time_s", "skin_m",
                          "neighbour_list_builds", "final", "density", "coordination", "wall_clock_s",
                          "particle_steps_per_second", "memory_bytes_per_particle", "runs"})
    EXPECT_TRUE(d.contains(key)) << key;
  EXPECT_NEAR(d["time_step_s"].get<double>(), 0.2 * d["rayleigh_time_s"].get<double>(), 1e-15);
  EXPECT_GE(d["density"]["mean"].get<double>(), s["stages"]["deposition"]["density"]["mean"].get<double>() - 0.002);
  EXPECT_GT(d["final"]["max_overlap_rel"].get<double>(), 0.0);
  EXPECT_LT(d["final"]["max_overlap_rel"].get<double>(), 0.05);
  bool noted = false;
  for (const auto& note : s["modelling_notes"]) noted |= note.get<std::string>().find("Mindlin") != std::string::npos;
  EXPECT_TRUE(noted);

  const auto rows = lines_of(out / "timeseries.csv");
  ASSERT_GT(rows.size(), 11u);
  EXPECT_EQ(rows[0], "time_s,layer,density,translational_energy_per_particle_mgd,translational_energy_j,"
                     "rotational_energy_j,mean_overlap_rel,max_overlap_rel,coordination");
  const auto steps_per_sample = static_cast<std::size_t>(std::llround(1e-3 / d["time_step_s"].get<double>()));
  EXPECT_EQ(rows.size() - 1, d["steps"].get<std::size_t>() / steps_per_sample + 1);  // one sample at the start
  // Every CSV loads as plain pandas.read_csv(path): the header first, no comment lines.
  const Result csv_check = aggpack::testing::check_outputs(
      "csv " + (out / "timeseries.csv").string() + " " + (out / "particles.csv").string() + " " +
      (out / "supports.csv").string());
  EXPECT_EQ(csv_check.exit_code, 0) << csv_check.output;
  const double last_time = std::stod(rows.back().substr(0, rows.back().find(',')));
  EXPECT_NEAR(last_time, d["simulated_time_s"].get<double>(), 1e-9);

  // Same bytes with one thread as with two.
  const fs::path one = dir_ / "one", two = dir_ / "two";
  ASSERT_EQ(run("run " + scenario.string() + " --quiet --threads 1 --out " + one.string()).exit_code, 0);
  ASSERT_EQ(run("run " + scenario.string() + " --quiet --threads 2 --out " + two.string()).exit_code, 0);
  EXPECT_EQ(slurp(one / "particles.csv"), slurp(two / "particles.csv"));
  EXPECT_EQ(slurp(one / "timeseries.csv"), slurp(two / "timeseries.csv"));

  // --stop-after deposition leaves the stage out and says so.
  const fs::path early = dir_ / "early";
  ASSERT_EQ(run("run " + scenario.string() + " --quiet --stop-after deposition --out " + early.string()).exit_code, 0);
  EXPECT_FALSE(fs::exists(early / "timeseries.csv"));
  const auto e = nlohmann::json::parse(std::ifstream(early / "summary.json"));
  EXPECT_FALSE(e["stages"].contains("dynamics"));
  EXPECT_EQ(e["density"], s["stages"]["deposition"]["density"]);

  // The settled bed reads back: its Hertz overlaps of the floor and walls are contacts, not intrusions.
  const fs::path again = dir_ / "again.toml";
  std::ofstream(again) << "[container]\nside = 0.06\nheight = 0.5\n[particles]\nfrom = \""
                       << (out / "particles.csv").string() << "\"\n[analysis]\nbox_sides = [0.03]\n";
  const Result back = run("run " + again.string() + " --quiet --out " + (dir_ / "again").string());
  ASSERT_EQ(back.exit_code, 0) << back.output;
  const auto a = nlohmann::json::parse(std::ifstream(dir_ / "again" / "summary.json"));
  EXPECT_GT(a["input"]["largest_boundary_overlap_rel"].get<double>(), 0.0);
  EXPECT_LT(a["input"]["largest_boundary_overlap_rel"].get<double>(), 0.02);
  EXPECT_EQ(a["density"]["mean"], s["density"]["mean"]);  // the same bed, the same boxes
  bool overlap_noted = false;
  for (const auto& note : a["modelling_notes"])
    overlap_noted |= note.get<std::string>().find("overlap the floor or walls by up to") != std::string::npos;
  EXPECT_TRUE(overlap_noted);
  // A sphere pushed a tenth of its radius into the floor is refused, by name and depth.
  const fs::path intruder = dir_ / "intruder.csv";
  std::ofstream(intruder) << "x,y,z,r\n0.03,0.03,0.0045,0.005\n";
  std::ofstream(again) << "[container]\nside = 0.06\nheight = 0.5\n[particles]\nfrom = \"" << intruder.string()
                       << "\"\n[analysis]\nbox_sides = [0.001]\n";
  const Result refused = run("run " + again.string() + " --quiet --out " + (dir_ / "refused").string());
  EXPECT_EQ(refused.exit_code, 2) << refused.output;
  EXPECT_NE(refused.output.find("particle 0 (data row 1) at (0.03, 0.03, 0.0045) m, radius 0.005 m, reaches "
                                "0.0005 m (0.1 r) beyond the floor"),
            std::string::npos)
      << refused.output;
  EXPECT_FALSE(fs::exists(dir_ / "refused"));
}

// An explicit [[protocol]] runs the steps as given: the default order written out gives the
// same bytes, the layered mode is plain data, and an analyse step between two others reports
// the bed at that point under its own name.
TEST_F(Cli, AnExplicitProtocolRunsItsSteps) {
  const std::string base = "[container]\nside = 0.06\nheight = 0.5\n[particles]\ndiameter = 0.01\ncount = 300\n"
                           "[material]\nyoungs_modulus = 1e8\nwall_youngs_modulus = 1e8\n[deposition]\n"
                           "[analysis]\nbox_sides = [0.02]\n";
  // The default protocol, and the same written out with an extra analysis after the deposition.
  const auto implicit = run_text("implicit", base + "[dynamics]\nmax_time = 0.03\n");
  const auto explicit_run =
      run_text("explicit", base + "[dynamics]\nmax_time = 0.03\n"
                                  "[[protocol]]\nstep = \"deposit\"\n"
                                  "[[protocol]]\nstep = \"analyse\"\nname = \"deposition\"\n"
                                  "[[protocol]]\nstep = \"analyse\"\nname = \"loose\"\n"
                                  "[[protocol]]\nstep = \"settle\"\n");
  EXPECT_EQ(slurp(dir_ / "implicit" / "particles.csv"), slurp(dir_ / "explicit" / "particles.csv"));
  EXPECT_EQ(implicit["density"], explicit_run["density"]);
  EXPECT_EQ(explicit_run["stages"]["loose"]["density"], implicit["stages"]["deposition"]["density"]);
  EXPECT_EQ(explicit_run["stages"]["loose"]["coordination"], implicit["stages"]["deposition"]["coordination"]);
  EXPECT_EQ(explicit_run["scenario"]["protocol"].size(), 4u);
  EXPECT_TRUE(explicit_run["wall_clock_s"].contains("analysis_after_loose"));
  // --stop-after names an analyse step like a stage.
  const auto stopped = run_text("stopped", base + "[dynamics]\nmax_time = 0.03\n"
                                                  "[[protocol]]\nstep = \"deposit\"\n"
                                                  "[[protocol]]\nstep = \"analyse\"\nname = \"loose\"\n"
                                                  "[[protocol]]\nstep = \"settle\"\n",
                                " --stop-after loose");
  EXPECT_FALSE(stopped["stages"].contains("dynamics"));
  EXPECT_EQ(stopped["density"], implicit["stages"]["deposition"]["density"]);
  // Layer by layer as data: the same bytes as dynamics.layers = 2.
  run_text("layers_key", base + "[dynamics]\nmax_time = 0.02\nlayers = 2\n");
  run_text("layers_steps", base + "[dynamics]\nmax_time = 0.02\n"
                                  "[[protocol]]\nstep = \"deposit\"\nlayer = 0\nlayers = 2\n"
                                  "[[protocol]]\nstep = \"settle\"\nlayer = 0\n"
                                  "[[protocol]]\nstep = \"deposit\"\nlayer = 1\nlayers = 2\n"
                                  "[[protocol]]\nstep = \"settle\"\nlayer = 1\n");
  EXPECT_EQ(slurp(dir_ / "layers_key" / "particles.csv"), slurp(dir_ / "layers_steps" / "particles.csv"));
  EXPECT_EQ(slurp(dir_ / "layers_key" / "timeseries.csv"), slurp(dir_ / "layers_steps" / "timeseries.csv"));
}

// A step kind added after the loop (the proof that a new kind leaves the loop alone): a
// snapshot writes the bed at its point as particles_<name>.csv.
// aggpack predict: the models without a simulation; the same block in every summary.json.
TEST_F(Cli, PredictGivesTheModelsOfAScenarioOrAGrading) {
  const auto json = [](const Result& r) { return nlohmann::json::parse(r.output.substr(r.output.find('{'))); };
  // One size: CPM's monosized density beta / (1 + 1/K), for the defaults and for given values.
  Result r = run("predict " + example("example1.toml") + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NEAR(json(r).at("simulated").at("cpm").at("density").get<double>(), 0.72 / (1.0 + 1.0 / 4.1), 1e-12);
  r = run("predict " + example("example1.toml") + " --json --k 9 --beta 0.64");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto given = json(r);
  EXPECT_NEAR(given.at("simulated").at("cpm").at("density").get<double>(), 0.64 / (1.0 + 1.0 / 9.0), 1e-12);
  EXPECT_EQ(given.at("parameters").at("cpm_compaction_index_source"), "--k");
  EXPECT_EQ(json(run("predict " + example("example1.toml") + " --json --process vibrated_compressed"))
                .at("parameters")
                .at("cpm_compaction_index"),
            9.0);
  // A tapped protocol takes vibration's K until calibrated.
  EXPECT_EQ(json(run("predict " + example("example2_tapped.toml") + " --json")).at("parameters").at("cpm_compaction_index"),
            4.75);
  // A binary mix has Furnas's limit; a cut grading has its whole grading too, denser with its fines.
  const auto binary = json(run("predict " + example("example2.toml") + " --json")).at("simulated");
  EXPECT_GT(binary.at("furnas").at("densest").get<double>(), binary.at("cpm").at("density").get<double>());
  const auto mix = json(run("predict " + example("table2_mix3.toml") + " --json"));
  EXPECT_GT(mix.at("whole_grading").at("cpm").at("density").get<double>(),
            mix.at("simulated").at("cpm").at("density").get<double>());
  EXPECT_TRUE(mix.at("whole_grading").at("desmond_weeks").at("random_close_packing").is_null());  // beyond its fit
  // Gradings by name, alone or blended.
  r = run("predict fu2003_table1_coarse --mix astm_c33_fine_mid --ca-fa 1.5");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("CPM (K 4.1, beta 0.72): density 0."), std::string::npos) << r.output;
  // The sand's own beta: equal to the coarse one changes nothing; a looser sand packs the blend looser.
  const std::string blend = "predict fu2003_table1_coarse --mix astm_c33_fine_mid --ca-fa 1.5 --json";
  const auto density = [](const nlohmann::json& j) { return j.at("whole_grading").at("cpm").at("density").get<double>(); };
  const auto spheres = json(run(blend)), same = json(run(blend + " --beta-fine 0.72")),
             sand = json(run(blend + " --beta-fine 0.6"));
  EXPECT_EQ(density(same), density(spheres));
  EXPECT_LT(density(sand), density(spheres) - 0.02);
  EXPECT_EQ(sand.at("parameters").at("cpm_residual_packing_density_fine"), 0.6);
  EXPECT_EQ(sand.at("parameters").at("cpm_residual_packing_density_fine_source"), "--beta-fine");
  EXPECT_FALSE(spheres.at("parameters").contains("cpm_residual_packing_density_fine"));
  EXPECT_LT(density(json(run("predict " + example("table2_mix3.toml") + " --json --beta-fine 0.6"))),
            density(mix));
  // Every shipped scenario (a particle file's included) and every shipped grading has a CPM density.
  for (const auto& entry : fs::directory_iterator(AGGPACK_EXAMPLES)) {
    if (entry.path().extension() != ".toml") continue;
    const Result p = run("predict " + entry.path().string() + " --json");
    ASSERT_EQ(p.exit_code, 0) << entry.path() << "\n" << p.output;
    const auto j = json(p);
    const double d = j.at("simulated").at("cpm").at("density").get<double>();
    EXPECT_GT(d, 0.5) << entry.path();
    EXPECT_LT(d, 0.8) << entry.path();
  }
  std::istringstream listed(run("grading --list").output);
  std::vector<std::string> gradings;
  for (std::string kind, name; listed >> kind >> name;)
    if (kind == "grading") gradings.push_back(name);  // not the bands: a band is two curves
  ASSERT_GE(gradings.size(), 10u);
  for (const std::string& grading : gradings) {
    const Result p = run("predict " + grading + " --json");
    ASSERT_EQ(p.exit_code, 0) << grading << "\n" << p.output;
    const double d = json(p).at("whole_grading").at("cpm").at("density").get<double>();
    EXPECT_GT(d, 0.55) << grading;
    EXPECT_LT(d, 0.85) << grading;
  }
  // Refused, exit 2, saying why.
  for (const auto& [args, words] : std::vector<std::pair<std::string, std::string>>{
           {"predict fu2003_table1_coarse --mix astm_c33_fine_mid", "--mix and --ca-fa go together"},
           // A blend's ratio has no default in either command (grading blended 1:1 without a word).
           {"grading fu2003_table1_coarse --mix astm_c33_fine_mid", "--mix and --ca-fa go together"},
           {"grading fu2003_table1_coarse --ca-fa 1.5", "--mix and --ca-fa go together"},
           {"grading fu2003_table1_coarse --mix astm_c33_fine_mid --ca-fa 0", "--ca-fa 0: expected a number above 0"},
           {"predict " + example("example1.toml") + " --k 5 --process poured", "give one"},
           {"predict " + example("example1.toml") + " --beta 1.5", "between 0 and 1"},
           {"predict " + example("example1.toml") + " --process shaken", "expected poured, rodded"},
           {"predict no_such_grading", "neither a shipped grading"},
           {"predict " + example("example2.toml") + " --beta-fine 0.6", "applies to a blend's fine aggregate"},
           {"predict fu2003_table1_coarse --mix astm_c33_fine_mid --ca-fa 1.5 --beta-fine 0", "between 0 and 1"}}) {
    const Result bad = run(args);
    EXPECT_EQ(bad.exit_code, 2) << args << "\n" << bad.output;
    EXPECT_NE(bad.output.find(words), std::string::npos) << args << "\n" << bad.output;
  }
  // Every run's summary holds the same block as predict prints for its scenario.
  const auto summary = run_text("predicted", "[container]\nside = 0.06\nheight = 0.2\n[particles]\ndiameter = 0.01\n"
                                             "count = 300\n[deposition]\n[analysis]\nbox_sides = [0.03]\n");
  EXPECT_NEAR(summary.at("predictions").at("simulated").at("cpm").at("density").get<double>(), 0.72 / (1.0 + 1.0 / 4.1),
              1e-12);
}

// aggpack calibrate: K and beta from a monosized bed and the mix of the same protocol; the
// calibrated model then gives back both simulated densities, by construction.
TEST_F(Cli, CalibrateFitsTheModelToTheProtocolsOwnBeds) {
  const fs::path scenario = dir_ / "binary.toml";
  std::ofstream(scenario) << "seed = 1\n[container]\nside = 0.1\nheight = 0.3\n[particles]\norder = \"shuffled\"\n"
                             "classes = [{ diameter = 0.01, count = 600 }, { diameter = 0.005, count = 1200 }]\n"
                             "[deposition]\n[analysis]\nbox_sides = [0.05]\n";
  const fs::path file = dir_ / "calibration.json";
  Result r = run("calibrate " + scenario.string() + " --seeds 2 --out " + file.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("calibrated CPM from"), std::string::npos) << r.output;
  const auto c = nlohmann::json::parse(std::ifstream(file));
  EXPECT_EQ(c.at("kind"), "aggpack CPM calibration");
  EXPECT_EQ(c.at("monosized").at("density_per_seed").size(), 2u);
  const double mono = c.at("monosized").at("mean").get<double>(), mix = c.at("mix").at("mean").get<double>();
  EXPECT_GT(mix, mono);  // two sizes pack denser than one
  const double k = c.at("cpm").at("compaction_index").get<double>(), beta = c.at("cpm").at("residual_packing_density").get<double>();
  EXPECT_NEAR(beta / (1.0 + 1.0 / k), mono, 1e-9);
  r = run("predict " + scenario.string() + " --calibration " + file.string() + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto p = nlohmann::json::parse(r.output.substr(r.output.find('{')));
  EXPECT_NEAR(p.at("simulated").at("cpm").at("density").get<double>(), mix, 1e-9);
  EXPECT_NE(p.at("parameters").at("cpm_compaction_index_source").get<std::string>().find("calibrated by aggpack calibrate"),
            std::string::npos);
  // A scenario can name the file ([models] calibration): its runs' predictions use it.
  std::ofstream(dir_ / "uses.toml") << "seed = 1\n[container]\nside = 0.1\nheight = 0.3\n[particles]\n"
                                       "order = \"shuffled\"\nclasses = [{ diameter = 0.01, count = 600 }, "
                                       "{ diameter = 0.005, count = 1200 }]\n[deposition]\n[analysis]\n"
                                       "box_sides = [0.05]\n[models]\ncalibration = \"calibration.json\"\n";
  r = run("run " + (dir_ / "uses.toml").string() + " --quiet --out " + (dir_ / "uses").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto summary = nlohmann::json::parse(std::ifstream(dir_ / "uses" / "summary.json"));
  EXPECT_NEAR(summary.at("predictions").at("parameters").at("cpm_compaction_index").get<double>(), k, 1e-12);
  // Refused before any simulation, exit 2.
  std::ofstream(dir_ / "mono.toml") << "[container]\nside = 0.1\nheight = 0.3\n[particles]\ndiameter = 0.01\n"
                                       "count = 600\n[deposition]\n[analysis]\nbox_sides = [0.05]\n";
  for (const auto& [args, words] : std::vector<std::pair<std::string, std::string>>{
           {"calibrate " + (dir_ / "mono.toml").string() + " --out " + (dir_ / "x.json").string(), "one size class"},
           {"calibrate " + scenario.string() + " --out " + dir_.string(), "a folder; expected the calibration file"},
           {"predict " + scenario.string() + " --calibration " + scenario.string(), "not JSON"},
           {"predict " + scenario.string() + " --calibration " + file.string() + " --k 4", "give it alone"}}) {
    const Result bad = run(args);
    EXPECT_EQ(bad.exit_code, 2) << args << "\n" << bad.output;
    EXPECT_NE(bad.output.find(words), std::string::npos) << args << "\n" << bad.output;
  }
  EXPECT_FALSE(fs::exists(dir_ / "x.json"));
}

// aggpack whole-grading: a series of cut-offs simulated, CPM carrying the residual below them.
TEST_F(Cli, WholeGradingCarriesACutOffSeriesToTheWholeGrading) {
  const fs::path scenario = dir_ / "blend.toml";
  std::ofstream(scenario) << "seed = 1\n[container]\nside = \"2 in\"\nheight = \"4 in\"\n[particles]\nca_fa = 1.5\n"
                             "fill_height = \"2.5 in\"\n[particles.coarse]\nname = \"fu2003_table1_coarse\"\n"
                             "d_min = \"0.25 in\"\nd_max = \"0.5 in\"\n[particles.fine]\nname = \"astm_c33_fine_mid\"\n"
                             "d_min = \"0.12 in\"\n[deposition]\n[analysis]\nbox_sides = [\"0.8 in\"]\n";
  const fs::path file = dir_ / "estimate.json";
  Result r = run("whole-grading " + scenario.string() + " --cut-offs 0.12in,0.2in,0.16in --seeds 2 --out " +
                 file.string() + " --plot " + (dir_ / "plots" / "cut_offs.svg").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string plot = slurp(dir_ / "plots" / "cut_offs.svg");
  EXPECT_EQ(plot.rfind("<svg", 0), 0u);
  EXPECT_NE(plot.find("whole grading: "), std::string::npos);
  const auto e = nlohmann::json::parse(std::ifstream(file));
  ASSERT_EQ(e.at("cut_offs").size(), 3u);
  EXPECT_EQ(e.at("cut_off_key"), "particles.fine.d_min");
  // Coarsest first; a finer cut leaves less out and places more spheres.
  for (std::size_t k = 1; k < 3; ++k) {
    EXPECT_LT(e.at("cut_offs")[k].at("cut_off_m").get<double>(), e.at("cut_offs")[k - 1].at("cut_off_m").get<double>());
    EXPECT_LT(e.at("cut_offs")[k].at("left_out_volume_fraction").get<double>(),
              e.at("cut_offs")[k - 1].at("left_out_volume_fraction").get<double>());
    EXPECT_GT(e.at("cut_offs")[k].at("spheres").get<int>(), e.at("cut_offs")[k - 1].at("spheres").get<int>());
  }
  const auto& w = e.at("whole_grading");
  EXPECT_DOUBLE_EQ(w.at("density").get<double>(),
                   w.at("cpm").get<double>() + e.at("residual_fit").at("at_nothing_left_out").get<double>());
  // The figure's data beside it (issue 34, item 15): one row a plotted point, the simulated
  // points at 100 x the volume fraction left out, with their means and standard errors.
  const fs::path data = dir_ / "plots" / "cut_offs.csv";
  const Result read = aggpack::testing::check_outputs("csv " + data.string());
  EXPECT_EQ(read.exit_code, 0) << read.output;
  const std::string csv = slurp(data);
  EXPECT_EQ(csv.rfind("series,left_out_volume_percent,packing_density,packing_density_error\n", 0), 0u) << csv;
  for (const auto& c : e.at("cut_offs"))
    EXPECT_NE(csv.find(fmt::format("simulated (mean ± se over seeds),{},{},{}\n",
                                   100.0 * c.at("left_out_volume_fraction").get<double>(), c.at("mean").get<double>(),
                                   c.at("standard_error").get<double>())),
              std::string::npos)
        << csv;
  // This toy blend leaves four fifths of its grading out: the band says the estimate is none.
  EXPECT_FALSE(w.at("trustworthy").get<bool>());
  EXPECT_NE(r.output.find("warning: the band is"), std::string::npos) << r.output;
  // Refused before any simulation, exit 2.
  for (const auto& [args, words] : std::vector<std::pair<std::string, std::string>>{
           {"whole-grading " + scenario.string() + " --cut-offs 0.2in,0.16in", "expected three or more"},
           {"whole-grading " + scenario.string() + " --cut-offs 0.2in,0.2in,0.16in", "given twice"},
           {"whole-grading " + scenario.string() + " --cut-offs 0.2in,x,0.16in", "--cut-offs"},
           {"whole-grading " + example("example2.toml") + " --cut-offs 0.2in,0.16in,0.1in", "not sampled from a grading"},
           {"whole-grading " + scenario.string() + " --cut-offs 0.2in,0.16in,0.1in --plot " + dir_.string(),
            "a folder; expected a file's name"}}) {
    const Result bad = run(args);
    EXPECT_EQ(bad.exit_code, 2) << args << "\n" << bad.output;
    EXPECT_NE(bad.output.find(words), std::string::npos) << args << "\n" << bad.output;
  }
}

TEST_F(Cli, ASnapshotStepWritesTheBedAtItsPoint) {
  std::ofstream(dir_ / "snap.toml")
      << "[container]\nside = 0.06\nheight = 0.5\n[particles]\ndiameter = 0.01\ncount = 200\n"
         "[material]\nyoungs_modulus = 1e8\nwall_youngs_modulus = 1e8\n[deposition]\n[dynamics]\nmax_time = 0.02\n"
         "[analysis]\nbox_sides = [0.02]\n"
         "[[protocol]]\nstep = \"deposit\"\n[[protocol]]\nstep = \"snapshot\"\nname = \"loose\"\n"
         "[[protocol]]\nstep = \"settle\"\n";
  ASSERT_EQ(run("run " + (dir_ / "snap.toml").string() + " --quiet --out " + (dir_ / "snap").string()).exit_code, 0);
  ASSERT_EQ(run("run " + (dir_ / "snap.toml").string() + " --quiet --stop-after deposition --out " +
                (dir_ / "loose").string())
                .exit_code,
            0);
  // The snapshot is the deposited bed (the run stopped after deposition has it as its final
  // bed) and differs from the settled one.
  EXPECT_EQ(slurp(dir_ / "snap" / "particles_loose.csv"), slurp(dir_ / "loose" / "particles.csv"));
  EXPECT_EQ(slurp(dir_ / "loose" / "particles_loose.csv"), slurp(dir_ / "loose" / "particles.csv"));
  EXPECT_NE(slurp(dir_ / "snap" / "particles_loose.csv"), slurp(dir_ / "snap" / "particles.csv"));
  const Result csv = aggpack::testing::check_outputs("csv " + (dir_ / "snap" / "particles_loose.csv").string());
  EXPECT_EQ(csv.exit_code, 0) << csv.output;
  // And as a VTP beside the CSV, the two listed with their times in particles.pvd for ParaView
  // to animate: the deposited bed at 0 s, the settled one at the end of the DEM.
  const Result vtp = aggpack::testing::check_outputs("vtp " + (dir_ / "snap" / "particles_loose.vtp").string() +
                                                     " 200 " + (dir_ / "snap" / "particles_loose.csv").string());
  EXPECT_EQ(vtp.exit_code, 0) << vtp.output;
  const Result pvd = aggpack::testing::check_outputs("pvd " + (dir_ / "snap" / "particles.pvd").string());
  EXPECT_EQ(pvd.exit_code, 0) << pvd.output;
  const auto summary = nlohmann::json::parse(std::ifstream(dir_ / "snap" / "summary.json"));
  const double end = summary.at("stages").at("dynamics").at("simulated_time_s").get<double>();
  EXPECT_EQ(pvd.output, fmt::format("0 particles_loose.vtp\n{} particles.vtp\nok\n", end));
  // A run stopped after deposition ends with the snapshot's bed: one frame, the snapshot.
  const Result stopped = aggpack::testing::check_outputs("pvd " + (dir_ / "loose" / "particles.pvd").string());
  EXPECT_EQ(stopped.output, "0 particles_loose.vtp\nok\n");
  std::ofstream(dir_ / "bad.toml") << "[container]\nside = 0.06\nheight = 0.5\n[particles]\ndiameter = 0.01\n"
                                      "count = 200\n[deposition]\n[[protocol]]\nstep = \"deposit\"\n"
                                      "[[protocol]]\nstep = \"snapshot\"\nname = \"../x\"\n";
  const Result bad = run("check " + (dir_ / "bad.toml").string());
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.output.find("protocol[1].name: expected letters, digits"), std::string::npos) << bad.output;
}

// output.frame_interval: a pour and two taps write frames/frame_NNNNN.vtp as the DEM goes, at
// the first sample and then at the first sample at or after each multiple of the interval (the
// times of timeseries.csv), each a VTP of the bed then, listed in particles.pvd before the final
// bed; the same bytes for one and two threads; a later run without frames removes them; bad
// values are refused before any work.
// A user's own frames/ beside an --overwrite run is not taken over (listed in the manifest,
// then removed by a failed or a later run): the run is refused, the folder untouched.
TEST_F(Cli, AFramesFolderNoRunWroteIsNotTakenOver) {
  const fs::path out = dir_ / "mine";
  fs::create_directories(out / "frames");
  std::ofstream(out / "frames" / "my_picture.png") << "mine";
  std::ofstream(out / "notes.txt") << "mine";
  const std::string text = "[container]\nside = 0.06\nheight = 0.3\n[particles]\ndiameter = 0.01\ncount = 100\n"
                           "[material]\nyoungs_modulus = 1e8\nwall_youngs_modulus = 1e8\n[dynamics]\nmax_time = 0.2\n"
                           "[analysis]\nbox_sides = [0.005]\n[pour]\n[output]\nframe_interval = 0.05\n";
  std::ofstream(dir_ / "frames_mine.toml") << text;
  const Result r = run("run " + (dir_ / "frames_mine.toml").string() + " --overwrite --out " + out.string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("'frames' is there and no aggpack run wrote it"), std::string::npos) << r.output;
  EXPECT_EQ(slurp(out / "frames" / "my_picture.png"), "mine");
  EXPECT_EQ(slurp(out / "notes.txt"), "mine");
  EXPECT_FALSE(fs::exists(out / "summary.json"));
}

// In a periodic container the DEM lets spheres cross the sides; a frame shows them wrapped
// into the box, as the final bed is (two spheres of this pour were outside it).
TEST_F(Cli, APeriodicBedsFramesHoldEverySphereInsideTheBox) {
  const std::string text = "seed = 3\n[container]\nside = 0.04\nheight = 0.3\nsides = \"periodic\"\n[particles]\n"
                           "diameter = 0.008\ncount = 300\n[material]\nyoungs_modulus = 1e8\nwall_youngs_modulus = 1e8\n"
                           "[dynamics]\nmax_time = 0.4\n[analysis]\nbox_sides = [0.012]\n[pour]\nvelocity = 2\n"
                           "[output]\nframe_interval = 0.05\nvtp_encoding = \"ascii\"\n";
  run_text("periodic_frames", text, " --threads 1");
  std::size_t frames = 0, points = 0;
  for (const auto& entry : fs::directory_iterator(dir_ / "periodic_frames" / "frames")) {
    const std::string vtp = slurp(entry.path());
    const std::size_t at = vtp.find('>', vtp.find("<DataArray", vtp.find("<Points>"))) + 1;
    std::istringstream values(vtp.substr(at, vtp.find("</DataArray>", at) - at));
    for (double x = 0, y = 0, z = 0; values >> x >> y >> z; ++points) {
      EXPECT_GE(x, 0.0) << entry.path();
      EXPECT_LT(x, 0.04) << entry.path();
      EXPECT_GE(y, 0.0) << entry.path();
      EXPECT_LT(y, 0.04) << entry.path();
    }
    ++frames;
  }
  EXPECT_GE(frames, 8u);
  EXPECT_GT(points, 1000u);
  // The last frame, at the DEM's end, is the final bed (both wrapped): particles.pvd keeps its
  // time axis (two entries at one time made it number the frames) and ends at the DEM's end.
  const std::string pvd = slurp(dir_ / "periodic_frames" / "particles.pvd");
  std::vector<double> times;
  for (std::size_t at = pvd.find("timestep=\""); at != std::string::npos; at = pvd.find("timestep=\"", at + 1))
    times.push_back(std::stod(pvd.substr(at + 10)));
  ASSERT_FALSE(times.empty()) << pvd;
  for (std::size_t k = 1; k < times.size(); ++k) EXPECT_LT(times[k - 1], times[k]) << pvd;
  const auto summary = nlohmann::json::parse(std::ifstream(dir_ / "periodic_frames" / "summary.json"));
  EXPECT_NEAR(times.back(), summary["stages"]["dynamics"]["simulated_time_s"].get<double>(), 1e-9) << pvd;
}

TEST_F(Cli, FramesOfAPourAndItsTapsAreWrittenAtTheSamplesForAnAnimation) {
  const std::string base = "seed = 4\n[container]\nside = 0.06\nheight = 0.3\n[particles]\ndiameter = 0.01\n"
                           "count = 200\n[material]\nyoungs_modulus = 1e8\nwall_youngs_modulus = 1e8\n"
                           "[dynamics]\nmax_time = 0.5\n[analysis]\nbox_sides = [0.02]\n[pour]\nbatches = 2\n"
                           "[tapping]\ntaps = 2\nintensity = 3\nrest_time = 0.05\nrest_until_quiet = true\n";
  const double interval = 0.05;
  const std::string text = base + "[output]\nframe_interval = 0.05\n";
  run_text("frames1", text, " --threads 1");
  // The same scenario file (its name is in each VTP's provenance), with two threads.
  ASSERT_EQ(run("run " + (dir_ / "frames1.toml").string() + " --quiet --threads 2 --out " + (dir_ / "frames2").string())
                .exit_code,
            0);
  const fs::path out = dir_ / "frames1";

  // The frames the rule gives over timeseries.csv's sample times (written to 9 digits).
  std::vector<double> expected;
  {
    std::istringstream csv(slurp(out / "timeseries.csv"));
    std::string line;
    std::getline(csv, line);  // the header
    double next = 0.0;        // the multiple of the interval the next frame waits for
    while (std::getline(csv, line)) {
      const double t = std::stod(line.substr(0, line.find(',')));
      if (t < (next - 1e-6) * interval) continue;
      expected.push_back(t);
      next = std::floor(t / interval + 1e-6) + 1.0;
    }
  }
  ASSERT_GE(expected.size(), 10u);  // 0.5 s of pour at most, then two taps of 0.05 s rest at most

  // particles.pvd: the frames in order, then the final bed, at times that increase.
  const std::string pvd = slurp(out / "particles.pvd");
  std::vector<std::pair<double, std::string>> listed;  // timestep, file
  for (std::size_t at = pvd.find("<DataSet "); at != std::string::npos; at = pvd.find("<DataSet ", at + 1)) {
    const auto attribute = [&](const std::string& name) {
      const std::size_t from = pvd.find(name + "=\"", at) + name.size() + 2;
      return pvd.substr(from, pvd.find('"', from) - from);
    };
    listed.emplace_back(std::stod(attribute("timestep")), attribute("file"));
  }
  const auto summary = nlohmann::json::parse(std::ifstream(out / "summary.json"));
  ASSERT_FALSE(listed.empty());
  // The final bed ends the list, unless the last frame was taken at its time (then it is that bed).
  const bool final_listed = listed.back().second == "particles.vtp";
  const std::size_t frames = listed.size() - (final_listed ? 1 : 0);
  ASSERT_EQ(frames, expected.size()) << pvd;
  std::size_t files = 0;
  for (const auto& e : fs::directory_iterator(out / "frames")) files += e.path().extension() == ".vtp" ? 1 : 0;
  EXPECT_EQ(files, frames);
  for (std::size_t f = 0; f < frames; ++f) {
    EXPECT_EQ(listed[f].second, fmt::format("frames/frame_{:05}.vtp", f + 1));
    EXPECT_NEAR(listed[f].first, expected[f], 1e-8 * expected[f] + 1e-12) << f;
    if (f > 0) {
      EXPECT_GT(listed[f].first, listed[f - 1].first);
    }
  }
  if (final_listed) {
    EXPECT_GT(listed.back().first, listed[frames - 1].first);
  }
  // The last time is the end of the DEM (taps.csv's last row).
  const std::string taps = slurp(out / "taps.csv");
  const std::string last_tap = taps.substr(taps.rfind('\n', taps.size() - 2) + 1);
  EXPECT_NEAR(listed.back().first, std::stod(last_tap.substr(last_tap.find(',') + 1)), 1e-8);

  // Each frame decodes (check_outputs reads every file of the pvd) and holds the spheres in the
  // bed then: the first batch's 100 while it falls, then all 200, through the taps.
  const Result checked = aggpack::testing::check_outputs("pvd " + (out / "particles.pvd").string());
  EXPECT_EQ(checked.exit_code, 0) << checked.output;
  std::size_t spheres_before = 0;
  for (std::size_t f = 0; f < frames; ++f) {
    const std::string vtp = slurp(out / listed[f].second);
    const std::size_t at = vtp.find("NumberOfPoints=\"") + 16;
    const std::size_t spheres = std::stoul(vtp.substr(at, vtp.find('"', at) - at));
    EXPECT_TRUE(spheres == 100 || spheres == 200) << f << ": " << spheres;
    EXPECT_GE(spheres, spheres_before) << f;
    spheres_before = spheres;
    for (const char* array : {"Name=\"radius\"", "Name=\"diameter\"", "Name=\"id\"", "Name=\"velocity\""})
      EXPECT_NE(vtp.find(array), std::string::npos) << array;
    EXPECT_NE(vtp.find("compressor=\"vtkZLibDataCompressor\""), std::string::npos);  // binary, as particles.vtp
  }
  EXPECT_EQ(slurp(out / listed.front().second).find("NumberOfPoints=\"200\""), std::string::npos);
  EXPECT_NE(slurp(out / listed[frames - 1].second).find("NumberOfPoints=\"200\""), std::string::npos);

  // The same bytes for two threads.
  EXPECT_TRUE(slurp(out / "particles.pvd") == slurp(dir_ / "frames2" / "particles.pvd"));
  for (std::size_t f = 0; f < frames; ++f)
    EXPECT_TRUE(slurp(out / listed[f].second) == slurp(dir_ / "frames2" / listed[f].second)) << listed[f].second;
  const auto manifest = nlohmann::json::parse(std::ifstream(out / "aggpack-manifest.json"));
  for (std::size_t f = 0; f < frames; ++f)  // each frame by its path (issue 55: a user's file among them is not the run's)
    EXPECT_NE(std::find(manifest["files"].begin(), manifest["files"].end(), listed[f].second), manifest["files"].end())
        << listed[f].second;

  // A later run into the folder without frames removes them.
  std::ofstream(dir_ / "frames1.toml") << base;
  ASSERT_EQ(run("run " + (dir_ / "frames1.toml").string() + " --quiet --out " + out.string()).exit_code, 0);
  EXPECT_FALSE(fs::exists(out / "frames"));
  EXPECT_FALSE(fs::exists(out / "particles.pvd"));

  // Bad values: exit 2, the key named, nothing written.
  std::string long_run = base;  // 20 s of pour at most and two taps: 20 134 frames of 1 ms
  long_run.replace(long_run.find("max_time = 0.5"), 14, "max_time = 20");
  expect_refused({
      {base + "[output]\nframe_interval = 0\n", "output.frame_interval"},
      {base + "[output]\nframe_interval = -0.1\n", "output.frame_interval"},
      {base + "[output]\nframe_interval = \"0.1\"\n", "output.frame_interval"},
      {base + "[output]\nframe_interval = 0.0001\n",
       "output.frame_interval: 0.0001 s is shorter than dynamics.sample_interval"},
      {long_run + "[output]\nframe_interval = 0.001\n", "output.frame_interval: up to 2.013e+04 frames"},
      {base + "[output]\nframe_interval = 0.05\nformats = [\"csv\"]\n", "output.frame_interval: frames are VTP"},
      {"[container]\nside = 0.06\nheight = 0.5\n[particles]\ndiameter = 0.01\ncount = 200\n[deposition]\n"
       "[analysis]\nbox_sides = [0.02]\n[output]\nframe_interval = 0.05\n",
       "output.frame_interval: frames are taken at the DEM's samples"},
  });
}

// Protocol errors name the step and the key, exit 2 and write nothing.
TEST_F(Cli, ProtocolErrorsNameTheStepAndTheKey) {
  const std::string base = "[container]\nside = 0.06\nheight = 0.5\n[particles]\ndiameter = 0.01\ncount = 300\n"
                           "[deposition]\n[analysis]\nbox_sides = [0.02]\n";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {base + "[[protocol]]\nstep = \"pour\"\n", "protocol[0].step"},
      {base + "[[protocol]]\nstep = \"deposit\"\n[[protocol]]\nstep = \"settle\"\n",
       "protocol[1].step: a settle step takes its settings from a [dynamics] table"},
      {base + "[[protocol]]\nstep = \"deposit\"\nlayers = 2\n", "no deposit or pour step places part 1 of 2"},
      {base + "[[protocol]]\nstep = \"deposit\"\n[[protocol]]\nstep = \"deposit\"\n",
       "protocol[1].layer: part 0 of 1 is already deposited by protocol[0]"},
      {base + "[[protocol]]\nstep = \"deposit\"\nlayers = 2\n[[protocol]]\nstep = \"deposit\"\nlayer = 1\n",
       "protocol[1].layers: every deposit and pour step splits the drop sequence alike"},
      {base + "[[protocol]]\nstep = \"deposit\"\n[[protocol]]\nstep = \"analyse\"\n", "protocol[1].name"},
      {base + "[[protocol]]\nstep = \"deposit\"\nlayer = 3\n", "protocol[0].layer"},
      {base + "[[protocol]]\nstep = \"deposit\"\nfrozen = true\n", "protocol[0].frozen"},
      {base + "[dynamics]\nlayers = 2\n[[protocol]]\nstep = \"deposit\"\n", "dynamics.layers: with [[protocol]]"},
      {base + "[[protocol]]\nstep = \"analyse\"\nname = \"x\"\n", "no deposit step places the particles"},
  };
  expect_refused(cases);
}

// A pour inserts the spheres as a random gas above the floor; they fall through the DEM
// until quiet. Every sphere ends inside the container, the count is exact, a pour onto a
// deposited bed works, and the result is the same bytes for one and two threads.
TEST_F(Cli, PoursAGasThatFallsIntoABed) {
  const std::string base = "[container]\nside = 0.06\nheight = 0.3\n[particles]\ndiameter = 0.01\ncount = 300\n"
                           "[material]\nyoungs_modulus = 1e8\nwall_youngs_modulus = 1e8\n[dynamics]\nmax_time = 1.5\n"
                           "[analysis]\nbox_sides = [0.02]\n";
  const auto poured = run_text("poured", base + "[pour]\nbatches = 3\nvelocity = 0.5\n", " --threads 1");
  EXPECT_EQ(poured["particle_count"], 300);
  const auto& pour = poured["stages"]["pour"];
  EXPECT_EQ(pour["particles_poured"], 300);
  EXPECT_EQ(pour["batches"], 3);
  EXPECT_EQ(pour["solid_fraction"], 0.2);
  EXPECT_GT(pour["highest_slab_top_m"].get<double>(), pour["lowest_slab_bottom_m"].get<double>() + 0.05);
  EXPECT_EQ(poured["stages"]["dynamics"]["ended_by"], "quiet");
  EXPECT_EQ(poured["scenario"]["pour"]["batches"], 3);
  bool noted = false;
  for (const auto& note : poured["modelling_notes"]) noted |= note.get<std::string>().rfind("pour: 300 particles", 0) == 0;
  EXPECT_TRUE(noted) << poured["modelling_notes"];
  // A random loose to poured packing of monosized spheres in a narrow box (walls lower it).
  EXPECT_GT(poured["density"]["mean"].get<double>(), 0.50);
  EXPECT_LT(poured["density"]["mean"].get<double>(), 0.66);
  // Every sphere inside the walls and on or above the floor (a Hertz overlap at most).
  std::istringstream rows(slurp(dir_ / "poured" / "particles.csv"));
  std::string line;
  std::getline(rows, line);
  std::size_t count = 0;
  for (; std::getline(rows, line); ++count) {
    double v[4];
    ASSERT_EQ(std::sscanf(line.c_str(), "%*d,%lf,%lf,%lf,%lf", &v[0], &v[1], &v[2], &v[3]), 4) << line;
    const double x = v[0], y = v[1], z = v[2], r = v[3];
    EXPECT_GT(x - r, -5e-5);  // max overlap 2.6e-3 of a diameter: 2.6e-5 m
    EXPECT_LT(x + r, 0.06 + 5e-5);
    EXPECT_GT(y - r, -5e-5);
    EXPECT_LT(y + r, 0.06 + 5e-5);
    EXPECT_GT(z - r, -5e-5);
    EXPECT_LT(z, 0.15);  // fallen: 300 spheres at about 0.6 fill 0.08 m
  }
  EXPECT_EQ(count, 300u);
  EXPECT_TRUE(fs::exists(dir_ / "poured" / "timeseries.csv"));
  run_text("poured_2", base + "[pour]\nbatches = 3\nvelocity = 0.5\n", " --threads 2");
  EXPECT_EQ(slurp(dir_ / "poured" / "particles.csv"), slurp(dir_ / "poured_2" / "particles.csv"));
  EXPECT_EQ(slurp(dir_ / "poured" / "timeseries.csv"), slurp(dir_ / "poured_2" / "timeseries.csv"));
  // Onto a deposited bed: half deposited, half poured on top.
  const auto both = run_text("both", base + "[deposition]\n[pour]\n"
                                            "[[protocol]]\nstep = \"deposit\"\nlayer = 0\nlayers = 2\n"
                                            "[[protocol]]\nstep = \"analyse\"\nname = \"deposition\"\n"
                                            "[[protocol]]\nstep = \"pour\"\nlayer = 1\nlayers = 2\n");
  EXPECT_EQ(both["particle_count"], 300);
  EXPECT_EQ(both["stages"]["deposition"]["particles_placed"], 150);
  EXPECT_EQ(both["stages"]["pour"]["particles_poured"], 150);
  EXPECT_GT(both["stages"]["pour"]["lowest_slab_bottom_m"].get<double>(), 0.03);  // above the deposited half
}

// Poured, then tapped: taps.csv has the density before and after every tap, stages.tapping
// the protocol, and the run is the same bytes for one and two threads (1100 spheres: above the
// size from which the DEM runs its loops on threads).
TEST_F(Cli, TapsAPouredBedAndWritesTheCompactionCurve) {
  const std::string text = "[container]\nside = 0.1\nheight = 0.3\n[particles]\ndiameter = 0.01\ncount = 1100\n"
                           "[material]\nyoungs_modulus = 1e8\nwall_youngs_modulus = 1e8\n[dynamics]\nmax_time = 1.5\n"
                           "[analysis]\nbox_sides = [0.02]\n[pour]\n[tapping]\ntaps = 2\nintensity = 3\n"
                           "rest_time = 0.05\n";
  std::ofstream(dir_ / "tapped.toml") << text;
  for (const char* threads : {"1", "2"}) {
    const Result r = run("run " + (dir_ / "tapped.toml").string() + " --quiet --threads " + threads + " --out " +
                         (dir_ / (std::string("tapped_") + threads)).string());
    ASSERT_EQ(r.exit_code, 0) << r.output;
  }
  const auto summary = nlohmann::json::parse(std::ifstream(dir_ / "tapped_1" / "summary.json"));
  const auto& tapping = summary["stages"]["tapping"];
  EXPECT_EQ(tapping["taps"], 2);
  EXPECT_EQ(tapping["density_after_each_tap"].size(), 2u);
  EXPECT_NEAR(tapping["amplitude_m"].get<double>(), 3 * 9.81 / std::pow(2 * M_PI * 30, 2), 1e-12);
  EXPECT_EQ(tapping["density_before"], summary["stages"]["pour"]["density"]["mean"]);  // the poured bed's analysis
  EXPECT_EQ(tapping["density_after_each_tap"][1], summary["density"]["mean"]);
  EXPECT_EQ(summary["scenario"]["tapping"]["intensity"], 3.0);
  const std::string taps = slurp(dir_ / "tapped_1" / "taps.csv");
  EXPECT_EQ(taps.rfind("tap,time_s,density,translational_energy_per_particle_mgd\n0,", 0), 0u) << taps;
  EXPECT_EQ(std::count(taps.begin(), taps.end(), '\n'), 4);  // header, before, two taps
  const Result csv = aggpack::testing::check_outputs("csv " + (dir_ / "tapped_1" / "taps.csv").string());
  EXPECT_EQ(csv.exit_code, 0) << csv.output;
  EXPECT_EQ(taps, slurp(dir_ / "tapped_2" / "taps.csv"));
  EXPECT_EQ(slurp(dir_ / "tapped_1" / "particles.csv"), slurp(dir_ / "tapped_2" / "particles.csv"));
}

// A bare number is metres; one far beyond any bed or grain was meant in another unit: the
// message names the file, line and key, the reading in metres and the unit to write (it was a
// bed-depth message with no key). With its unit written, a large length is taken.
TEST_F(Cli, ALengthFarTooLargeForItsKeyAsksForItsUnit) {
  const std::string particles = "[particles]\ndiameter = 0.01\ncount = 100\n[deposition]\n";
  std::ofstream(dir_ / "inches.toml") << "[container]\nside = 12\nheight = 0.3\n" << particles;
  const Result r = run("run " + (dir_ / "inches.toml").string() + " --out " + (dir_ / "inches").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find((dir_ / "inches.toml").string() + ":2:8: container.side: 12 is a bare number, read as 12 m, "
                          "more than 2 m: if it is in inches or millimetres, write its unit (\"12 in\", \"12 mm\")"),
            std::string::npos)
      << r.output;
  EXPECT_FALSE(fs::exists(dir_ / "inches"));
  expect_refused({{"[container]\nside = 0.1\nheight = 0.3\n[particles]\ndiameter = 0.5\ncount = 100\n[deposition]\n",
                   "particles.diameter: 0.5 is a bare number, read as 0.5 m, more than 0.2 m"}});
  // Written with its unit, the same length is what was meant: refused later, for what it is.
  std::ofstream(dir_ / "metres.toml") << "[container]\nside = \"12 m\"\nheight = 0.3\n" << particles;
  const Result m = run("check " + (dir_ / "metres.toml").string());
  EXPECT_EQ(m.output.find("bare number"), std::string::npos) << m.output;
}

// The console tells a protocol's steps in the order they ran (it told every tapping before an
// import_lammps that came first), and a pour's fraction as the solid fraction it is.
TEST_F(Cli, TheConsoleTellsTheStepsInTheOrderTheyRan) {
  const std::string base = "[container]\nside = 0.06\nheight = 0.3\n[particles]\ndiameter = 0.01\ncount = 150\n"
                           "[material]\nyoungs_modulus = 1e8\nwall_youngs_modulus = 1e8\n[deposition]\n"
                           "[dynamics]\nmax_time = 0.3\n[analysis]\nbox_sides = [0.02]\n";
  const std::string tap_settings = "[tapping]\ntaps = 1\nintensity = 2\nrest_time = 0.05\n";
  // A bed handed over as LAMMPS data, written by an export step (no LAMMPS run needed).
  std::ofstream(dir_ / "first.toml") << base << "[[protocol]]\nstep = \"deposit\"\n[[protocol]]\nstep = "
                                              "\"export_lammps\"\nname = \"hand_over\"\n[[protocol]]\nstep = \"settle\"\n";
  const Result first = run("run " + (dir_ / "first.toml").string() + " --stop-after deposition --out " +
                           (dir_ / "first").string());
  ASSERT_EQ(first.exit_code, 0) << first.output;
  std::ofstream(dir_ / "second.toml") << base << tap_settings << "[[protocol]]\nstep = \"deposit\"\n[[protocol]]\nstep = "
                                               "\"import_lammps\"\nfile = \"first/lammps/hand_over/bed.data\"\n"
                                               "[[protocol]]\nstep = \"tap\"\n";
  const Result second = run("run " + (dir_ / "second.toml").string() + " --out " + (dir_ / "second").string());
  ASSERT_EQ(second.exit_code, 0) << second.output;
  const auto deposition = second.output.find("  deposition: "), imported = second.output.find("  import_lammps: "),
             tapping = second.output.find("  tapping: ");
  ASSERT_NE(deposition, std::string::npos) << second.output;
  ASSERT_NE(imported, std::string::npos) << second.output;
  ASSERT_NE(tapping, std::string::npos) << second.output;
  EXPECT_LT(deposition, imported) << second.output;
  EXPECT_LT(imported, tapping) << second.output;

  // One numbering across the bridge: the bed taken back from LAMMPS data has LAMMPS's ids.
  const fs::path data = dir_ / "first" / "lammps" / "hand_over" / "bed.data";
  const Result back = run("import-lammps " + data.string() + " --scenario " + (dir_ / "first.toml").string() +
                          " --quiet --out " + (dir_ / "back").string());
  ASSERT_EQ(back.exit_code, 0) << back.output;
  std::map<long, double> data_z;  // Atoms (sphere): id type diameter density x y z
  {
    std::ifstream in(data);
    bool atoms = false;
    for (std::string line; std::getline(in, line);) {
      if (line.rfind("Atoms", 0) == 0) atoms = true;
      else if (atoms && line.rfind("Velocities", 0) == 0) break;
      long id = 0, type = 0;
      double d = 0, rho = 0, x = 0, y = 0, z = 0;
      if (atoms && std::sscanf(line.c_str(), "%ld %ld %lf %lf %lf %lf %lf", &id, &type, &d, &rho, &x, &y, &z) == 7)
        data_z[id] = z;
    }
  }
  ASSERT_EQ(data_z.size(), 150u);
  std::ifstream rows(dir_ / "back" / "particles.csv");
  std::string row;
  std::getline(rows, row);
  std::size_t matched = 0;
  for (; std::getline(rows, row); ++matched) {
    long id = 0;
    double x = 0, y = 0, z = 0;
    ASSERT_EQ(std::sscanf(row.c_str(), "%ld,%lf,%lf,%lf", &id, &x, &y, &z), 4) << row;
    ASSERT_TRUE(data_z.contains(id)) << row;
    EXPECT_EQ(z, data_z[id]) << row;
  }
  EXPECT_EQ(matched, 150u);

  std::string pour_base = base;
  pour_base.replace(pour_base.find("[deposition]\n"), 13, "[pour]\n");
  std::ofstream(dir_ / "poured.toml") << pour_base << tap_settings << "[[protocol]]\nstep = \"pour\"\n[[protocol]]\nstep = \"tap\"\n";
  const Result poured = run("run " + (dir_ / "poured.toml").string() + " --out " + (dir_ / "poured").string());
  ASSERT_EQ(poured.exit_code, 0) << poured.output;
  EXPECT_NE(poured.output.find("  pour: 150 particles inserted as a gas at solid fraction 0.2 in 1 batch"),
            std::string::npos)
      << poured.output;
  EXPECT_LT(poured.output.find("  pour: "), poured.output.find("  tapping: ")) << poured.output;
}

// pour.gap >= 0 (README): with no gap each slab starts at the top of what is already in the
// container (the floor, for the first), its spheres inside it, and the pour runs to rest; a
// negative gap is refused.
TEST_F(Cli, APourMayHaveNoGapAboveTheBed) {
  const std::string base = "[container]\nside = 0.06\nheight = 0.3\n[particles]\ndiameter = 0.01\ncount = 200\n"
                           "[material]\nyoungs_modulus = 1e8\nwall_youngs_modulus = 1e8\n[dynamics]\nmax_time = 1.5\n"
                           "[analysis]\nbox_sides = [0.02]\n";
  const auto poured = run_text("no_gap", base + "[pour]\ngap = 0\nbatches = 2\n", " --threads 1");
  EXPECT_EQ(poured["particle_count"], 200);
  EXPECT_EQ(poured["stages"]["dynamics"]["ended_by"], "quiet");
  EXPECT_EQ(poured["scenario"]["pour"]["gap_m"], 0.0);
  EXPECT_EQ(poured["stages"]["pour"]["gap_m"], 0.0);
  EXPECT_EQ(poured["stages"]["pour"]["lowest_slab_bottom_m"], 0.0);  // the floor: an empty container
  expect_refused({{base + "[pour]\ngap = \"-1 mm\"\n", "pour.gap: expected a number >= 0"}});
}

TEST_F(Cli, PourErrorsNameTheKey) {
  const std::string base = "[container]\nside = 0.06\nheight = 0.3\n[particles]\ndiameter = 0.01\ncount = 300\n"
                           "[analysis]\nbox_sides = [0.02]\n";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {base + "[dynamics]\n[pour]\nsolid_fraction = 0.5\n", "pour.solid_fraction"},
      {base + "[dynamics]\n[pour]\nbatches = 0\n", "pour.batches"},
      {base + "[dynamics]\n[pour]\nvelocity = -1\n", "pour.velocity"},
      {base + "[dynamics]\n[pour]\nspeed = 1\n", "pour.speed"},
      {base + "[pour]\n", "pour: a pour falls through the DEM with the [dynamics] settings"},
      {base + "[dynamics]\n[pour]\n[deposition]\n", "give the order of their steps as [[protocol]]"},
      {base + "[dynamics]\nlayers = 2\n[pour]\n", "dynamics.layers: a pour settles as it goes"},
      {base + "[deposition]\n[[protocol]]\nstep = \"pour\"\n", "protocol[0].step: a pour step inserts"},
      {base + "[dynamics]\n[pour]\n[[protocol]]\nstep = \"settle\"\n", "no pour step places the particles"},
      {base + "[deposition]\n[tapping]\n", "tapping: tapping moves the bed through the DEM"},
      {base + "[deposition]\n[dynamics]\n[tapping]\nintensity = 0\n", "tapping.intensity"},
      {base + "[deposition]\n[dynamics]\n[tapping]\nrest_until_quiet = 1\n", "tapping.rest_until_quiet: expected true or false"},
      {base + "[deposition]\n[dynamics]\n[[protocol]]\nstep = \"deposit\"\n[[protocol]]\nstep = \"tap\"\n",
       "protocol[1].step: a tap step takes its settings from a [tapping] table"},
  };
  expect_refused(cases);
}

TEST_F(Cli, SettlesLayerByLayerWithTheLayersBelowFrozen) {
  const fs::path scenario = dir_ / "layers.toml", out = dir_ / "layers";
  std::ofstream(scenario) << settling_scenario(3);
  const Result r = run("run " + scenario.string() + " --quiet --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto s = nlohmann::json::parse(std::ifstream(out / "summary.json"));
  EXPECT_EQ(s["particle_count"], 400);
  EXPECT_EQ(s["stages"]["deposition"]["layers"], 3);
  EXPECT_EQ(s["stages"]["deposition"]["particles_placed"], 400);
  const auto& runs = s["stages"]["dynamics"]["runs"];
  ASSERT_EQ(runs.size(), 3u);
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_EQ(runs[k]["layer"], k);
    EXPECT_EQ(runs[k]["particles_frozen"].get<std::size_t>() + runs[k]["particles_settled"].get<std::size_t>(),
              400 * (k + 1) / 3);
  }
  EXPECT_EQ(runs[1]["particles_frozen"], 133);
  std::set<std::string> layers_seen;
  for (const auto& row : lines_of(out / "timeseries.csv"))
    if (!row.empty() && std::isdigit(row[0])) layers_seen.insert(row.substr(row.find(',') + 1, 1));
  EXPECT_EQ(layers_seen, (std::set<std::string>{"0", "1", "2"}));
  EXPECT_NE(run("run " + scenario.string() + " --quiet --stop-after deposition --out " + (dir_ / "x").string())
                .output.find("no deposited bed to stop at"),
            std::string::npos);
}

TEST_F(Cli, HelpOnEverySubcommandExitsZero) {
  for (auto sub : {"", "run ", "check ", "analyze "}) {
    const Result r = run(std::string(sub) + "--help");
    EXPECT_EQ(r.exit_code, 0) << sub;
    EXPECT_NE(r.output.find("Usage"), std::string::npos) << r.output;
  }
}

// --threads says its bounds once, as they are: 0 for all cores, or 1 to 256 (the entry said
// "0 (all cores) to 256" and "1 to 256").
TEST_F(Cli, ThreadsHelpStatesItsBoundsOnce) {
  for (auto sub : {"run", "resume", "calibrate", "whole-grading", "reproduce", "sweep"}) {
    const Result r = run(std::string(sub) + " --help");
    EXPECT_EQ(r.exit_code, 0) << sub;
    const auto at = r.output.find("--threads");
    ASSERT_NE(at, std::string::npos) << r.output;
    const std::string entry = r.output.substr(at, r.output.find("\n  -", at + 1) - at);
    EXPECT_NE(entry.find("0 (all cores) or 1 to 256"), std::string::npos) << entry;
    EXPECT_EQ(entry.find("256", entry.find("256") + 1), std::string::npos) << entry;
  }
}

}  // namespace

namespace {
// Issue 34, item 14: a concrete engineer's quantities beside the packing density, ASTM C29's
// voids content and dry bulk density, for a simple cubic lattice (pi / 6 exactly) and for the
// models' predictions, in summary.json and on the console.
TEST(CliEngineersQuantities, VoidsAndBulkDensityStandBesideEveryDensity) {
  aggpack::testing::ScratchDir scratch("aggpack_bulk_");
  const fs::path out = scratch.path() / "lattice";
  const auto r = aggpack::testing::run_cli("run " + std::string(AGGPACK_EXAMPLES) + "/cubic_lattice.toml --out " +
                                           out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto summary = nlohmann::json::parse(std::ifstream(out / "summary.json"));
  const auto& bulk = summary.at("bulk_density");
  const double phi = M_PI / 6.0, rho = summary.at("scenario").at("material").at("density_kg_m3").get<double>();
  EXPECT_NEAR(summary.at("density").at("mean").get<double>(), phi, 1e-9);
  EXPECT_NEAR(bulk.at("voids_content_percent").get<double>(), 100.0 * (1.0 - phi), 1e-7);
  EXPECT_NEAR(bulk.at("kg_m3").get<double>(), phi * rho, 1e-6);
  // 1 lb/ft3 = 0.45359237 kg / 0.3048^3 m3 = 16.018463 kg/m3.
  EXPECT_NEAR(bulk.at("lb_ft3").get<double>(), phi * rho / 16.018463373960138, 1e-6);
  char line[96];
  std::snprintf(line, sizeof line, "voids %.1f %%, dry bulk density %.0f kg/m3", 100.0 * (1.0 - phi), phi * rho);
  EXPECT_NE(r.output.find(line), std::string::npos) << line << " missing in\n" << r.output;
  const auto cpm = summary.at("predictions").at("simulated").at("cpm");
  EXPECT_NEAR(cpm.at("bulk_density_kg_m3").get<double>(), cpm.at("density").get<double>() * rho, 1e-6);
  EXPECT_NEAR(cpm.at("voids_content_percent").get<double>(), 100.0 * (1.0 - cpm.at("density").get<double>()), 1e-9);
}
}  // namespace

// `reproduce --dry-run` (issue 34): the folder it reads and the runs it would make, per case
// and in all, from the plan the campaign runs; nothing written. The quick plan is the 14 runs
// of reproduce_quick.
TEST_F(Cli, ReproduceDryRunListsTheFolderAndTheRunsAndWritesNothing) {
  const Result quick = run("reproduce --quick --dry-run --examples " + std::string(AGGPACK_EXAMPLES) + " --out " +
                           (dir_ / "reproduce").string());
  ASSERT_EQ(quick.exit_code, 0) << quick.output;
  EXPECT_NE(quick.output.find("examples: " + fs::absolute(AGGPACK_EXAMPLES).lexically_normal().string() + "\n"),
            std::string::npos)
      << quick.output;
  EXPECT_NE(quick.output.find("runs: 14 (1 seed per case)"), std::string::npos) << quick.output;
  std::istringstream lines(quick.output);
  std::size_t listed = 0;
  for (std::string line; std::getline(lines, line);)
    if (line.find(" x ") != std::string::npos) listed += std::stoul(line);
  EXPECT_EQ(listed, 14u) << quick.output;
  EXPECT_FALSE(fs::exists(dir_ / "reproduce"));
  // Three seeds by default; the whole-grading series adds three cut-offs for every mix.
  EXPECT_NE(run("reproduce --dry-run").output.find("runs: 60 (3 seeds per case)"), std::string::npos);
  EXPECT_NE(run("reproduce --dry-run --whole-grading").output.find("runs: 126 "), std::string::npos);
  // Table 2's DEM protocol deposits seed 1 of every mix again on its own bed and settles it.
  const Result settled = run("reproduce --dry-run --settle-table2");
  EXPECT_NE(settled.output.find("runs: 68 "), std::string::npos) << settled.output;
  EXPECT_NE(settled.output.find("  1 x Table 2 mix 3 (with DEM)\n"), std::string::npos) << settled.output;
  // A folder without the paper's tables: exit 2 naming the file.
  const Result empty = run("reproduce --dry-run --examples " + dir_.string());
  EXPECT_EQ(empty.exit_code, 2) << empty.output;
  EXPECT_NE(empty.output.find((dir_ / "fu2003_table2.csv").string()), std::string::npos) << empty.output;
}
