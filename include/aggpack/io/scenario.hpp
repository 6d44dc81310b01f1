#pragma once
#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "aggpack/core/container.hpp"
#include "aggpack/deposition/drop_and_roll.hpp"
#include "aggpack/deposition/gas_insertion.hpp"
#include "aggpack/dynamics/contact_law_registry.hpp"
#include "aggpack/dynamics/dem_system.hpp"
#include "aggpack/dynamics/materials.hpp"
#include "aggpack/dynamics/settle.hpp"
#include "aggpack/dynamics/jig.hpp"
#include "aggpack/dynamics/rod.hpp"
#include "aggpack/dynamics/tap.hpp"
#include "aggpack/io/dem_calibration_file.hpp"
#include "aggpack/grains/grain_library.hpp"
#include "aggpack/io/protocol.hpp"
#include "aggpack/io/vtk.hpp"
#include "aggpack/sizes/grading_sampler.hpp"
#include "aggpack/sizes/size_spec.hpp"

namespace aggpack {

// One aggregate grading in a scenario, with its cut-offs.
struct GradingSource {
  std::string key;                 // where it was given: "particles.grading", "particles.coarse", ...
  Grading grading;
  std::optional<double> d_min, d_max;  // m
  std::optional<Band> band;        // a band to check it against, reported
};

// Sizes sampled from a sieve grading, or from a coarse/fine mix at a volume ratio.
struct GradedParticles {
  GradingSource main;                  // the grading, or the coarse aggregate of a mix
  std::optional<GradingSource> fine;   // set for a mix
  double ca_fa = 0.0;                  // coarse/fine volume ratio of a mix
  SamplingMode sampling = SamplingMode::Mass;
  MixOrder order = MixOrder::Interleaved;
  Amount amount;                       // a count or a solid volume
  std::optional<double> fill_height;   // m: set when the solid volume was derived from it
  double expected_density = 0.6;       // used with fill_height
};

// Where particle positions come from: generated sizes (placed by a stage) or a file.
// particles.from's value for a bed that the library's caller gives the run (Python's
// aggpack.run(scenario, bed=...), RunControls::starting_bed) instead of a file.
inline constexpr const char* kBedFromCaller = "-";

struct ParticleSource {
  std::optional<SizeSpec> sizes;           // set when the scenario generates particles by class
  std::optional<GradedParticles> graded;   // set when it samples them from gradings
  std::optional<std::filesystem::path> file;  // set when positions are read from a file (or given: bed_from_caller)
  double file_length_unit = 1.0;           // metres per file unit
  std::optional<std::int64_t> file_timestep;  // a LAMMPS dump's snapshot to read; none: the last
  // Largest overlap of the floor or a wall accepted from a file, as a fraction of the
  // radius: a settled bed's Hertz contacts (1e-4 r at rock stiffness, 1e-2 r at E/100).
  double boundary_overlap_tolerance = 0.02;
  // Deepest overlap of two spheres from a file, as a fraction of the smaller radius; beyond
  // it the file is refused unless it comes from a soft-contact DEM (soft_contacts).
  double overlap_tolerance = 0.25;
  bool soft_contacts = false;
  // The material of each component (a size class, as listed; a mix's coarse, then fine; one
  // grading), as an index of the run's materials (material_count). Empty: all [material].
  std::vector<std::uint8_t> component_material;
  // The grains of each component (indexed as component_material), or none for spheres; empty:
  // spheres throughout.
  std::vector<std::optional<GrainShapeSpec>> component_shape;
  [[nodiscard]] bool has_grains() const {
    for (const auto& shape : component_shape)
      if (shape) return true;
    return false;
  }
  // particles.from = "-": the positions are a bed the caller gives the run, not a file's.
  [[nodiscard]] bool bed_from_caller() const { return file && file->native() == kBedFromCaller; }
  // Component c's material (a particle file is one component: 0).
  [[nodiscard]] std::uint8_t material_of_component(std::size_t c) const {
    return component_material.empty() ? 0 : component_material.at(c);
  }
};

// [material]: the spheres' density and the contact law's parameters (dynamics.friction_model
// chooses the law); the contact law's own struct, so each default is written once.
struct Material {
  double density = 2650.0;  // kg/m^3
  ContactParameters contact;
  std::filesystem::path file;  // the material file it was read from (`file = ...`), or empty
};

// [materials.NAME]: a material of its own for the components that name it (`material =
// "NAME"`): any key of [material] but the walls' and the law's, the rest from [material].
struct NamedMaterial {
  std::string name;
  Material material;
};

struct AnalysisSettings {
  std::vector<double> box_sides;    // virtual cube sides, m; empty: one cube, the largest admissible
  double contact_tolerance = 1e-6;  // relative gap that still counts as a contact
  std::optional<double> slice_thickness;  // m; default d_max / 4
  std::optional<double> shell_thickness;  // m; default d_max / 4
};

// The DEM settling stage ([dynamics]); see docs/method.md section 5. The DEM's, the time
// step's and the quiet criterion's own settings, and the layers of the default protocol.
// Which code runs a settle step: aggpack's own DEM, or LAMMPS as a child process (the step
// exported, run with `lmp`, under `mpirun -np N` for N ranks, and imported back).
enum class DemEngine { Aggpack, Lammps };
inline constexpr std::array kDemEngineNames{EnumName<DemEngine>{DemEngine::Aggpack, "aggpack"},
                                            EnumName<DemEngine>{DemEngine::Lammps, "lammps"}};

struct DynamicsStage {
  DemEngine engine = DemEngine::Aggpack;
  int lammps_ranks = 1;               // MPI ranks of LAMMPS (1: no mpirun)
  std::string lammps_binary = "lmp";  // found on PATH
  DemSettings dem;              // gravity, skin (0: 0.1 d_min); the time step comes from the rule
  TimeStepRule time_step;
  QuietCriterion quiet;
  std::size_t layers = 1;       // > 1: deposit and settle layer by layer (the paper's method)
  bool allow_unstable_time_step = false;  // run a step above TimeStepRule::kStableFraction (noted)
};

// [limits]: the bounds that keep any input from exhausting the machine (README, "Limits").
// Each is checked before any work; a run that needs more is refused with the key to raise.
struct RunLimits {
  double max_particles = 1e8;        // particles a run may generate or read
  std::optional<double> max_memory_gib;  // none: 80 % of the machine's physical memory
  double max_grid_cells = 67108864;  // 2^26 cells of the neighbour grid (256 MiB); at most 2^31
  double max_input_file_gib = 2.0;   // largest particle file read
  [[nodiscard]] std::uintmax_t max_input_bytes() const {
    return static_cast<std::uintmax_t>(max_input_file_gib * double(1u << 30));
  }
  double max_profile_bins = 1e6;     // slices and shells of the profiles
  double max_template_minutes = 10;  // the grains' templates, by estimate (estimated_library_seconds)
};

// The memory limit in bytes: max_memory_gib, or 80 % of the machine's physical memory.
[[nodiscard]] double memory_limit_bytes(const RunLimits& limits);

struct OutputSettings {
  std::filesystem::path directory;
  bool csv = true;
  bool vtp = true;
  // particles.vtp's arrays: zlib-compressed binary (the default), or ASCII text.
  VtpEncoding vtp_encoding = VtpEncoding::ZlibAppended;
  // Checkpoints of a run into `directory` (checkpoint.bin), at most every `checkpoint_every`
  // seconds of wall clock (0: at every safe point), for `aggpack resume`.
  bool checkpoint = true;
  double checkpoint_every = 60.0;
  // Frames of the DEM for an animation (frames/frame_00001.vtp, ... in particles.pvd): at the
  // first sample, then at the first sample at or after each multiple of this simulated time, s;
  // none when unset.
  std::optional<double> frame_interval;
};

struct Scenario {
  std::filesystem::path file;
  std::vector<std::string> overrides;  // the --set key=value assignments it was read with, in order
  std::optional<std::filesystem::path> models_calibration;  // [models] calibration: K and beta for the predictions
  std::vector<DemCalibrationFile> calibrations;  // calibrated_by: DEM calibrations whose values replaced the file's
  std::string title;
  std::uint64_t seed = 1;
  Container container;
  // The unit container.side is written in ("in", "mm"): the console gives lengths in it beside
  // SI. Empty: metres, or a bare number.
  std::string written_length_unit;
  ParticleSource particles;
  Material material;                       // [material]: material 0, "default"
  std::vector<NamedMaterial> materials;    // [materials.NAME], alphabetically: materials 1, 2, ...
  std::vector<MaterialPairCoefficients> material_pairs;  // [[material_pairs]]
  std::optional<DepositionSettings> deposition;  // [deposition]; fill_height resolved (default: the container)
  std::optional<PourSettings> pour;              // [pour]
  std::optional<TappingSettings> tapping;        // [tapping] (dynamics/tap.hpp)
  std::optional<RoddingSettings> rodding;        // [rodding] (dynamics/rod.hpp)
  std::optional<JiggingSettings> jigging;        // [jigging] (dynamics/jig.hpp)
  std::optional<DynamicsStage> dynamics;
  AnalysisSettings analysis;
  RunLimits limits;
  OutputSettings output;
  std::optional<Protocol> protocol;  // [[protocol]] as given; none: the stages' default order
};

// The run's materials: 0 is [material] ("default"), then [materials.NAME] in order.
[[nodiscard]] inline std::size_t material_count(const Scenario& sc) { return 1 + sc.materials.size(); }
[[nodiscard]] const Material& material_of(const Scenario& sc, std::size_t index);
[[nodiscard]] std::string material_name(const Scenario& sc, std::size_t index);
[[nodiscard]] std::vector<double> material_densities(const Scenario& sc);
// The materials some component is made of, in index order ([material] alone when none names one).
[[nodiscard]] std::vector<std::size_t> used_materials(const Scenario& sc);
// Gives the spheres of a particle file (read at the density of [material] or of `particles.material`)
// their materials: `names`, a "material" column (one per sphere; empty: none), by the
// scenario's names, each sphere's mass from its material. InputError naming `file`, the row and
// the name when a name is not one of the scenario's.
void assign_file_materials(ParticleStore& particles, const std::vector<std::string>& names, const Scenario& sc,
                           const std::string& file);
// Every material's contact parameters, in index order (make_contact_model's input).
[[nodiscard]] std::vector<ContactParameters> material_contacts(const Scenario& sc);

struct ScenarioOverrides {
  std::vector<std::string> set;  // "key.path=value", TOML syntax for the value (bare words are strings)
  // The option the user typed for an assignment of `set` that aggpack made from it (a cut-off
  // of --cut-offs: "--cut-offs 0.07in"), quoted in messages instead of "--set key=value".
  // For messages only: a checkpoint does not keep it.
  std::map<std::string, std::string> typed_as;  // assignment -> option as typed
  std::optional<std::uint64_t> seed;
  std::optional<std::filesystem::path> output_directory;
};

// A scenario file's text: refused when it is not a regular file, or is over 16 MiB.
std::string read_scenario_text(const std::filesystem::path& file);
// Reads and validates a scenario. Throws InputError naming the file, line and key.
// A file that is not a regular file, or is over 16 MiB, is refused before it is read.
Scenario load_scenario(const std::filesystem::path& file, const ScenarioOverrides& overrides = {});
// The same on text in memory; `file` names it in messages and anchors its relative paths.
Scenario parse_scenario(std::string_view text, const std::filesystem::path& file,
                        const ScenarioOverrides& overrides = {});

// The scenario's keys as its file gives them, --set assignments, --seed and --out applied (not
// its calibration files' assignments: calibrated_by stays a key): what parse_scenario reads, as
// JSON values. Read again (written as TOML, anchored at `file`), it is the same scenario.
nlohmann::json scenario_keys(std::string_view text, const std::filesystem::path& file,
                             const ScenarioOverrides& overrides = {});

// The scenario with every value resolved, in SI units, as written to summary.json (with
// "protocol" when the scenario gives one).
nlohmann::json to_json(const Scenario& scenario);
nlohmann::json to_json(const Protocol& protocol);

}  // namespace aggpack
