// Checkpoints and resume, as a user meets them: a run killed (SIGKILL) or stopped (SIGINT) at
// several points of its protocol, then `aggpack resume`, ends with every output file the same
// bytes as an uninterrupted run's (with another thread count), and summary.json the same but
// for the machine's figures (wall clock, speed, memory) and the note that it was resumed.
// Resume refuses, with exit code 2 and a message naming the folder, what it cannot continue.
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <map>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "aggpack/run/checkpoint.hpp"
#include "run_cli.hpp"

namespace {

namespace fs = std::filesystem;
using aggpack::testing::run_cli;
using aggpack::testing::signal_aggpack_when;
using aggpack::testing::slurp;

// Poured in two batches, settled, then tapped twice: every resumable loop (a batch falling,
// the bed settling, a tap's rest), 1100 spheres (the DEM's threaded loops), ~2 s.
constexpr const char* kPourAndTap =
    "seed = 4\n[container]\nside = 0.1\nheight = 0.3\n[particles]\ndiameter = 0.01\ncount = 1100\n"
    "[material]\nyoungs_modulus = 1e8\nwall_youngs_modulus = 1e8\n[dynamics]\nmax_time = 0.5\n"
    "[analysis]\nbox_sides = [0.02]\n[pour]\nbatches = 2\n"
    "[tapping]\ntaps = 2\nintensity = 3\nrest_time = 0.05\nrest_until_quiet = true\n";
// Deposited and settled in three layers, the lower ones frozen, ~1.5 s.
constexpr const char* kLayered =
    "seed = 3\n[container]\nside = 0.08\nheight = 0.5\n[particles]\ndiameter = 0.01\ncount = 1500\n"
    "[material]\nyoungs_modulus = 1e8\nwall_youngs_modulus = 1e8\n[deposition]\n[dynamics]\nmax_time = 0.1\n"
    "layers = 3\n[analysis]\nbox_sides = [0.04]\n";

// summary.json's values by key path, without what measures the machine or the run's history.
void flatten(const nlohmann::json& v, const std::string& path, std::map<std::string, nlohmann::json>& out) {
  for (const char* machine : {"wall_clock_s", "particle_steps_per_second", "particles_per_second", "threads",
                              "memory_bytes_per_particle", "resumed_from_checkpoint", "scenario.output."})
    if (path.find(machine) != std::string::npos) return;
  if (v.is_object()) {
    for (const auto& [k, x] : v.items()) flatten(x, path.empty() ? k : path + "." + k, out);
  } else if (v.is_array()) {
    for (std::size_t i = 0; i < v.size(); ++i) flatten(v[i], path + "[" + std::to_string(i) + "]", out);
  } else {
    out[path] = v;
  }
}
std::map<std::string, nlohmann::json> summary_values(const fs::path& dir) {
  std::map<std::string, nlohmann::json> values;
  flatten(nlohmann::json::parse(std::ifstream(dir / "summary.json")), "", values);
  return values;
}

// Where the values of a table of `count` 4-byte values start in `bytes`: the first place
// where `count` (8 bytes) is followed by such values, as `fits` would have them; npos if none.
std::size_t find_table(const std::string& bytes, std::uint64_t count,
                       const std::function<bool(const std::vector<std::uint32_t>&, std::size_t end)>& fits) {
  for (std::size_t at = 0; at + 8 + 4 * count <= bytes.size(); ++at) {
    std::uint64_t n = 0;
    std::memcpy(&n, bytes.data() + at, 8);
    if (n != count) continue;
    std::vector<std::uint32_t> values(count);
    std::memcpy(values.data(), bytes.data() + at + 8, 4 * count);
    if (fits(values, at + 8 + 4 * count)) return at + 8;
  }
  return std::string::npos;
}

class Resume : public ::testing::Test {
 protected:
  aggpack::testing::ScratchDir scratch_{"aggpack_resume_test_"};
  const fs::path& dir_ = scratch_.path();

  fs::path write_scenario(const std::string& name, const std::string& text) {
    const fs::path path = dir_ / (name + ".toml");
    std::ofstream(path) << text;
    return path;
  }

  // Starts `aggpack run`, checkpointing at every safe point, and sends `signal_number` once
  // the checkpoint in `out` was taken at the safe point `when` names (taken_at).
  // Returns the exit code (or minus the signal), or nullopt when the run ended first.
  static std::optional<int> run_and_signal_when(const fs::path& scenario, const fs::path& out, const std::string& when,
                                                int signal_number) {
    return signal_when({"run", scenario.string(), "--quiet", "--threads", "1", "--checkpoint-every", "0", "--out",
                        out.string()},
                       out, when, signal_number);
  }

  // The same for `aggpack resume out` on `threads` threads: a resumed run killed in its turn.
  static std::optional<int> resume_and_signal_when(const fs::path& out, const std::string& when, int signal_number,
                                                   const std::string& threads) {
    return signal_when({"resume", out.string(), "--quiet", "--threads", threads, "--checkpoint-every", "0"}, out,
                       when, signal_number);
  }

  // Whether the checkpoint in `out` was taken at `when`: "before step K of N" is any safe
  // point of step K (K - 1 steps completed; its first safe point alone lasts until the step's
  // next one, a few milliseconds, and a poll could miss it); anything else, a safe point whose
  // description contains `when`. A resumed run's checkpoint holds the one it started from
  // until it writes its own.
  static bool taken_at(const fs::path& out, const std::string& when) {
    aggpack::Checkpoint checkpoint;
    try {
      checkpoint = aggpack::read_checkpoint(out);  // written atomically: whole, when there
    } catch (const aggpack::InputError&) {
      return false;  // none yet, or the finished run has removed it
    }
    unsigned step = 0;
    if (std::sscanf(when.c_str(), "before step %u of", &step) == 1) return checkpoint.steps_completed + 1 >= step;
    return checkpoint.where.find(when) != std::string::npos;
  }

