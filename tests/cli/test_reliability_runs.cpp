// Runs that go wrong while they run (issue 33): a long tap honours a signal inside it, a bed
// that blows up stops at once with the cause and leaves nothing behind, a DEM cut by max_time
// says its bed is not settled, cut-off series that would repeat one bed are refused, and
// `analyze` refuses a packing whose extent would size its arrays beyond the limits.
#include <gtest/gtest.h>

#include "run_cli.hpp"

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <set>
#include <vector>
#include <string>
#include <thread>

namespace {

namespace fs = std::filesystem;
using aggpack::testing::run_cli;
using aggpack::testing::signal_aggpack_when;
using aggpack::testing::slurp;

class ReliabilityRuns : public ::testing::Test {
 protected:
  aggpack::testing::ScratchDir scratch_{"aggpack_reliability_runs_"};
  const fs::path& dir_ = scratch_.path();

  fs::path write(const std::string& name, const std::string& text) {
    const fs::path path = dir_ / name;
    std::ofstream(path) << text;
    return path;
  }
};

// 500 spheres of 1 cm deposited, barely settled, then one slow tap: 1 Hz, so the tap is half a
// second of simulated time, some 4 x 10^5 steps of the stiff spheres (tens of seconds of wall
// clock). The signal comes while the tap is under way.
TEST_F(ReliabilityRuns, ASignalInsideALongTapStopsTheRunInsideTheTap) {
  const fs::path scenario =
      write("slow_tap.toml",
            "[container]\nside = 0.1\nheight = 0.1\n[particles]\ndiameter = 0.01\ncount = 500\n[deposition]\n"
            "[dynamics]\nmax_time = 0.001\n[tapping]\ntaps = 1\nfrequency = 1\nintensity = 0.1\nrest_time = 0.6\n");
  const fs::path out = dir_ / "out";
  // Inside the tap a safe point comes every quarter second or so; before it had none, and
  // the first checkpoint naming the tap came only once the tap was over.
  const std::optional<int> code = signal_aggpack_when(
      {"run", scenario.string(), "--quiet", "--threads", "1", "--checkpoint-every", "0", "--out", out.string()},
      [&] { return slurp(out / "checkpoint.bin").find("while tap 1 of 1") != std::string::npos; }, SIGTERM,
      std::chrono::seconds(30));
  ASSERT_TRUE(code.has_value()) << "the run ended before its tap was checkpointed";
  ASSERT_EQ(*code, 143);
  const auto summary = nlohmann::json::parse(std::ifstream(out / "summary.json"));
  const std::string stopped = summary.at("interruption").at("stopped").get<std::string>();
  std::smatch at;
  ASSERT_TRUE(std::regex_search(stopped, at, std::regex("while tap 1 of 1 at ([0-9.]+) s simulated"))) << stopped;
  // The tap begins at 0.001 s and lasts 0.5 s: stopped before its end.
  EXPECT_LT(std::stod(at[1].str()), 0.5) << stopped;
}

// A time step a hundred times beyond the contacts' resolution, opted in: the bed blows up in
// its first samples. The run stops then, with exit 2, says it blew up, when, and the likely
// cause, and leaves neither a checkpoint nor the folder it made.
TEST_F(ReliabilityRuns, ABedThatBlowsUpStopsAtOnceNamingTheCauseAndLeavesNothing) {
  const fs::path scenario =
      write("unstable.toml",
            "[container]\nside = 0.1\nheight = 0.1\n[particles]\ndiameter = 0.01\ncount = 500\n[deposition]\n"
            "[dynamics]\ntime_step = 1e-4\nallow_unstable_time_step = true\nmax_time = 1\n");
  const fs::path out = dir_ / "out";
  const auto r = run_cli("run " + scenario.string() + " --threads 1 --checkpoint-every 0 --out " + out.string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  for (const char* word : {"unstable.toml", "blew up", "s simulated", "time step", "Rayleigh",
                           "allow_unstable_time_step"})
    EXPECT_NE(r.output.find(word), std::string::npos) << word << " missing in\n" << r.output;
  EXPECT_EQ(r.output.find("internal error"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(out)) << "a refused run leaves its folder (checkpoint.bin: " << fs::exists(out / "checkpoint.bin")
                                << ")";
  // Into a folder that was there already: the folder stays, with no checkpoint in it.
  fs::create_directories(out);
  EXPECT_EQ(run_cli("run " + scenario.string() + " --quiet --threads 1 --out " + out.string()).exit_code, 2);
  EXPECT_TRUE(fs::exists(out));
  EXPECT_FALSE(fs::exists(out / "checkpoint.bin"));
}

// A pour cut by max_time while its spheres still bounce: the density is reported, marked as
// not settled in summary.json, on the console and in the modelling notes; the same pour given
// the time to come to rest is settled.
TEST_F(ReliabilityRuns, ADemCutWhileTheBedMovesSaysItIsNotSettled) {
  const std::string pour = "[container]\nside = 0.1\nheight = 0.2\n[particles]\ndiameter = 0.01\ncount = 600\n"
                           "[material]\nyoungs_modulus = 1e7\nwall_youngs_modulus = 1e7\n[pour]\n"
                           "[analysis]\nbox_sides = [0.03]\n[dynamics]\n";
  const fs::path cut = dir_ / "cut";
  const auto r = run_cli("run " + write("cut.toml", pour + "max_time = 0.2\n").string() + " --threads 1 --out " +
                         cut.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("NOT SETTLED"), std::string::npos) << r.output;
  const auto summary = nlohmann::json::parse(std::ifstream(cut / "summary.json"));
  EXPECT_FALSE(summary.at("settled").get<bool>());
  EXPECT_GT(summary.at("final_translational_energy_per_particle_mgd").get<double>(),
            summary.at("quiet_translational_energy_per_particle_mgd").get<double>());
  bool noted = false;
  for (const auto& note : summary.at("modelling_notes")) noted |= note.get<std::string>().starts_with("not settled");
  EXPECT_TRUE(noted);

  const fs::path rest = dir_ / "rest";
  ASSERT_EQ(run_cli("run " + write("rest.toml", pour + "max_time = 3\n").string() + " --quiet --threads 1 --out " +
                    rest.string())
                .exit_code,
            0);
  const auto settled = nlohmann::json::parse(std::ifstream(rest / "summary.json"));
  EXPECT_EQ(settled.at("stages").at("dynamics").at("ended_by"), "quiet");
  EXPECT_TRUE(settled.at("settled").get<bool>());
  EXPECT_LE(settled.at("final_translational_energy_per_particle_mgd").get<double>(),
            settled.at("quiet_translational_energy_per_particle_mgd").get<double>());
}

// Cut-offs at or below the sand's smallest sieve were all clamped to it: three runs of one bed.
// Refused before any run, naming the cut-offs and the sieve; a scenario's own d_min there too.
TEST_F(ReliabilityRuns, CutOffsBelowTheSmallestSieveAreRefusedBeforeAnyRun) {
  const std::string mix = std::string(AGGPACK_EXAMPLES) + "/table2_mix3.toml";
  const auto whole = run_cli("whole-grading " + mix + " --cut-offs 0.001in,0.0005in,1e-320m --seeds 1 --out " +
                             (dir_ / "whole").string());
  EXPECT_EQ(whole.exit_code, 2) << whole.output;
  for (const char* word : {"--cut-offs", "smallest sieve", "0.001in (0.0254 mm)", "1e-320m", "astm_c33_fine_mid"})
    EXPECT_NE(whole.output.find(word), std::string::npos) << word << " missing in\n" << whole.output;
  EXPECT_FALSE(fs::exists(dir_ / "whole"));
  const auto sweep = run_cli("sweep " + mix + " --fa 30,40 --cut-offs 0.001in,0.0005in,0.0002in --seeds 1 --out " +
                             (dir_ / "sweep").string());
  EXPECT_EQ(sweep.exit_code, 2) << sweep.output;
  EXPECT_NE(sweep.output.find("smallest sieve"), std::string::npos) << sweep.output;
  const auto check = run_cli("check " + mix + " --set particles.fine.d_min=1e-320");
  EXPECT_EQ(check.exit_code, 2) << check.output;
  for (const char* word : {"d_min", "smallest sieve", "cuts nothing"})
    EXPECT_NE(check.output.find(word), std::string::npos) << word << " missing in\n" << check.output;
}

// A column of spheres with one 6 x 10^7 diameters above the others passes the neighbour
// grid's limit (one column of cells) but sized the bed's slices by its height: 1.4 GB of
// profile before any check, and std::bad_alloc under a memory limit. Refused now, with the
// reason, before any array is made. (The limit is left off under AddressSanitizer, which
// reserves terabytes of address space.)
TEST_F(ReliabilityRuns, AnalyzeRefusesAPackingWhoseProfileWouldNeedTooManySlices) {
  const fs::path csv = write("tall.csv", "x,y,z,r\n0.5,0.5,0.5,0.5\n0.5,0.5,1.5,0.5\n0.5,0.5,2.5,0.5\n0.5,0.5,6e7,0.5\n");
  const std::string limit = std::getenv("ASAN_OPTIONS") ? "" : "ulimit -v 1000000; ";
  const auto r = aggpack::testing::run_command(limit + AGGPACK_EXE + " analyze " + csv.string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  for (const char* word : {"tall.csv", "6e+07 m above the floor", "limits.max_profile_bins"})
    EXPECT_NE(r.output.find(word), std::string::npos) << word << " missing in\n" << r.output;
  EXPECT_EQ(r.output.find("internal error"), std::string::npos) << r.output;
}

}  // namespace

namespace {

std::set<std::string> folder_names(const fs::path& folder) {
  std::set<std::string> names;
  for (const auto& entry : fs::directory_iterator(folder)) names.insert(entry.path().filename().string());
  return names;
}
std::set<std::string> manifest_names(const fs::path& folder) {
  const auto manifest = nlohmann::json::parse(std::ifstream(folder / "aggpack-manifest.json"));
  const auto files = manifest.at("files").get<std::vector<std::string>>();
  return {files.begin(), files.end()};
}

// Issue 34, item 1: the README's Example 1, then the same scenario with --stop-after
// deposition into the same folder, kept the first run's timeseries.csv beside the second's
// summary. The second run now removes the first's files (its manifest lists them) and says so.
// A virtual cube that the preflight lets through (the bed at its loosest would hold it) but
// the poured bed, denser, cannot: the refusal comes after the DEM, and the bed it made is kept
// (listed in the manifest) for `analyze`, not thrown away; a run into the folder again replaces it.
TEST_F(ReliabilityRuns, ACubeThatDoesNotFitThePouredBedKeepsTheBed) {
  const fs::path scenario = write(
      "pour.toml",
      "title = \"pour\"\nseed = 1\n[container]\nside = 0.09\nheight = 0.4\n[particles]\ndiameter = 0.01\n"
      "count = 700\n[material]\nyoungs_modulus = 1e8\nwall_youngs_modulus = 1e8\nfriction_particle = 0.5\n"
      "friction_wall = 0.5\n[pour]\nbatches = 2\n[dynamics]\nmax_time = 1.5\n[analysis]\nbox_sides = [0.069]\n");
  const fs::path out = dir_ / "out";
  const auto r = run_cli("run " + scenario.string() + " --threads 2 --out " + out.string());
  ASSERT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("analysis.box_sides: a virtual cube of side 0.069 m comes closer than d_max"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("s of DEM) is kept in " + (out / "particles_unanalysed.csv").string()), std::string::npos)
      << r.output;
  EXPECT_EQ(folder_names(out), (std::set<std::string>{"aggpack-manifest.json", "particles_unanalysed.csv"}));
  EXPECT_EQ(manifest_names(out), (std::set<std::string>{"particles_unanalysed.csv"}));
  // The kept bed is the whole bed, and `analyze` measures it.
  const auto a = run_cli("analyze " + (out / "particles_unanalysed.csv").string() + " --cube 0.04 --json");
  ASSERT_EQ(a.exit_code, 0) << a.output;
  const auto measured = nlohmann::json::parse(a.output.substr(a.output.find('{')));
  EXPECT_GT(measured["density"]["mean"].get<double>(), 0.5);
  // Run again with a cube that fits: the folder holds that run's outputs only.
  const auto again = run_cli("run " + scenario.string() + " --threads 2 --quiet --out " + out.string() +
                             " --set analysis.box_sides=[0.04]");
  ASSERT_EQ(again.exit_code, 0) << again.output;
  EXPECT_FALSE(fs::exists(out / "particles_unanalysed.csv"));
  EXPECT_TRUE(fs::exists(out / "summary.json"));
}

TEST_F(ReliabilityRuns, AReusedFolderHoldsTheLastRunsOutputsOnly) {
  const fs::path scenario =
      write("settle.toml", "[container]\nside = 0.1\nheight = 0.1\n[particles]\ndiameter = 0.01\ncount = 500\n"
                           "[material]\nyoungs_modulus = 1e7\nwall_youngs_modulus = 1e7\n[deposition]\n"
                           "[dynamics]\nmax_time = 0.02\n");
  const fs::path out = dir_ / "out";
  ASSERT_EQ(run_cli("run " + scenario.string() + " --quiet --out " + out.string()).exit_code, 0);
  ASSERT_TRUE(fs::exists(out / "timeseries.csv"));
  const auto again = run_cli("run " + scenario.string() + " --stop-after deposition --out " + out.string());
  ASSERT_EQ(again.exit_code, 0) << again.output;
  EXPECT_NE(again.output.find("removed the files of the earlier run in " + out.string()), std::string::npos)
      << again.output;
  EXPECT_NE(again.output.find("timeseries.csv"), std::string::npos) << again.output;
  EXPECT_FALSE(fs::exists(out / "timeseries.csv"));
  // Every file in the folder is the last run's, and its manifest lists them.
  std::set<std::string> expected = manifest_names(out);
  expected.insert("aggpack-manifest.json");
  for (const std::string& name : folder_names(out)) EXPECT_TRUE(expected.contains(name)) << name;
  EXPECT_FALSE(nlohmann::json::parse(std::ifstream(out / "summary.json")).at("stages").contains("dynamics"));

  // A folder of an aggpack from before manifests (a summary.json naming its version): its
  // outputs are recognised by name and replaced the same way.
  const fs::path old = dir_ / "old";
  fs::create_directories(old);
  std::ofstream(old / "summary.json") << "{\"aggpack_version\": \"0.0.9\"}\n";
  std::ofstream(old / "timeseries.csv") << "time_s\n0\n";
  ASSERT_EQ(run_cli("run " + scenario.string() + " --quiet --stop-after deposition --out " + old.string()).exit_code,
            0);
  EXPECT_FALSE(fs::exists(old / "timeseries.csv"));
}

// A folder holding files no aggpack run wrote is refused before any work, naming them; with
// --overwrite the run writes beside them and leaves them alone.
TEST_F(ReliabilityRuns, AFolderWithOtherFilesIsRefusedUnlessOverwrite) {
  const fs::path scenario = write("deposit.toml", "[container]\nside = 0.1\nheight = 0.1\n[particles]\n"
                                                  "diameter = 0.01\ncount = 500\n[deposition]\n");
  const fs::path out = dir_ / "mine";
  fs::create_directories(out);
  std::ofstream(out / "notes.txt") << "mine";
  const auto refused = run_cli("run " + scenario.string() + " --out " + out.string());
  EXPECT_EQ(refused.exit_code, 2) << refused.output;
  for (const char* word : {"mine", "notes.txt", "no aggpack run wrote", "--overwrite"})
    EXPECT_NE(refused.output.find(word), std::string::npos) << word << " missing in\n" << refused.output;
  EXPECT_EQ(folder_names(out), std::set<std::string>{"notes.txt"});
  const auto written = run_cli("run " + scenario.string() + " --quiet --overwrite --out " + out.string());
  ASSERT_EQ(written.exit_code, 0) << written.output;
  EXPECT_EQ(slurp(out / "notes.txt"), "mine");
  EXPECT_TRUE(fs::exists(out / "summary.json"));
  EXPECT_FALSE(manifest_names(out).contains("notes.txt"));
}

}  // namespace

namespace {

// Issue 55, item 1: the README's cluster workflow. A run exports its bed and a deck to
// lammps/cluster/, the user runs LAMMPS there (its dump and log), and runs the scenario into
// the folder again: the user's files are named and the folder refused, never deleted; with
// --overwrite the run replaces its own deck and leaves them. A folder that only bears an
// output's name (summary.json/) is the user's too.
TEST_F(ReliabilityRuns, ARunIntoAnEarlierRunsFolderKeepsWhatTheUserPutInsideIt) {
  const fs::path scenario = write(
      "cluster.toml", "[container]\nside = 0.06\nheight = 0.3\n[particles]\ndiameter = 0.01\ncount = 150\n"
                      "[material]\nyoungs_modulus = 1e8\nwall_youngs_modulus = 1e8\n[deposition]\n[dynamics]\n"
                      "max_time = 0.3\n[analysis]\nbox_sides = [0.02]\n[[protocol]]\nstep = \"deposit\"\n"
                      "[[protocol]]\nstep = \"export_lammps\"\nname = \"cluster\"\n[[protocol]]\nstep = \"settle\"\n");
  const fs::path out = dir_ / "first";
  const std::string command = "run " + scenario.string() + " --stop-after deposition --quiet --out " + out.string();
  ASSERT_EQ(run_cli(command).exit_code, 0);
  const fs::path deck = out / "lammps" / "cluster";
  ASSERT_TRUE(fs::exists(deck / "settle.in"));
  EXPECT_TRUE(manifest_names(out).contains("lammps/cluster/settle.in"));
  std::ofstream(deck / "settled.dump") << "LAMMPS's result";
  std::ofstream(deck / "log.lammps") << "LAMMPS's log";

  const auto refused = run_cli(command);
  EXPECT_EQ(refused.exit_code, 2) << refused.output;
  for (const char* word : {"lammps/cluster/log.lammps", "lammps/cluster/settled.dump", "--overwrite"})
    EXPECT_NE(refused.output.find(word), std::string::npos) << word << " missing in\n" << refused.output;
  EXPECT_EQ(slurp(deck / "settled.dump"), "LAMMPS's result");
  EXPECT_TRUE(fs::exists(deck / "settle.in"));

  const auto beside = run_cli(command + " --overwrite");
  ASSERT_EQ(beside.exit_code, 0) << beside.output;
  EXPECT_EQ(slurp(deck / "settled.dump"), "LAMMPS's result");
  EXPECT_EQ(slurp(deck / "log.lammps"), "LAMMPS's log");
  EXPECT_TRUE(fs::exists(deck / "settle.in"));
  EXPECT_FALSE(manifest_names(out).contains("lammps/cluster/settled.dump"));
  EXPECT_TRUE(manifest_names(out).contains("lammps/cluster/settle.in"));

  // A manifest from before per-file listing named the folder whole: only the deck's files are
  // recognised as the run's; LAMMPS's dump beside it is the user's.
  std::ofstream(out / "aggpack-manifest.json")
      << R"({"aggpack_version": "0.1.0", "files": ["checkpoint.bin", "lammps", "summary.json", "particles.csv"]})";
  const auto legacy = run_cli(command);
  EXPECT_EQ(legacy.exit_code, 2) << legacy.output;
  EXPECT_NE(legacy.output.find("lammps/cluster/settled.dump"), std::string::npos) << legacy.output;
  EXPECT_EQ(legacy.output.find("settle.in"), std::string::npos) << legacy.output;

  // A folder bearing an output's name is not an output.
  const fs::path named = dir_ / "named";
  ASSERT_EQ(run_cli("run " + scenario.string() + " --stop-after deposition --quiet --out " + named.string()).exit_code,
            0);
  fs::remove(named / "summary.json");
  fs::create_directories(named / "summary.json");
  std::ofstream(named / "summary.json" / "mine.txt") << "mine";
  const auto folder_named = run_cli("run " + scenario.string() + " --stop-after deposition --out " + named.string());
  EXPECT_EQ(folder_named.exit_code, 2) << folder_named.output;
  EXPECT_NE(folder_named.output.find("summary.json"), std::string::npos) << folder_named.output;
  EXPECT_EQ(slurp(named / "summary.json" / "mine.txt"), "mine");
}

// Issue 55, item 1: a user's picture among an earlier run's frames stays; the frames go.
TEST_F(ReliabilityRuns, AUsersFileAmongTheFramesIsNeverRemoved) {
  const fs::path scenario = write(
      "frames.toml", "[container]\nside = 0.06\nheight = 0.3\n[particles]\ndiameter = 0.01\ncount = 100\n"
                     "[material]\nyoungs_modulus = 1e8\nwall_youngs_modulus = 1e8\n[dynamics]\nmax_time = 0.2\n"
                     "[analysis]\nbox_sides = [0.005]\n[pour]\n[output]\nframe_interval = 0.05\n");
  const fs::path out = dir_ / "frames_run";
  ASSERT_EQ(run_cli("run " + scenario.string() + " --quiet --threads 1 --out " + out.string()).exit_code, 0);
  ASSERT_TRUE(fs::exists(out / "frames" / "frame_00001.vtp"));
  EXPECT_TRUE(manifest_names(out).contains("frames/frame_00001.vtp"));
  std::ofstream(out / "frames" / "my_render.png") << "mine";
  const auto refused = run_cli("run " + scenario.string() + " --quiet --threads 1 --out " + out.string());
  EXPECT_EQ(refused.exit_code, 2) << refused.output;
  EXPECT_NE(refused.output.find("frames/my_render.png"), std::string::npos) << refused.output;
  EXPECT_EQ(slurp(out / "frames" / "my_render.png"), "mine");
  // Without frames this time, --overwrite: the run's frames go, the picture stays.
  const auto again = run_cli("run " + scenario.string() + " --quiet --threads 1 --overwrite --set "
                             "output.frame_interval=1e9 --out " + out.string());
  EXPECT_EQ(again.exit_code, 2) << again.output;  // a frame interval is there: the user's frames are not written among
  EXPECT_TRUE(fs::exists(out / "frames" / "frame_00001.vtp"));  // refused before anything was removed
  fs::path plain = write("plain.toml", slurp(scenario).substr(0, slurp(scenario).find("[output]")));
  ASSERT_EQ(run_cli("run " + plain.string() + " --quiet --threads 1 --overwrite --out " + out.string()).exit_code, 0);
  EXPECT_FALSE(fs::exists(out / "frames" / "frame_00001.vtp"));
  EXPECT_EQ(slurp(out / "frames" / "my_render.png"), "mine");
}

// Issue 55, item 14: a run refused before it began (here: a virtual cube larger than the
// container) leaves the folder of an earlier refused run as it was, manifest and all, so that
// the next run into it is not refused for "a file that no aggpack run wrote".
TEST_F(ReliabilityRuns, ARefusedRunLeavesTheManifestDescribingTheFolder) {
  const fs::path scenario = write(
      "pour.toml",
      "title = \"pour\"\nseed = 1\n[container]\nside = 0.09\nheight = 0.4\n[particles]\ndiameter = 0.01\n"
      "count = 700\n[material]\nyoungs_modulus = 1e8\nwall_youngs_modulus = 1e8\nfriction_particle = 0.5\n"
      "friction_wall = 0.5\n[pour]\nbatches = 2\n[dynamics]\nmax_time = 1.5\n[analysis]\nbox_sides = [0.069]\n");
  const fs::path out = dir_ / "out";
  ASSERT_EQ(run_cli("run " + scenario.string() + " --threads 2 --out " + out.string()).exit_code, 2);
  ASSERT_TRUE(fs::exists(out / "particles_unanalysed.csv"));
  const auto before = run_cli("run " + scenario.string() + " --quiet --set analysis.box_sides=[0.5] --out " +
                              out.string());
  ASSERT_EQ(before.exit_code, 2) << before.output;
  EXPECT_EQ(manifest_names(out), (std::set<std::string>{"particles_unanalysed.csv"}));
  const auto again = run_cli("run " + scenario.string() + " --threads 2 --quiet --set analysis.box_sides=[0.04] "
                             "--out " + out.string());
  ASSERT_EQ(again.exit_code, 0) << again.output;
  EXPECT_FALSE(fs::exists(out / "particles_unanalysed.csv"));
}

// A manifest edited or damaged to name files outside its folder removes none of them: a later
// run into the folder removes only what lies inside it.
TEST_F(ReliabilityRuns, AManifestNeverReachesOutOfItsFolder) {
  const fs::path scenario = write("deposit.toml", "[container]\nside = 0.1\nheight = 0.1\n[particles]\n"
                                                  "diameter = 0.01\ncount = 500\n[deposition]\n");
  const fs::path out = dir_ / "out";
  ASSERT_EQ(run_cli("run " + scenario.string() + " --quiet --out " + out.string()).exit_code, 0);
  std::ofstream(dir_ / "victim.txt") << "mine";
  std::ofstream(out / "aggpack-manifest.json")
      << R"({"files": ["summary.json", "particles.csv", "particles.vtp", "supports.csv", "../victim.txt", )"
      << "\"" << (dir_ / "victim.txt").string() << "\"]}";
  ASSERT_EQ(run_cli("run " + scenario.string() + " --quiet --out " + out.string()).exit_code, 0);
  EXPECT_EQ(slurp(dir_ / "victim.txt"), "mine");
}

}  // namespace
