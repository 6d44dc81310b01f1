#include "aggpack/run/checkpoint.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <set>
#include <span>

#include <fmt/format.h>

#include "aggpack/core/error.hpp"
#include "aggpack/core/input_file.hpp"
#include "aggpack/core/version.hpp"
#include "aggpack/io/dem_setup.hpp"
#include "aggpack/io/atomic_file.hpp"
#include "aggpack/run/carried_dem.hpp"
#include "aggpack/run/protocol.hpp"
#include "aggpack/run/steps.hpp"
#include "core/checksum.hpp"
#include "run/report_archive.hpp"

namespace aggpack {

namespace {
constexpr std::string_view kMagic = "aggpack checkpoint";
constexpr std::uint32_t kFormat = 8;  // raise when what a checkpoint holds changes (8: rodding, jigging)
constexpr std::array<const char*, 3> kSections{"header", "run state", "step state"};

template <class Archive>
void archive_overrides(Archive& ar, ScenarioOverrides& o) {
  std::optional<std::string> directory;
  if (o.output_directory) directory = o.output_directory->string();
  ar(o.set, o.seed, directory);
  if (directory) o.output_directory = *directory;
}

// The header's fields (the first section).
template <class Archive>
void archive_header(Archive& ar, Checkpoint& c) {
  ar(c.version, c.scenario_file, c.working_directory, c.scenario_text);
  archive_overrides(ar, c.overrides);
  ar(c.stop_after, c.inputs_fingerprint, c.where, c.steps_completed);
}

void write_u64(std::ostream& out, std::uint64_t value) { out.write(reinterpret_cast<const char*>(&value), sizeof value); }

// Passes what is written on to `target`, adding it to a checksum on the way.
class ChecksumBuffer final : public std::streambuf {
 public:
  explicit ChecksumBuffer(std::streambuf& target) : target_(target) {}
  [[nodiscard]] std::uint64_t value() const { return sum_.value(); }

 protected:
  std::streamsize xsputn(const char* data, std::streamsize size) override {
    const std::streamsize written = target_.sputn(data, size);
    sum_.add({data, static_cast<std::size_t>(std::max<std::streamsize>(written, 0))});
    return written;
  }
  int_type overflow(int_type c) override {
    if (traits_type::eq_int_type(c, traits_type::eof())) return traits_type::not_eof(c);
    const char byte = traits_type::to_char_type(c);
    return xsputn(&byte, 1) == 1 ? c : traits_type::eof();
  }
  int sync() override { return target_.pubsync(); }

