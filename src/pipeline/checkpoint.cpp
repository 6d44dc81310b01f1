#include "aggpack/pipeline/checkpoint.hpp"

#include <cstring>
#include <sstream>

#include <fmt/format.h>

#include "aggpack/core/error.hpp"
#include "aggpack/core/input_file.hpp"
#include "aggpack/core/version.hpp"
#include "aggpack/io/atomic_file.hpp"
#include "aggpack/pipeline/steps.hpp"
#include "pipeline/report_archive.hpp"

namespace aggpack {

namespace {
constexpr std::string_view kMagic = "aggpack checkpoint";
constexpr std::uint32_t kFormat = 2;  // raise when what a checkpoint holds changes

template <class Archive>
void archive_overrides(Archive& ar, ScenarioOverrides& o) {
  std::optional<std::string> directory;
  if (o.output_directory) directory = o.output_directory->string();
  ar(o.set, o.seed, directory);
  if (directory) o.output_directory = *directory;
}

// The header's fields; the run and step states follow, each as a string (its length, then its bytes).
template <class Archive>
void archive_header(Archive& ar, Checkpoint& c) {
  ar(c.version, c.scenario_file, c.working_directory, c.scenario_text);
  archive_overrides(ar, c.overrides);
  ar(c.stop_after, c.inputs_fingerprint, c.where, c.steps_completed);
}

// What `write` writes, in the layout of a cereal string: its length (patched in once written), its bytes.
void write_as_string(std::ostream& out, const StateWriter& write) {
  const std::streampos at = out.tellp();
  std::uint64_t length = 0;
  out.write(reinterpret_cast<const char*>(&length), sizeof length);
  if (write) write(out);
  const std::streampos end = out.tellp();
  length = static_cast<std::uint64_t>(end - at) - sizeof length;
  out.seekp(at);
  out.write(reinterpret_cast<const char*>(&length), sizeof length);
  out.seekp(end);
}

// The run's state from step to step (the scenario and the drop sequence are made again).
template <class Archive>
void archive_run_state(Archive& ar, RunReport& r, RunContext& c) {
  ar(r.particles, r.deposition, raw(r.pours), r.tappings, r.dynamics, r.analyses, r.deposited, r.snapshots, r.lammps_exchanges, raw(r.supports),
     r.series, r.wall_clock_s, c.simulated_time, c.deposition_stopped_at);
}
}  // namespace

void encode_checkpoint(std::ostream& out, const Checkpoint& header, const StateWriter& run_state,
                       const StateWriter& step_state) {
  {
    cereal::BinaryOutputArchive ar(out);  // writes through to `out` at once: no buffer to flush
    ar(std::string(kMagic), kFormat);
    archive_header(ar, const_cast<Checkpoint&>(header));
  }
  write_as_string(out, run_state);
  write_as_string(out, step_state);
}

Checkpoint decode_checkpoint(const std::string& bytes, const std::filesystem::path& file) {
  std::istringstream in(bytes, std::ios::binary);
  Checkpoint c;
  try {
    cereal::BinaryInputArchive ar(in);
    // The magic first, read by hand: any file may be given, and cereal trusts string lengths.
    if (bytes.size() < 8 + kMagic.size() || bytes.compare(8, kMagic.size(), kMagic) != 0)
      throw InputError(fmt::format("{}: not an aggpack checkpoint", file.string()));
    std::string magic;
    std::uint32_t format = 0;
    ar(magic, format);
    if (format != kFormat)
      throw InputError(fmt::format("{}: a checkpoint of format {}; this aggpack ({}) reads format {}", file.string(),
                                   format, kVersion, kFormat));
    archive_header(ar, c);
    ar(c.run_state, c.step_state);
  } catch (const cereal::Exception& e) {
    throw InputError(fmt::format("{}: the checkpoint is truncated or damaged ({})", file.string(), e.what()));
  } catch (const std::bad_alloc&) {
    throw InputError(fmt::format("{}: the checkpoint is damaged (a length beyond memory)", file.string()));
  } catch (const std::length_error&) {
    throw InputError(fmt::format("{}: the checkpoint is damaged (a length beyond memory)", file.string()));
  }
  if (c.version != kVersion)
    throw InputError(fmt::format("{}: written by aggpack {}, this is aggpack {}: a run continues only with the build "
                                 "that began it (its results would not be the same bytes); run the scenario again",
                                 file.string(), c.version, kVersion));
  return c;
}

Checkpoint read_checkpoint(const std::filesystem::path& run_directory) {
  const std::filesystem::path file = run_directory / kCheckpointFile;
  std::error_code ec;
  if (!std::filesystem::is_directory(run_directory, ec))
    throw InputError(fmt::format("{}: not a run's folder (no such directory)", run_directory.string()));
  if (!std::filesystem::exists(file, ec))
    throw InputError(fmt::format(
        "{}: no {} here: the run finished (its summary.json says so), or it ran with checkpoints off "
        "(output.checkpoint = false, --no-checkpoint), or this is not a run's folder",
        run_directory.string(), kCheckpointFile));
  return decode_checkpoint(read_input_file(file, "the checkpoint", std::uintmax_t{64} << 30), file);
}

std::filesystem::path resumed_scenario_path(const Checkpoint& checkpoint) {
  const std::filesystem::path given = checkpoint.scenario_file;
  std::error_code ec;
  if (given.is_absolute() || std::filesystem::current_path(ec) == checkpoint.working_directory) return given;
  return std::filesystem::path(checkpoint.working_directory) / given;
}

void encode_run_state(std::ostream& out, const RunReport& report, const RunContext& context) {
  cereal::BinaryOutputArchive ar(out);
  archive_run_state(ar, const_cast<RunReport&>(report), const_cast<RunContext&>(context));
}

void decode_run_state(const std::string& state, RunReport& report, RunContext& context) {
  std::istringstream in(state, std::ios::binary);
  try {
    cereal::BinaryInputArchive ar(in);
    archive_run_state(ar, report, context);
  } catch (const cereal::Exception& e) {
    throw InputError(fmt::format("the checkpoint's run state is truncated or damaged ({})", e.what()));
  }
}

std::uint64_t input_fingerprint(const ParticleStore& particles, const std::vector<double>& radii) {
  std::uint64_t hash = 0xcbf29ce484222325ull;  // FNV-1a over the bytes
  const auto add = [&](const void* data, std::size_t bytes) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < bytes; ++i) hash = (hash ^ p[i]) * 0x100000001b3ull;
  };
  add(particles.position.data(), particles.position.size() * sizeof(Vec3));
  add(particles.radius.data(), particles.radius.size() * sizeof(double));
  add(radii.data(), radii.size() * sizeof(double));
  return hash;
}

