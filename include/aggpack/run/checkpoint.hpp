#pragma once
#include <array>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <ostream>
#include <optional>
#include <string>
#include <string_view>

#include "aggpack/core/error.hpp"
#include "aggpack/core/stop_request.hpp"
#include "aggpack/io/scenario.hpp"
#include "aggpack/run/safe_point.hpp"

namespace aggpack {

struct RunReport;
struct RunContext;
struct ParticleStore;

// checkpoint.bin in a run's folder: the run's state at a safe point, for `aggpack resume`.
inline constexpr const char* kCheckpointFile = "checkpoint.bin";

// What a checkpoint holds. The scenario's text and the command line's overrides make the
// same scenario again; the rest is the run's state at the safe point named by `where`.
struct Checkpoint {
  std::string version;          // aggpack's, of the run that wrote it (resume refuses another)
  std::string scenario_file;    // as the run was given it: it anchors the scenario's relative paths
  std::string working_directory;  // the run's, absolute: where a relative scenario_file lies
  std::string scenario_text;
  ScenarioOverrides overrides;
  std::optional<std::string> stop_after;
  std::uint64_t inputs_fingerprint = 0;  // of the bed the run started from and its calibrations (input_fingerprint)
  std::string where;                     // "before step 2 of 3", "while settling at 0.1230 s simulated"
  std::uint64_t steps_completed = 0;     // protocol steps done before the safe point
  // As read back (writing streams them into the file instead, encode_checkpoint):
  std::string run_state;                 // the steps' reports and beds (empty before the first step)
  std::string step_state;                // the step in progress (empty between steps)
};

// The file: "aggpack checkpoint" (as a cereal string) and the format number, then three
// sections, the header, the run state and the step state, each its length (8 bytes), its
// bytes and their checksum (XXH64, 8 bytes): any damage to a section is seen before anything
// in it is decoded. `header` (its run_state and step_state left aside) with the states the
// two writers write (null: empty), straight into `out`.
void encode_checkpoint(std::ostream& out, const Checkpoint& header, const StateWriter& run_state,
                       const StateWriter& step_state);
// Throws InputError naming `file` when the bytes are not a checkpoint of this version, or
// damaged_checkpoint() when a section does not match its checksum or its header cannot be read.
Checkpoint decode_checkpoint(const std::string& bytes, const std::filesystem::path& file);
// The three sections of a checkpoint, each checked against its checksum (as decode_checkpoint).
std::array<std::string_view, 3> checkpoint_sections(std::string_view bytes, const std::filesystem::path& file);
// The bytes with the checksums of the sections from `first` on (0: the header, 1: the run
// state, 2: the step state) made to match them, as far as their lengths allow: for the fuzz
// target and the tests, to reach the checks made past the checksums.
std::string resealed_checkpoint(std::string bytes, std::size_t first = 0);

// A checkpoint whose bytes decode, but to what its run cannot be: thrown by the decoding of
// the run and step states, turned into damaged_checkpoint() naming the file by resume_run().
class DamagedCheckpoint : public InputError {
 public:
  using InputError::InputError;
};
// "FILE is damaged; run again without resume (what)".
InputError damaged_checkpoint(const std::filesystem::path& file, std::string_view what);
// The checkpoint in a run's folder; InputError when there is none or it cannot be read.
Checkpoint read_checkpoint(const std::filesystem::path& run_directory);
// The scenario file's path for a resumed run: as given when resumed from the same working
// directory (the summary's paths are then the same), else made absolute against the run's.
std::filesystem::path resumed_scenario_path(const Checkpoint& checkpoint);

// The steps' reports and beds, and the state passed from step to step. Decoding checks them
// against the run (report.scenario, context.radii, and the particle file's bed in
// report.particles): DamagedCheckpoint when they do not fit.
void encode_run_state(std::ostream& out, const RunReport& report, const RunContext& context);
void decode_run_state(const std::string& state, RunReport& report, RunContext& context);

// A hash of the bed and the drop sequence a run starts from: a resumed run must start from
// the same (its particle or grading files unchanged).
// `calibrations`: the values the scenario's calibration files gave it (a file refitted since the
// checkpoint would continue the run with other physics).
std::uint64_t input_fingerprint(const ParticleStore& particles, const std::vector<double>& radii,
                                std::string_view calibrations = {});

// Writes a run's checkpoints: at a safe point once `every_seconds` of wall clock have passed
// since the last one (0: at every safe point), and at the safe point where a stop was
// requested, before the run stops there. Each is written atomically over the last. A write
// that fails (a full disk) does not stop the run: checkpoints end there, and error() says why.
class Checkpointer final : public SafePoint {
 public:
  using SaveRun = StateWriter;  // encode_run_state of the run now
  Checkpointer(std::filesystem::path directory, double every_seconds, Checkpoint header, const StopRequest* stop,
               SaveRun save_run);
  // The protocol's position: `completed` steps done (the current one is next, or in progress).
  void set_steps_completed(std::uint64_t completed) { header_.steps_completed = completed; }
  void reached(const std::string& where, const StateWriter& save_step) override;
  // Writes one now (the start of a run: resume then always has a checkpoint to start from).
  void write(const std::string& where, const StateWriter& save_step);
  // Where the last checkpoint was taken; none when none has been written.
  [[nodiscard]] const std::optional<std::string>& last_written() const { return last_where_; }
  [[nodiscard]] double seconds_spent() const { return seconds_spent_; }  // writing them
  [[nodiscard]] const std::optional<std::string>& error() const { return error_; }

 private:
  using Clock = std::chrono::steady_clock;
  std::filesystem::path directory_;
  double every_seconds_;
  Checkpoint header_;
  const StopRequest* stop_;
  SaveRun save_run_;
  Clock::time_point last_write_;
  std::optional<std::string> last_where_;
  double seconds_spent_ = 0.0;
  std::optional<std::string> error_;
};

}  // namespace aggpack