  static std::optional<int> signal_when(const std::vector<std::string>& arguments, const fs::path& out,
                                        const std::string& when, int signal_number) {
    return signal_aggpack_when(
        arguments, [&] { return taken_at(out, when); }, signal_number);
  }

  // Every file of `reference` is in `resumed` with the same bytes (summary.json: the same
  // values but for the machine's), and the finished run left no checkpoint behind.
  static void expect_same_run(const fs::path& reference, const fs::path& resumed) {
    std::size_t files = 0;
    for (const auto& entry : fs::directory_iterator(reference)) {
      const std::string name = entry.path().filename().string();
      ++files;
      if (name == "summary.json") continue;
      EXPECT_TRUE(slurp(entry.path()) == slurp(resumed / name)) << name << " differs";
    }
    EXPECT_GE(files, 4u);
    const auto expected = summary_values(reference), got = summary_values(resumed);
    for (const auto& [key, value] : expected) EXPECT_EQ(got.count(key) ? got.at(key) : nullptr, value) << key;
    EXPECT_EQ(got.size(), expected.size());
    EXPECT_FALSE(fs::exists(resumed / "checkpoint.bin"));
    for (const auto& entry : fs::directory_iterator(resumed))
      EXPECT_EQ(entry.path().filename().string().find(".aggpack-incomplete."), std::string::npos) << entry.path();
  }
};

TEST_F(Resume, ARunKilledInAnyLoopOfItsProtocolResumesToTheSameBytes) {
  const fs::path scenario = write_scenario("pour_tap", kPourAndTap);
  const fs::path reference = dir_ / "reference";
  const auto r = run_cli("run " + scenario.string() + " --quiet --threads 1 --no-checkpoint --out " + reference.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  ASSERT_FALSE(fs::exists(reference / "checkpoint.bin"));
  // One run killed in each loop in turn, each time resumed (on one thread or two) from the
  // checkpoint the killed run (or resumed run) left. "before step 3": between the pour (and its
  // analysis) and the taps, where the checkpoint's run state holds the DEM system the taps
  // continue, contact history and all.
  const fs::path out = dir_ / "killed";
  ASSERT_EQ(run_and_signal_when(scenario, out, "while pouring, 550 of 1100", SIGKILL), -SIGKILL)
      << "the run ended while pouring";
  EXPECT_FALSE(fs::exists(out / "summary.json"));
  const std::string threads[] = {"2", "1", "2"};
  const std::string kill_points[] = {"while settling", "before step 3 of 3", "while tap 2 of 2"};
  for (std::size_t k = 0; k < 3; ++k) {
    SCOPED_TRACE("resumed and killed " + kill_points[k]);
    ASSERT_EQ(resume_and_signal_when(out, kill_points[k], SIGKILL, threads[k]), -SIGKILL)
        << "the resumed run ended before " << kill_points[k];
    EXPECT_FALSE(fs::exists(out / "summary.json"));
  }
  const auto resumed = run_cli("resume " + out.string() + " --threads 1");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_NE(resumed.output.find("resuming " + out.string() + " from its checkpoint, taken while tap 2 of 2"),
            std::string::npos)
      << resumed.output;
  expect_same_run(reference, out);
  const auto summary = nlohmann::json::parse(std::ifstream(out / "summary.json"));
  EXPECT_NE(summary.at("resumed_from_checkpoint").get<std::string>().find("while tap 2 of 2"), std::string::npos);
}

// A run with grains (rigid bodies of 2 spheres beside spheres of their own) killed while
// pouring, between the pour and the taps, and while tapping, each time resumed (on one thread
// or two), ends with the bytes of the run never stopped: the bodies' poses, motions and
// contacts are in the checkpoint. A body changed in a resealed checkpoint is refused.
TEST_F(Resume, ARunWithGrainsKilledInEachLoopResumesToTheSameBytes) {
  const fs::path scenario = write_scenario(
      "grains",
      "seed = 6\n[container]\nside = 0.036\nheight = 0.3\n[particles]\nclasses = [{ diameter = 0.008, count = 100, "
      "shape = { family = \"rounded\", spheres = 2, templates = 3 } }, { diameter = 0.005, count = 20 }]\n"
      "[material]\nyoungs_modulus = 1e7\nwall_youngs_modulus = 1e7\nfriction_particle = 0.5\n[dynamics]\n"
      "max_time = 0.6\n[analysis]\nbox_sides = [0.005]\n[pour]\nbatches = 2\nsolid_fraction = 0.15\n"
      "[tapping]\ntaps = 1\nintensity = 3\nrest_time = 0.05\nrest_until_quiet = true\n");
  const fs::path reference = dir_ / "reference";
  const auto r = run_cli("run " + scenario.string() + " --quiet --threads 1 --no-checkpoint --out " + reference.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const fs::path out = dir_ / "killed";
  ASSERT_EQ(run_and_signal_when(scenario, out, "while pouring", SIGKILL), -SIGKILL) << "the run ended while pouring";
  const std::string threads[] = {"2", "1"};
  const std::string kill_points[] = {"before step 3 of 3", "while tap 1 of 1"};
  for (std::size_t k = 0; k < 2; ++k) {
    SCOPED_TRACE("resumed and killed " + kill_points[k]);
    ASSERT_EQ(resume_and_signal_when(out, kill_points[k], SIGKILL, threads[k]), -SIGKILL)
        << "the resumed run ended before " << kill_points[k];
  }
  // The bodies' templates in the run state's bed: 100 ids of the 3 templates (not the members'
  // counts, all 2). One changed to another template, resealed: refused.
  const std::string intact = slurp(out / "checkpoint.bin");
  const std::size_t shapes = find_table(intact, 100, [](const std::vector<std::uint32_t>& v, std::size_t) {
    return std::all_of(v.begin(), v.end(), [](std::uint32_t id) { return id < 3; }) &&
           std::any_of(v.begin(), v.end(), [&](std::uint32_t id) { return id != v.front(); });
  });
  ASSERT_NE(shapes, std::string::npos);
  std::string damaged = intact;
  damaged[shapes + 4 * 7] = static_cast<char>((damaged[shapes + 4 * 7] + 1) % 3);
  std::ofstream(out / "checkpoint.bin", std::ios::binary | std::ios::trunc) << aggpack::resealed_checkpoint(damaged);
  const auto refused = run_cli("resume " + out.string() + " --quiet --threads 1");
  EXPECT_EQ(refused.exit_code, 2) << refused.output;
  EXPECT_NE(refused.output.find("(a grain) is not one of the run's"), std::string::npos) << refused.output;
  std::ofstream(out / "checkpoint.bin", std::ios::binary | std::ios::trunc) << intact;
  const auto resumed = run_cli("resume " + out.string() + " --threads 1");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  expect_same_run(reference, out);
}

// With frames (output.frame_interval), a run killed while pouring or in a tap's rest and
// resumed (with another thread count) writes the same frames, the same bytes, and the same
// particles.pvd as the uninterrupted run: the frames before its checkpoint are kept, the later
// ones written again.
TEST_F(Resume, ARunWithFramesKilledAndResumedWritesTheSameFrames) {
  // kPourAndTap's protocol with 300 spheres, for speed.
  const fs::path scenario = write_scenario(
      "frames",
      "seed = 4\n[container]\nside = 0.06\nheight = 0.3\n[particles]\ndiameter = 0.01\ncount = 300\n"
      "[material]\nyoungs_modulus = 1e8\nwall_youngs_modulus = 1e8\n[dynamics]\nmax_time = 0.5\n"
      "[analysis]\nbox_sides = [0.02]\n[pour]\nbatches = 2\n"
      "[tapping]\ntaps = 2\nintensity = 3\nrest_time = 0.05\nrest_until_quiet = true\n"
      "[output]\nframe_interval = 0.04\n");
  const fs::path reference = dir_ / "reference";
  const auto r = run_cli("run " + scenario.string() + " --quiet --threads 1 --no-checkpoint --out " + reference.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::vector<std::string> frames;
  for (const auto& e : fs::directory_iterator(reference / "frames")) frames.push_back(e.path().filename().string());
  ASSERT_GE(frames.size(), 5u);
  for (const std::string when : {"while pouring, 150 of 300", "while tap 2 of 2"}) {
    SCOPED_TRACE("killed " + when);
    const fs::path out = dir_ / ("killed_" + std::to_string(when.size()));
    ASSERT_EQ(run_and_signal_when(scenario, out, when, SIGKILL), -SIGKILL) << "the run ended before " << when;
    if (when.starts_with("while tap")) {  // the frames of the pour were written before it was killed
      EXPECT_TRUE(fs::exists(out / "frames" / "frame_00001.vtp"));
    }
    const auto resumed = run_cli("resume " + out.string() + " --threads 2");
    ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
    expect_same_run(reference, out);
    std::size_t written = 0;
    for (const auto& e : fs::directory_iterator(out / "frames")) written += e.is_regular_file() ? 1 : 0;
    EXPECT_EQ(written, frames.size());
    for (const std::string& frame : frames)
      EXPECT_TRUE(slurp(reference / "frames" / frame) == slurp(out / "frames" / frame)) << frame << " differs";
    EXPECT_TRUE(slurp(reference / "particles.pvd") == slurp(out / "particles.pvd"));
  }
}

// With periodic sides, killed between a settling and the taps that continue its DEM system:
// the checkpoint's carried system has its spheres where the DEM has them, the bed wrapped into
// the box; resumed, it continues to the same bytes.
TEST_F(Resume, APeriodicRunKilledBetweenTwoDemStepsResumesToTheSameBytes) {
  const fs::path scenario = write_scenario(
      "periodic",
      "seed = 8\n[container]\nside = 0.05\nheight = 0.2\nsides = \"periodic\"\n[particles]\ndiameter = 0.01\n"
      "count = 300\n[material]\nyoungs_modulus = 1e8\nwall_youngs_modulus = 1e8\n[deposition]\n"
      "[dynamics]\nmax_time = 0.1\n[tapping]\ntaps = 1\nintensity = 3\nrest_time = 0.03\n"
      "[analysis]\nbox_sides = [0.02]\n[[protocol]]\nstep = \"deposit\"\n[[protocol]]\nstep = \"settle\"\n"
      "[[protocol]]\nstep = \"tap\"\n");
  const fs::path reference = dir_ / "reference";
  const auto r = run_cli("run " + scenario.string() + " --quiet --threads 1 --no-checkpoint --out " + reference.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto summary = nlohmann::json::parse(std::ifstream(reference / "summary.json"));
  EXPECT_TRUE(summary.at("stages").at("tapping").value("continues_dem_system", false));
  const fs::path out = dir_ / "killed";
  ASSERT_EQ(run_and_signal_when(scenario, out, "before step 3 of 3", SIGKILL), -SIGKILL);
  const auto resumed = run_cli("resume " + out.string() + " --threads 2");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  expect_same_run(reference, out);
}

// A cylindrical measure (its shape and rim in the checkpoint's container), poured, settled and
// tapped, killed in the tap and resumed: the same bytes, the measure's content the same.
TEST_F(Resume, ACylinderRunKilledInItsTapResumesToTheSameBytes) {
  const fs::path scenario = write_scenario(
      "cylinder",
      "seed = 6\n[container]\nshape = \"cylinder\"\ndiameter = 0.06\nheight = 0.2\nrim = 0.025\n"
      "[particles]\ndiameter = 0.006\ncount = 400\n[material]\nyoungs_modulus = 1e8\nwall_youngs_modulus = 1e8\n"
      "[pour]\n[dynamics]\nmax_time = 0.3\n[tapping]\ntaps = 2\nintensity = 3\nrest_time = 0.03\n"
      "[analysis]\nbox_sides = [0.012]\n[[protocol]]\nstep = \"pour\"\n[[protocol]]\nstep = \"settle\"\n"
      "[[protocol]]\nstep = \"tap\"\n");
  const fs::path reference = dir_ / "reference";
  const auto r = run_cli("run " + scenario.string() + " --quiet --threads 1 --no-checkpoint --out " + reference.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(nlohmann::json::parse(std::ifstream(reference / "summary.json")).contains("measure"));
  const fs::path out = dir_ / "killed";
  ASSERT_EQ(run_and_signal_when(scenario, out, "before step 3 of 3", SIGKILL), -SIGKILL);
  const auto resumed = run_cli("resume " + out.string() + " --threads 2");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  expect_same_run(reference, out);
}

// Killed in a later layer (the layers below frozen), resumed, killed again, resumed again.
TEST_F(Resume, ALayeredRunKilledTwiceResumesToTheSameBytes) {
  const fs::path scenario = write_scenario("layered", kLayered);
  const fs::path reference = dir_ / "reference";
  ASSERT_EQ(run_cli("run " + scenario.string() + " --quiet --threads 2 --no-checkpoint --out " + reference.string())
                .exit_code,
            0);
  const fs::path out = dir_ / "killed";
  ASSERT_EQ(run_and_signal_when(scenario, out, "before step 4 of 6", SIGKILL), -SIGKILL);
  // The resumed run is killed in its turn, in the last layer's settling.
  ASSERT_EQ(resume_and_signal_when(out, "before step 6 of 6", SIGKILL, "1"), -SIGKILL)
      << "the resumed run ended before it was killed";
  const auto resumed = run_cli("resume " + out.string() + " --quiet --threads 1");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  expect_same_run(reference, out);
}

// SIGINT: the run writes a checkpoint at the safe point where it stops, says so in the
// interrupted summary and on the terminal, and resumes from there.
TEST_F(Resume, SigintWritesACheckpointThatTheSummaryNamesAndResumeContinues) {
  const fs::path scenario = write_scenario("layered", kLayered);
  const fs::path reference = dir_ / "reference";
  ASSERT_EQ(run_cli("run " + scenario.string() + " --quiet --no-checkpoint --out " + reference.string()).exit_code, 0);
  const fs::path out = dir_ / "stopped";
  ASSERT_EQ(run_and_signal_when(scenario, out, "settling at 0.05", SIGINT), 130);
  const auto summary = nlohmann::json::parse(std::ifstream(out / "summary.json"));
  EXPECT_TRUE(summary.at("interrupted").get<bool>());
  const auto& checkpoint = summary.at("interruption").at("checkpoint");
  EXPECT_EQ(checkpoint.at("file"), "checkpoint.bin");
  // The checkpoint is the stop's own safe point.
  EXPECT_EQ(checkpoint.at("taken"), summary.at("interruption").at("stopped"));
  EXPECT_NE(checkpoint.at("resume").get<std::string>().find("aggpack resume"), std::string::npos);
  const auto resumed = run_cli("resume " + out.string() + " --quiet");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  expect_same_run(reference, out);
}

// An interrupted run's particles.csv is the bed as it stood mid-step, not a final bed:
// export-lammps RUN_DIR says so on the terminal and in the files it writes.
TEST_F(Resume, AnInterruptedRunsBedIsExportedAsTheBedWhereItStopped) {
  const fs::path scenario = write_scenario("layered", kLayered);
  const fs::path out = dir_ / "stopped";
  ASSERT_EQ(run_and_signal_when(scenario, out, "settling at 0.05", SIGINT), 130);
  const std::string stopped =
      nlohmann::json::parse(std::ifstream(out / "summary.json")).at("interruption").at("stopped").get<std::string>();
  const auto e = run_cli("export-lammps " + out.string() + " --out " + (dir_ / "deck").string());
  ASSERT_EQ(e.exit_code, 0) << e.output;
  const std::string said = "the bed of the interrupted run in " + out.string() + ", as it stood " + stopped;
  EXPECT_NE(e.output.find("exported " + said + ", not a final bed"), std::string::npos) << e.output;
  EXPECT_EQ(e.output.find("the final bed"), std::string::npos) << e.output;
  const std::string deck = slurp(dir_ / "deck" / "settle.in"), data = slurp(dir_ / "deck" / "bed.data");
  EXPECT_NE(deck.find("\n# Not a final bed: " + said), std::string::npos) << deck;
  EXPECT_NE(data.substr(0, data.find('\n')).find(". Not a final bed: " + said), std::string::npos) << data.substr(0, 300);
}

TEST_F(Resume, WithCheckpointsOffAnInterruptedSummarySaysThereIsNone) {
  const fs::path scenario = write_scenario("long", std::string(kLayered) + "[output]\ncheckpoint = false\n");
  const fs::path out = dir_ / "stopped";
  // Signalled some 0.3 s after it made its folder: inside the run, with no checkpoint to take.
  std::optional<std::chrono::steady_clock::time_point> began;
  const std::optional<int> code = signal_aggpack_when(
      {"run", scenario.string(), "--quiet", "--out", out.string()},
      [&] {
        if (!began && fs::exists(out)) began = std::chrono::steady_clock::now();
        return began && std::chrono::steady_clock::now() - *began >= std::chrono::milliseconds(300);
      },
      SIGTERM);
  ASSERT_TRUE(code.has_value()) << "the run ended before it was signalled";
  ASSERT_EQ(*code, 143);
  EXPECT_FALSE(fs::exists(out / "checkpoint.bin"));
  const auto summary = nlohmann::json::parse(std::ifstream(out / "summary.json"));
  EXPECT_TRUE(summary.at("interruption").at("checkpoint").is_null());
  EXPECT_EQ(summary.at("scenario").at("output").at("checkpoint"), false);
  const auto r = run_cli("resume " + out.string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("no checkpoint.bin here"), std::string::npos) << r.output;
}

// A checkpoint that cannot be written (here its name is taken by a folder; a full disk alike)
// does not stop the run: it finishes, and its summary says why checkpoints stopped.
TEST_F(Resume, ACheckpointThatCannotBeWrittenDoesNotStopTheRun) {
  const fs::path scenario = write_scenario("layered", kLayered);
  const fs::path out = dir_ / "out";
  fs::create_directories(out / "checkpoint.bin" / "taken");
  // The folder is not an earlier run's: the run writes beside it only when told to.
  const auto r = run_cli("run " + scenario.string() + " --checkpoint-every 0 --overwrite --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("warning: writing " + (out / "checkpoint.bin").string()), std::string::npos) << r.output;
  const auto summary = nlohmann::json::parse(std::ifstream(out / "summary.json"));
  EXPECT_NE(summary.at("checkpoint_error").get<std::string>().find("no further checkpoints"), std::string::npos);
  EXPECT_TRUE(summary.at("wall_clock_s").contains("checkpoints"));
}

// What resume cannot continue: exit 2, the folder or file named, what is wrong, nothing changed.
TEST_F(Resume, RefusesWhatItCannotContinue) {
  const fs::path scenario = write_scenario("layered", kLayered);
  const fs::path out = dir_ / "killed";
  ASSERT_EQ(run_and_signal_when(scenario, out, "before step 2 of 6", SIGKILL), -SIGKILL);
  const std::string checkpoint = slurp(out / "checkpoint.bin");
  const auto refused = [&](const std::string& args, const std::vector<std::string>& words) {
    SCOPED_TRACE("aggpack " + args);
    const auto r = run_cli(args);
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_EQ(r.output.find("internal error"), std::string::npos) << r.output;
    for (const std::string& word : words) EXPECT_NE(r.output.find(word), std::string::npos) << word << "\n" << r.output;
    EXPECT_FALSE(fs::exists(out / "summary.json"));
  };
  refused("resume " + (dir_ / "nowhere").string(), {"nowhere", "no such directory"});
  refused("resume " + dir_.string(), {dir_.string(), "no checkpoint.bin here"});
  refused("resume " + out.string() + " --set seed=5", {"seed=5"});
  refused("resume " + out.string() + " --threads 1000", {"--threads"});
  refused("resume " + out.string() + " --checkpoint-every -1", {"--checkpoint-every -1", "seconds"});
  const auto with_checkpoint = [&](const std::string& bytes, const std::vector<std::string>& words) {
    std::ofstream(out / "checkpoint.bin", std::ios::binary) << bytes;
    refused("resume " + out.string(), words);
  };
  with_checkpoint(checkpoint.substr(0, checkpoint.size() / 2),
                  {"checkpoint.bin is damaged; run again without resume", "runs past the end of the file"});
  with_checkpoint("a text file, not a checkpoint\n", {"checkpoint.bin", "not an aggpack checkpoint"});
  // Written by another version of aggpack (its version string patched in place).
  std::string version = run_cli("--version").output;
  version.erase(version.find_last_not_of(" \n") + 1);
  std::string other = checkpoint;
  const auto at = other.find(version);
  ASSERT_NE(at, std::string::npos);
  other.replace(at, version.size(), std::string(version.size(), '9'));
  with_checkpoint(aggpack::resealed_checkpoint(other), {"checkpoint.bin", "written by aggpack " + std::string(version.size(), '9'), "run the scenario again"});
  // The grading or particle file changed since the checkpoint: the bed would not be the same.
  // (200 spheres on a loose lattice, falling: far from quiet when killed.)
  const auto write_bed = [&](double last_z) {
    std::ofstream bed(dir_ / "bed.csv");
    bed << "x,y,z,r\n";
    for (int k = 0; k < 200; ++k)
      bed << 0.012 + 0.014 * (k % 5) << "," << 0.012 + 0.014 * (k / 5 % 5) << ","
          << (k == 199 ? last_z : 0.006 + 0.014 * (k / 25)) << ",0.005\n";
  };
  write_bed(0.2);
  const std::string settling = "[container]\nside = 0.08\nheight = 0.3\n[particles]\nfrom = \"bed.csv\"\n[material]\n"
                               "youngs_modulus = 1e8\nwall_youngs_modulus = 1e8\n[dynamics]\nmax_time = 100\n"
                               "quiet_kinetic_fraction = 1e-30\n[analysis]\nbox_sides = [0.01]\n";
  const fs::path from_file = write_scenario("from_file", settling);
  const fs::path settled = dir_ / "settled";
  ASSERT_EQ(run_and_signal_when(from_file, settled, "while settling", SIGKILL), -SIGKILL);
  write_bed(0.21);
  const auto r = run_cli("resume " + settled.string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("a particle, grading or calibration file the scenario reads has changed"), std::string::npos)
      << r.output;
  // A calibration file refitted since the checkpoint: the run would go on with other physics.
  write_bed(0.2);
  const auto calibration = [&](double value) {
    std::ofstream(dir_ / "cal.json")
        << R"({"kind": "aggpack DEM calibration", "scenario_file": "s.toml", "protocol": "settle", "seeds": 2,
               "measured": {"density": 0.6, "of": "the bed"},
               "fit": {"parameter": "rolling_friction", "value": 0.1, "band": [0.05, 0.15]},
               "assignments": ["material.rolling_friction=)"
        << value << R"("]})";
  };
  calibration(0.1);
  const fs::path calibrated = write_scenario("calibrated", "calibrated_by = \"cal.json\"\n" + settling);
  const fs::path killed = dir_ / "calibrated_run";
  ASSERT_EQ(run_and_signal_when(calibrated, killed, "while settling", SIGKILL), -SIGKILL);
  calibration(0.2);
  const auto refitted = run_cli("resume " + killed.string());
  EXPECT_EQ(refitted.exit_code, 2) << refitted.output;
  EXPECT_NE(refitted.output.find("calibration file the scenario reads has changed"), std::string::npos)
      << refitted.output;
}

// A damaged checkpoint.bin is refused: exit 2 and "checkpoint.bin is damaged; run again
// without resume", never a crash, never a resume to another result. A byte changed anywhere
// past the format number, in a section's length, in the DEM's user-index table or neighbour
// list: each section's checksum sees it. The same damage with the checksums made to match
// again (resealed_checkpoint) is refused by the checks of the decoded values against the
// scenario: indices, the bed's radii.
TEST_F(Resume, ADamagedCheckpointIsRefusedNeverResumed) {
  // 200 spheres deposited, then settling (never quiet: killed while settling).
  const fs::path scenario = write_scenario(
      "settling", "seed = 5\n[container]\nside = 0.06\nheight = 0.3\n[particles]\ndiameter = 0.01\ncount = 200\n"
                  "[material]\nyoungs_modulus = 1e8\nwall_youngs_modulus = 1e8\n[deposition]\n[dynamics]\n"
                  "max_time = 1\nquiet_kinetic_fraction = 1e-30\n[analysis]\nbox_sides = [0.02]\n");
  const fs::path out = dir_ / "killed";
  ASSERT_EQ(run_and_signal_when(scenario, out, "while settling", SIGKILL), -SIGKILL);
  const std::string intact = slurp(out / "checkpoint.bin");
  const auto refused = [&](const std::string& bytes, const std::string& damage) {
    SCOPED_TRACE(damage);
    std::ofstream(out / "checkpoint.bin", std::ios::binary | std::ios::trunc) << bytes;
    const auto r = run_cli("resume " + out.string() + " --quiet --threads 1");
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find((out / "checkpoint.bin").string() + " is damaged; run again without resume"),
              std::string::npos)
        << r.output;
    EXPECT_EQ(r.output.find("internal error"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(out / "summary.json"));
    // Resealed, the damage passes the checksums: the checks of the values refuse it.
    if (damage.find("resealed") != std::string::npos) {
      EXPECT_EQ(r.output.find("checksum"), std::string::npos) << r.output;
    }
  };
  const auto changed = [&](std::size_t at, unsigned char bits) {
    std::string bytes = intact;
    bytes[at] = static_cast<char>(bytes[at] ^ bits);
    return bytes;
  };
  // One byte changed, at 24 places across the file after its magic and format number (30 bytes).
  constexpr std::size_t kStart = 30;
  for (std::size_t k = 0; k < 24; ++k) {
    const std::size_t at = kStart + (intact.size() - kStart) * k / 24;
    refused(changed(at, 0x10), "byte " + std::to_string(at) + " of " + std::to_string(intact.size()));
  }
  refused(changed(intact.size() - 1, 0x01), "the last byte");
  // The run state's length (after the header's length, bytes and checksum): huge, or one more.
  std::uint64_t header = 0;
  std::memcpy(&header, intact.data() + kStart, 8);
  const std::size_t run_state_length = kStart + 8 + header + 8;
  refused(changed(run_state_length + 6, 0x40), "the run state's length, made huge");
  refused(changed(run_state_length, 0x01), "the run state's length, one more");
  // The DEM's user-index table: each of the 200 particles once.
  const std::size_t user_index = find_table(intact, 200, [](const std::vector<std::uint32_t>& v, std::size_t) {
    std::vector<bool> seen(v.size());
    for (const std::uint32_t i : v) {
      if (i >= v.size() || seen[i]) return false;
      seen[i] = true;
    }
    return true;
  });
  ASSERT_NE(user_index, std::string::npos);
  refused(changed(user_index + 4 * 17, 0x01), "the user-index table");
  refused(aggpack::resealed_checkpoint(changed(user_index + 4 * 17, 0x01)), "the user-index table, resealed");
  refused(aggpack::resealed_checkpoint(changed(user_index + 4 * 17 + 3, 0x80)),
          "the user-index table, out of range, resealed");
  // The neighbour list: its 201 row offsets (from 0, ascending), then its entries (as many as
  // the last offset says, after their count).
  std::uint32_t entries = 0;
  const std::size_t offsets = find_table(intact, 201, [&](const std::vector<std::uint32_t>& v, std::size_t end) {
    std::uint64_t count = 0;
    std::memcpy(&count, intact.data() + end, 8);
    entries = v.back();
    return v.front() == 0 && std::is_sorted(v.begin(), v.end()) && count == v.back() && count > 100;
  });
  ASSERT_NE(offsets, std::string::npos);
  const std::size_t list = offsets + 4 * 201 + 8;
  refused(changed(list + 4 * (entries / 2), 0x04), "the neighbour list");
  refused(aggpack::resealed_checkpoint(changed(list + 4 * (entries / 2) + 3, 0x7f)), "the neighbour list, resealed");
  refused(aggpack::resealed_checkpoint(changed(offsets + 4 * 100 + 3, 0x7f)), "a row's offset, resealed");
  // The bed's radii in the run state: 200 of 5 mm; one changed by a few per cent.
  std::string radius(16, '\0');
  const std::uint64_t count = 200;
  const double five_mm = 0.005;
  std::memcpy(radius.data(), &count, 8);
  std::memcpy(radius.data() + 8, &five_mm, 8);
  const std::size_t radii = intact.find(radius);
  ASSERT_NE(radii, std::string::npos);
  refused(aggpack::resealed_checkpoint(changed(radii + 8 + 8 * 3 + 5, 0x01)), "a radius, resealed");
  // Intact, it is not refused.
  std::ofstream(out / "checkpoint.bin", std::ios::binary | std::ios::trunc) << intact;
  const auto r = run_cli("resume " + out.string() + " --quiet --threads 1");
  EXPECT_EQ(r.exit_code, 0) << r.output;
}

// Issue 55, item 20: a pour of grains is counted in grains (its progress and the checkpoint's
// "where" said "2100 of 700 in": member spheres against grains). 150 grains of 2 spheres and
// 40 spheres in two batches: the first batch in is "95 of 190".
TEST_F(Resume, APourOfGrainsCountsItsParticlesNotTheirSpheres) {
  const fs::path scenario = write_scenario(
      "grains", "seed = 2\n[container]\nside = 0.045\nheight = 0.3\n[particles]\nclasses = [{ diameter = 0.008, "
                "count = 150, shape = { family = \"rounded\", spheres = 2, templates = 3 } }, { diameter = 0.005, "
                "count = 40 }]\n[material]\nyoungs_modulus = 1e7\nwall_youngs_modulus = 1e7\n[pour]\nbatches = 2\n"
                "solid_fraction = 0.15\n[dynamics]\nmax_time = 0.8\n[analysis]\nbox_sides = [0.006]\n");
  EXPECT_EQ(run_and_signal_when(scenario, dir_ / "grains", "while pouring, 95 of 190 in", SIGKILL), -SIGKILL)
      << "no checkpoint was taken while pouring, 95 of 190 in";
}

}  // namespace

namespace {

// Issue 55, item 2: a resume refused for its checkpoint's contents (damage past the checksums,
// resealed: the run state's or the step state's values do not fit the run) loses nothing (it
// deleted them in 238 of 239 such refusals). The
// interrupted run's particles.csv, summary.json and timeseries.csv stay as they were; they are
// replaced only by a resumed run's own.
TEST_F(Resume, ARefusedResumeLeavesTheInterruptedRunsOutputs) {
  const fs::path scenario = write_scenario(
      "stopped", "seed = 5\n[container]\nside = 0.06\nheight = 0.3\n[particles]\ndiameter = 0.01\ncount = 200\n"
                 "[material]\nyoungs_modulus = 1e8\nwall_youngs_modulus = 1e8\n[deposition]\n[dynamics]\n"
                 "max_time = 0.25\nquiet_kinetic_fraction = 1e-30\n[analysis]\nbox_sides = [0.02]\n");
  const fs::path out = dir_ / "stopped";
  ASSERT_EQ(run_and_signal_when(scenario, out, "while settling", SIGTERM), 128 + SIGTERM);
  const std::vector<std::string> outputs{"particles.csv", "summary.json", "timeseries.csv", "aggpack-manifest.json"};
  std::map<std::string, std::string> before;
  for (const std::string& name : outputs) {
    ASSERT_TRUE(fs::exists(out / name)) << name;
    before[name] = slurp(out / name);
  }
  const std::string intact = slurp(out / "checkpoint.bin");
  std::size_t refusals = 0;
  for (std::size_t k = 1; k <= 16; ++k) {  // 16 places across the file (40 took 45 s; a resume that goes on costs a run)
    std::string bytes = intact;
    const std::size_t at = intact.size() * k / 17;
    bytes[at] = static_cast<char>(bytes[at] ^ 0x04);
    std::ofstream(out / "checkpoint.bin", std::ios::binary | std::ios::trunc) << aggpack::resealed_checkpoint(bytes);
    const auto r = run_cli("resume " + out.string() + " --quiet --threads 1");
    if (r.exit_code == 2) {
      ++refusals;
      for (const std::string& name : outputs)
        EXPECT_EQ(slurp(out / name), before.at(name)) << name << " changed by a refused resume (byte " << at << ")";
    } else if (r.exit_code == 0) {  // damage the checks cannot see (a velocity's low bit): the run went on
      for (const std::string& name : outputs)
        std::ofstream(out / name, std::ios::binary | std::ios::trunc) << before.at(name);
    }
  }
  EXPECT_GE(refusals, 5u) << "too few of the changes were refused to test what a refusal leaves (7 of 16 were)";
}

}  // namespace

// Rodding and jigging (README "Rodding", "Jigging"): deposited in two parts, the lower rodded to
// the floor, the upper into the lower, then jigged; killed while rodding and while jigging,
// resumed on another thread count, it ends with the same bytes.
constexpr const char* kRodAndJig =
    "seed = 6\n[container]\nside = 0.08\nheight = 0.3\n[particles]\ndiameter = 0.01\ncount = 300\n"
    "[material]\nyoungs_modulus = 1e8\nwall_youngs_modulus = 1e8\n[deposition]\n[dynamics]\nmax_time = 0.05\n"
    "[analysis]\nbox_sides = [0.02]\n"
    "[rodding]\nstrokes = 3\nspeed = 2.0\nmax_force = 20.0\npenetration = \"10 mm\"\nrest_time = 0.02\nrest_until_quiet = false\n"
    "[jigging]\ndrops = 2\nheight = \"10 mm\"\nrest_time = 0.03\n"
    "[[protocol]]\nstep = \"deposit\"\nlayer = 0\nlayers = 2\n[[protocol]]\nstep = \"rod\"\n"
    "[[protocol]]\nstep = \"deposit\"\nlayer = 1\nlayers = 2\n[[protocol]]\nstep = \"rod\"\n"
    "[[protocol]]\nstep = \"jig\"\n";

TEST_F(Resume, ARoddedAndJiggedRunKilledWhileRoddingAndJiggingResumesToTheSameBytes) {
  const fs::path scenario = write_scenario("rod_jig", kRodAndJig);
  const fs::path reference = dir_ / "reference";
  const auto r = run_cli("run " + scenario.string() + " --quiet --threads 1 --no-checkpoint --out " + reference.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // The strokes reached their depths: the first rodding to 5 mm above the floor, the second
  // 25 mm into the first part (its top, the highest sphere of the part below).
  const auto summary = nlohmann::json::parse(std::ifstream(reference / "summary.json"));
  const auto& rodding = summary.at("stages").at("rodding").at("steps");
  ASSERT_EQ(rodding.size(), 2u);
  EXPECT_EQ(rodding[0].at("depth"), "floor");
  EXPECT_DOUBLE_EQ(rodding[0].at("target_tip_lowest_m").get<double>(), 0.005);
  EXPECT_EQ(rodding[1].at("depth"), "layer_below");
  EXPECT_GT(rodding[1].at("target_tip_lowest_m").get<double>(), 0.005 + 1e-4);  // above the floor mode's
  // Each stroke reached its target, or stopped where the bed pushed back with more than max_force.
  for (const auto& step : rodding)
    for (std::size_t k = 0; k < 3; ++k) {
      const double lowest = step.at("tip_lowest_of_each_stroke_m")[k].get<double>();
      const double force = step.at("peak_force_of_each_stroke_n")[k].get<double>();
      EXPECT_TRUE(std::abs(lowest - step.at("target_tip_lowest_m").get<double>()) < 1e-3 || force > 20.0)
          << lowest << " " << force;
    }
  for (const auto& step : rodding) {
    ASSERT_EQ(step.at("peak_force_of_each_stroke_n").size(), 3u);
    for (const auto& force : step.at("peak_force_of_each_stroke_n")) EXPECT_GT(force.get<double>(), 0.0);
  }
  const auto& jigging = summary.at("stages").at("jigging");
  EXPECT_EQ(jigging.at("drops"), 2);
  EXPECT_NEAR(jigging.at("impact_speed_m_s").get<double>(), std::sqrt(2.0 * 9.81 * 0.01), 1e-9);
  EXPECT_TRUE(fs::exists(reference / "rod_strokes.csv"));
  EXPECT_TRUE(fs::exists(reference / "jig_drops.csv"));

  const fs::path out = dir_ / "killed";
  ASSERT_EQ(run_and_signal_when(scenario, out, "while rod stroke 2 of 3", SIGKILL), -SIGKILL);
  ASSERT_EQ(resume_and_signal_when(out, "while jig drop 2 of 2", SIGKILL, "2"), -SIGKILL);
  const auto resumed = run_cli("resume " + out.string() + " --threads 1");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  expect_same_run(reference, out);
}

TEST_F(Resume, RoddingAndJiggingAreRefusedWhereTheyCannotRun) {
  const std::string base =
      "[container]\nside = 0.08\nheight = 0.3\n[particles]\ndiameter = 0.01\ncount = 30\n[deposition]\n";
  const auto refused = [&](const std::string& name, const std::string& text, const std::string& message) {
    const auto r = run_cli("check " + write_scenario(name, base + text).string());
    EXPECT_EQ(r.exit_code, 2) << name << ": " << r.output;
    EXPECT_NE(r.output.find(message), std::string::npos) << name << ": " << r.output;
  };
  refused("lammps", "[dynamics]\nengine = \"lammps\"\n[rodding]\n",
          "rodding runs in aggpack's own DEM only");
  refused("lammps_jig", "[dynamics]\nengine = \"lammps\"\n[jigging]\n", "jigging runs in aggpack's own DEM only");
  refused("no_dynamics", "[rodding]\n", "add a [dynamics] table");
  refused("unused", "[dynamics]\n[rodding]\n[[protocol]]\nstep = \"deposit\"\n[[protocol]]\nstep = \"settle\"\n",
          "[rodding] is given but no rod step uses it");
  refused("no_table", "[dynamics]\n[[protocol]]\nstep = \"deposit\"\n[[protocol]]\nstep = \"jig\"\n",
          "a jig step takes its settings from a [jigging] table");
  refused("wide_rod", "[dynamics]\n[rodding]\nrod_diameter = 0.09\n", "does not fit the container's section");
  refused("lift", "[dynamics]\n[jigging]\nlift_acceleration = 12\n", "is not below g");
  refused("export", "[dynamics]\n[rodding]\n[[protocol]]\nstep = \"deposit\"\n[[protocol]]\nstep = \"export_lammps\"\n"
          "name = \"x\"\n[[protocol]]\nstep = \"rod\"\n", "a rod or jig step has no LAMMPS deck");
}