Checkpointer::Checkpointer(std::filesystem::path directory, double every_seconds, Checkpoint header,
                           const StopRequest* stop, SaveRun save_run)
    : directory_(std::move(directory)), every_seconds_(every_seconds), header_(std::move(header)), stop_(stop),
      save_run_(std::move(save_run)), last_write_(Clock::now()) {}

void Checkpointer::reached(const std::string& where, const StateWriter& save_step) {
  const bool stopping = stop_ && stop_->requested();
  const bool due = std::chrono::duration<double>(Clock::now() - last_write_).count() >= every_seconds_;
  if (!error_ && (stopping || due)) write(where, save_step);
  stop_here_if_requested(stop_, where);
}

void Checkpointer::write(const std::string& where, const StateWriter& save_step) {
  const auto t0 = Clock::now();
  header_.where = where;
  // Before any step has changed the bed, resume starts the run afresh: no run state to save.
  const bool started = header_.steps_completed > 0 || save_step;
  try {
    write_file_atomically(directory_ / kCheckpointFile, [&](std::ostream& out) {
      encode_checkpoint(out, header_, started ? save_run_ : nullptr, save_step);
    });
    last_where_ = where;
  } catch (const std::exception& e) {
    error_ = fmt::format("writing {} {} failed ({}); no further checkpoints were written",
                         (directory_ / kCheckpointFile).string(), where, e.what());
  }
  last_write_ = Clock::now();
  seconds_spent_ += std::chrono::duration<double>(last_write_ - t0).count();
}

}  // namespace aggpack