 private:
  std::streambuf& target_;
  Checksum sum_;
};

// A section: its length (patched in once written), the bytes `write` writes (none when null),
// their checksum. Streamed: a bed's worth of bytes is not copied.
void write_section(std::ostream& out, const StateWriter& write) {
  const std::streampos at = out.tellp();
  write_u64(out, 0);
  ChecksumBuffer summed(*out.rdbuf());
  std::ostream section(&summed);
  if (write) write(section);
  section.flush();
  if (!section) out.setstate(std::ios::badbit);
  write_u64(out, summed.value());
  const std::streampos end = out.tellp();
  out.seekp(at);
  write_u64(out, static_cast<std::uint64_t>(end - at) - 2 * sizeof(std::uint64_t));
  out.seekp(end);
}

// The run's state from step to step (the scenario and the drop sequence are made again).
template <class Archive>
void archive_run_state(Archive& ar, RunReport& r, RunContext& c) {
  ar(r.particles, r.deposition, raw(r.pours), r.tappings, r.dynamics, r.analyses, r.deposited, r.snapshots, r.snapshot_times, r.frames, r.next_frame_multiple, r.lammps_exchanges, raw(r.supports),
     r.series, r.wall_clock_s, c.simulated_time, c.deposition_stopped_at, r.roddings, r.jiggings);
}
}  // namespace

InputError damaged_checkpoint(const std::filesystem::path& file, std::string_view what) {
  return InputError(fmt::format("{} is damaged; run again without resume ({})", file.string(), what));
}

void encode_checkpoint(std::ostream& out, const Checkpoint& header, const StateWriter& run_state,
                       const StateWriter& step_state) {
  {
    cereal::BinaryOutputArchive ar(out);  // writes through to `out` at once: no buffer to flush
    ar(std::string(kMagic), kFormat);
  }
  write_section(out, [&](std::ostream& section) {
    cereal::BinaryOutputArchive ar(section);
    archive_header(ar, const_cast<Checkpoint&>(header));
  });
  write_section(out, run_state);
  write_section(out, step_state);
}

std::array<std::string_view, 3> checkpoint_sections(std::string_view bytes, const std::filesystem::path& file) {
  // The magic first: any file may be given.
  if (bytes.size() < 8 + kMagic.size() || bytes.substr(8, kMagic.size()) != kMagic)
    throw InputError(fmt::format("{}: not an aggpack checkpoint", file.string()));
  std::string_view rest = bytes.substr(8 + kMagic.size());
  const auto take = [&](auto& value, std::string_view what) {
    if (rest.size() < sizeof value) throw damaged_checkpoint(file, fmt::format("it ends inside its {}", what));
    std::memcpy(&value, rest.data(), sizeof value);
    rest.remove_prefix(sizeof value);
  };
  std::uint32_t format = 0;
  take(format, "format number");
  if (format != kFormat)
    throw InputError(fmt::format("{}: a checkpoint of format {}; this aggpack ({}) reads format {}: run again without "
                                 "resume",
                                 file.string(), format, kVersion, kFormat));
  // Each section's checksum is checked before anything in it is decoded.
  std::array<std::string_view, 3> sections;
  for (std::size_t k = 0; k < sections.size(); ++k) {
    std::uint64_t length = 0, sum = 0;
    take(length, fmt::format("{}'s length", kSections[k]));
    if (length > rest.size())
      throw damaged_checkpoint(file, fmt::format("its {} of {} bytes runs past the end of the file", kSections[k], length));
    sections[k] = rest.substr(0, length);
    rest.remove_prefix(length);
    take(sum, fmt::format("{}'s checksum", kSections[k]));
    if (checksum(sections[k]) != sum)
      throw damaged_checkpoint(file, fmt::format("its {} does not match its checksum", kSections[k]));
  }
  if (!rest.empty()) throw damaged_checkpoint(file, fmt::format("{} bytes after its end", rest.size()));
  return sections;
}

Checkpoint decode_checkpoint(const std::string& bytes, const std::filesystem::path& file) {
  const std::array<std::string_view, 3> sections = checkpoint_sections(bytes, file);
  Checkpoint c;
  try {
    CheckedInputArchive ar(sections[0]);
    archive_header(ar, c);
    if (ar.left() > 0) throw cereal::Exception(fmt::format("{} bytes after the header's fields", ar.left()));
  } catch (const cereal::Exception& e) {
    throw damaged_checkpoint(file, fmt::format("its header: {}", e.what()));
  }
  if (c.version != kVersion)
    throw InputError(fmt::format("{}: written by aggpack {}, this is aggpack {}: a run continues only with the build "
                                 "that began it (its results would not be the same bytes); run the scenario again",
                                 file.string(), c.version, kVersion));
  c.run_state = sections[1];
  c.step_state = sections[2];
  return c;
}

std::string resealed_checkpoint(std::string bytes, std::size_t first) {
  std::size_t at = 8 + kMagic.size() + sizeof(std::uint32_t);
  for (std::size_t k = 0; k < kSections.size(); ++k) {
    std::uint64_t length = 0;
    if (bytes.size() < at + sizeof length) return bytes;
    std::memcpy(&length, bytes.data() + at, sizeof length);
    at += sizeof length;
    if (length > bytes.size() - at || bytes.size() - at - length < sizeof(std::uint64_t)) return bytes;
    const std::uint64_t sum = checksum(std::string_view(bytes).substr(at, length));
    at += length;
    if (k >= first) std::memcpy(bytes.data() + at, &sum, sizeof sum);
    at += sizeof sum;
  }
  return bytes;
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
  // The DEM system the next DEM step continues; inside a step, the step's own state holds it.
  ar(context.in_step ? CarriedDem().save() : context.dem.save());
}

namespace {
bool finite(const Vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// A flag inside a record restored as raw bytes is tested as a byte: any other value than 0
// or 1 in a bool is undefined behaviour.
bool is_flag(const bool& flag) {
  unsigned char byte = 0;
  std::memcpy(&byte, &flag, 1);
  return byte <= 1;
}

template <class E, std::size_t N>
bool is_named(const std::array<EnumName<E>, N>& names, E value) {
  return std::any_of(names.begin(), names.end(), [&](const EnumName<E>& e) { return e.value == value; });
}

// The particles a run adds, in order: the drop sequence (or the particle file's spheres), each
// a sphere of its radius or, with grains, a grain of its shape at that scale (its reach).
struct RunParticles {
  std::span<const double> radii;
  std::span<const RigidBodyShape* const> shapes;  // empty: all spheres; a null entry: a sphere
  SphereMaterials materials;
  [[nodiscard]] const RigidBodyShape* shape(std::size_t k) const { return shapes.empty() ? nullptr : shapes[k]; }
};

// A grain restored as `bodies` entry b from member sphere `first` on: the run's particle k as
// the pour adds it (its members' sizes, masses and places in the body, the union's mass
// properties, its template), its pose and motion finite, its orientation a unit quaternion.
bool is_runs_grain(const ParticleStore& bed, std::size_t b, std::size_t first, const RunParticles& run, std::size_t k) {
  const RigidBodyShape& shape = *run.shape(k);
  const RigidBodies& bodies = bed.bodies;
  const std::size_t members = shape.member_centres.size();
  if (bodies.first_member[b] != first || bodies.member_count[b] != members || members > bed.size() - first)
    return false;
  ParticleStore made;  // the grain as the run adds it, at the origin
  add_poured(made, {}, run.radii[k], &shape, {}, {}, run.materials.density_of(k), 0, run.materials.material(k));
  const Quaternion& q = bodies.orientation[b];
  const double q_norm2 = q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z;
  if (bodies.mass[b] != made.bodies.mass[0] || bodies.volume[b] != made.bodies.volume[0] ||
      !(bodies.principal_inertia[b] == made.bodies.principal_inertia[0]) || bodies.shape[b] != shape.id ||
      !finite(bodies.position[b]) || !finite(bodies.velocity[b]) || !finite(bodies.angular_velocity[b]) ||
      !(std::abs(q_norm2 - 1.0) <= 1e-6))
    return false;
  for (std::size_t m = 0; m < members; ++m) {
    const std::size_t i = first + m;
    if (bed.radius[i] != made.radius[m] || bed.mass[i] != made.mass[m] || bed.material[i] != made.material[m] ||
        bed.body[i] != b || !(bed.body_offset[i] == made.body_offset[m]) || !finite(bed.position[i]) ||
        !finite(bed.velocity[i]) || !finite(bed.angular_velocity[i]))
      return false;
  }
  return true;
}

// A bed of the run state: one value per sphere in every array (and per body in the bodies'),
// and the run's own particles in its order (all of them when `all`, else the first ones), each
// of its mass, at a finite place with a finite motion; a grain as is_runs_grain says.
void check_bed(const ParticleStore& bed, std::string_view what, const RunParticles& run, bool all) {
  const std::size_t n = bed.radius.size();
  const RigidBodies& b = bed.bodies;
  const std::size_t grains = b.mass.size();
  const bool with_bodies = !bed.body.empty() || grains > 0;
  if (bed.position.size() != n || bed.velocity.size() != n || bed.angular_velocity.size() != n ||
      bed.mass.size() != n || bed.layer.size() != n || bed.material.size() != n ||
      (with_bodies && (bed.body.size() != n || bed.body_offset.size() != n || grains == 0)) ||
      b.first_member.size() != grains || b.member_count.size() != grains || b.position.size() != grains ||
      b.orientation.size() != grains || b.velocity.size() != grains || b.angular_velocity.size() != grains ||
      b.volume.size() != grains || b.principal_inertia.size() != grains || b.shape.size() != grains)
    throw DamagedCheckpoint(fmt::format("its {} has arrays of different lengths", what));
  std::size_t sphere = 0, grain = 0, k = 0;  // the store's next sphere and body, the run's next particle
  for (; sphere < n; ++k) {
    if (k >= run.radii.size())
      throw DamagedCheckpoint(fmt::format("its {} holds more particles than the run's {}", what, run.radii.size()));
    if (run.shape(k)) {
      if (grain >= grains || !is_runs_grain(bed, grain, sphere, run, k))
        throw DamagedCheckpoint(fmt::format("its {}: particle {} (a grain) is not one of the run's", what, k));
      sphere += b.member_count[grain++];
      continue;
    }
    if (bed.radius[sphere] != run.radii[k] || bed.material[sphere] != run.materials.material(k) ||
        bed.mass[sphere] != ParticleStore::sphere_mass(run.radii[k], run.materials.density_of(k)) ||
        (with_bodies && bed.body[sphere] != kNoBody) || !finite(bed.position[sphere]) ||
        !finite(bed.velocity[sphere]) || !finite(bed.angular_velocity[sphere]))
      throw DamagedCheckpoint(fmt::format("its {}: particle {} is not one of the run's", what, k));
    ++sphere;
  }
  if (grain != grains) throw DamagedCheckpoint(fmt::format("its {} has grains beyond its spheres", what));
  if (all && k != run.radii.size())
    throw DamagedCheckpoint(fmt::format("its {} holds {} particles; the run has {}", what, k, run.radii.size()));
}

// What the run state holds beyond the beds, against the scenario: the records restored as raw
// bytes hold valid flags and names, and the names of snapshots (file names) and analyses are
// the protocol's.
void check_reports(const RunReport& r, const RunContext& c) {
  const auto fail = [](std::string_view what) { throw DamagedCheckpoint(fmt::format("its run state: {}", what)); };
  if (r.deposition && (!is_named(kDepositionEndNames, r.deposition->stats.end) || r.deposition->layers == 0))
    fail("the deposition's report");
  if (r.dynamics)
    for (const SettlingRun& run : r.dynamics->runs)
      if (!is_named(kSettleEndNames, run.ended_by) || !is_flag(run.time_step_from_scenario) ||
          !is_flag(run.continues_dem_system))
        fail("a settling run's report");
  if (r.supports.size() > r.particles.size()) fail("more supports than particles");
  std::set<std::string> snapshots, analyses;
  for (const Step& step : scenario_protocol(r.scenario).steps) {
    if (const auto* s = std::get_if<SnapshotStep>(&step.kind)) snapshots.insert(s->name);
    if (const auto* a = std::get_if<AnalyseStep>(&step.kind)) analyses.insert(a->report_as);
  }
  for (const auto& [name, bed] : r.snapshots)
    if (!snapshots.contains(name)) fail(fmt::format("a snapshot \"{}\" the protocol does not take", name));
  for (const auto& [name, time] : r.snapshot_times)
    if (!r.snapshots.contains(name) || !std::isfinite(time) || time < 0.0)
      fail(fmt::format("the time of snapshot \"{}\"", name));
  for (const auto& [name, analysis] : r.analyses)
    if (!analyses.contains(name)) fail(fmt::format("an analysis \"{}\" the protocol does not make", name));
  if (!std::isfinite(c.simulated_time) || c.simulated_time < 0.0) fail("its simulated time");
  // The frames written, numbered from 1 in order, at times that do not decrease.
  for (std::size_t f = 0; f < r.frames.size(); ++f)
    if (r.frames[f].file != frame_file_name(f + 1) || !std::isfinite(r.frames[f].time) || r.frames[f].time < 0.0 ||
        (f > 0 && r.frames[f].time < r.frames[f - 1].time))
      fail(fmt::format("frame {}", f + 1));
  if (r.next_frame_multiple > (std::uint64_t{1} << 53) || (r.frames.empty() != (r.next_frame_multiple == 0)))
    fail("the next frame's time");
}
}  // namespace

void decode_run_state(const std::string& state, RunReport& report, RunContext& context) {
  // The spheres the run places: the particle file's (in the store until now), or the drop sequence.
  const bool from_file = report.scenario.particles.file.has_value();
  const std::vector<double> radii = from_file ? report.particles.radius : context.radii;
  std::string carried_dem;
  try {
    CheckedInputArchive ar(state);
    archive_run_state(ar, report, context);
    ar(carried_dem);
    if (ar.left() > 0) throw cereal::Exception(fmt::format("{} bytes after its end", ar.left()));
  } catch (const cereal::Exception& e) {
    throw DamagedCheckpoint(fmt::format("its run state: {}", e.what()));
  }
  // Each sphere of its material: the particle file's all of one, the drop sequence's by component.
  const std::vector<double> densities = material_densities(report.scenario);
  const std::vector<std::uint8_t> file_materials(
      from_file ? radii.size() : 0, report.scenario.particles.material_of_component(0));
  // With grains, each grain's scale is its reach at its sieve size, as the pour takes it.
  const RunGrains::PourPart poured = context.grains.pour_part(radii, 0);
  const RunParticles run{poured.radii, context.grains.empty() ? std::span<const RigidBodyShape* const>() : poured.shapes,
                         SphereMaterials{from_file ? file_materials : context.sphere_materials, densities}};
  check_bed(report.particles, "bed", run, from_file);
  if (report.deposited) check_bed(*report.deposited, "bed after deposition", run, from_file);
  for (const auto& [name, bed] : report.snapshots) check_bed(bed, "snapshot " + name, run, from_file);
  check_reports(report, context);
  const Scenario& sc = report.scenario;
  if (!sc.dynamics && carried_dem != CarriedDem().save())
    throw DamagedCheckpoint("its run state: a DEM system in a run without dynamics");
  if (!sc.dynamics) return;
  try {
    // What a DEM step of this scenario makes for these frozen particles (its time step from the
    // smallest free sphere).
    const auto setup_for = [&](const std::vector<std::uint8_t>& frozen) {
      double r_min = std::numeric_limits<double>::infinity();
      for (std::size_t i = 0; i < report.particles.size(); ++i)
        if (frozen.empty() || frozen[i] == 0) r_min = std::min(r_min, report.particles.radius[i]);
      return dem_setup(sc, r_min, context.threads);
    };
    context.dem.restore(carried_dem, report.particles, sc.container, setup_for);
  } catch (const InputError& e) {
    throw DamagedCheckpoint(fmt::format("its run state: {}", e.what()));
  }
}

std::uint64_t input_fingerprint(const ParticleStore& particles, const std::vector<double>& radii,
                                std::string_view calibrations) {
  std::uint64_t hash = 0xcbf29ce484222325ull;  // FNV-1a over the bytes
  const auto add = [&](const void* data, std::size_t bytes) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < bytes; ++i) hash = (hash ^ p[i]) * 0x100000001b3ull;
  };
  add(particles.position.data(), particles.position.size() * sizeof(Vec3));
  add(particles.radius.data(), particles.radius.size() * sizeof(double));
  add(radii.data(), radii.size() * sizeof(double));
  add(calibrations.data(), calibrations.size());
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
