// Runs the aggpack executable as a user would and checks exit codes and files.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

namespace {

namespace fs = std::filesystem;

struct Result {
  int exit_code;
  std::string output;  // stdout and stderr
};

Result run(const std::string& args) {
  const std::string cmd = std::string(AGGPACK_EXE) + " " + args + " 2>&1";
  FILE* pipe = popen(cmd.c_str(), "r");
  std::string out;
  std::array<char, 4096> buf{};
  while (fgets(buf.data(), buf.size(), pipe)) out += buf.data();
  const int status = pclose(pipe);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

class Cli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("aggpack_cli_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string example(const std::string& name) const { return std::string(AGGPACK_EXAMPLES) + "/" + name; }
  fs::path dir_;
};

TEST_F(Cli, RunWritesTheThreeFilesAndTheSummaryKeys) {
  const fs::path out = dir_ / "run";
  const Result r = run("run " + example("cubic_lattice.toml") + " --quiet --seed 5 --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(r.output.empty()) << r.output;  // --quiet
  for (auto f : {"particles.csv", "particles.vtp", "summary.json"}) EXPECT_TRUE(fs::exists(out / f)) << f;
  for (const auto& e : fs::directory_iterator(out))
    EXPECT_EQ(e.path().string().find(".tmp."), std::string::npos) << "leftover " << e.path();
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
  std::string header;
  std::getline(csv, header);
  EXPECT_EQ(header, "id,x,y,z,r");
}

TEST_F(Cli, BadInputExitsWithTwoAndWritesNothing) {
  const fs::path out = dir_ / "bad";
  const std::vector<std::string> bad_runs = {
      "run " + example("cubic_lattice.toml") + " --set analysis.box_sides='[\"9 in\"]'",  // cube does not fit
      "run " + example("cubic_lattice.toml") + " --set material.density=-1",
      "run " + example("cubic_lattice.toml") + " --set container.side='\"5 in\"'",  // particles outside
      "run " + example("cubic_lattice.toml") + " --stop-after deposition",  // no such stage here
      "run " + example("example1.toml") + " --stop-after dynamics",
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

// The paper's Example 1 end to end: deposition, analysis and every output file.
TEST_F(Cli, RunsExample1ThroughDeposition) {
  const fs::path out = dir_ / "ex1";
  const Result r = run("run " + example("example1.toml") + " --stop-after deposition --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
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
  EXPECT_EQ(header, "id,support_1,support_2,support_3");
  EXPECT_EQ(first, "0,floor,,");
  // Same seed, same bytes; another seed, another packing.
  const fs::path again = dir_ / "ex1b", other = dir_ / "ex1c";
  ASSERT_EQ(run("run " + example("example1.toml") + " --out " + again.string()).exit_code, 0);
  ASSERT_EQ(run("run " + example("example1.toml") + " --seed 2 --out " + other.string()).exit_code, 0);
  const auto slurp = [](const fs::path& f) {
    std::ifstream in(f);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
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
  // The blend at #4 (4.75 mm): (1.52 x 6.8 % + 97.5 %) / 2.52, within the inch/metric opening difference.
  bool found = false;
  for (const auto& s : j["mix"]["sieves"])
    if (s["sieve"] == "#4") {
      found = true;
      EXPECT_NEAR(s["percent_passing"].get<double>(), (1.52 * 6.8 + 97.5) / 2.52, 0.3);
    }
  EXPECT_TRUE(found);
  EXPECT_GT(j["cut"]["cut_below_fraction"].get<double>(), 0.3);
  EXPECT_EQ(run("grading no_such_grading").exit_code, 2);
  EXPECT_EQ(run("grading astm_c33_fine_mid --band astm_c33_99").exit_code, 2);
  EXPECT_EQ(run("grading astm_c33_fine_mid --d-min '20 mm'").exit_code, 2);
  r = run("grading --list");
  EXPECT_NE(r.output.find("band astm_c33_67"), std::string::npos);
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

TEST_F(Cli, HelpOnEverySubcommandExitsZero) {
  for (auto sub : {"", "run ", "check ", "analyze "}) {
    const Result r = run(std::string(sub) + "--help");
    EXPECT_EQ(r.exit_code, 0) << sub;
    EXPECT_NE(r.output.find("Usage"), std::string::npos) << r.output;
  }
}

}  // namespace
