#pragma once
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "aggpack/core/container.hpp"
#include "aggpack/io/protocol.hpp"
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
struct ParticleSource {
  std::optional<SizeSpec> sizes;           // set when the scenario generates particles by class
  std::optional<GradedParticles> graded;   // set when it samples them from gradings
  std::optional<std::filesystem::path> file;  // set when positions are read from a file
  double file_length_unit = 1.0;           // metres per file unit
  // Largest overlap of the floor or a wall accepted from a file, as a fraction of the
  // radius: a settled bed's Hertz contacts (1e-4 r at rock stiffness, 1e-2 r at E/100).
  double boundary_overlap_tolerance = 0.02;
};

struct Material {
  double density = 2650.0;          // kg/m^3
  double youngs_modulus = 50e9;     // Pa
  double poisson_ratio = 0.25;
  double wall_youngs_modulus = 200e9;  // Pa, walls and floor (steel)
  double wall_poisson_ratio = 0.3;
  double friction_particle = 0.17;  // particle-particle Coulomb coefficient
  double friction_wall = 0.17;      // particle-wall and particle-floor
  double restitution = 0.5;
  double rolling_friction = 0.0;    // rolling resistance mu_r, 0 for none
};

struct AnalysisSettings {
  std::vector<double> box_sides;    // virtual cube sides, m; empty: one cube, the largest admissible
  double contact_tolerance = 1e-6;  // relative gap that still counts as a contact
  std::optional<double> slice_thickness;  // m; default d_max / 4
  std::optional<double> shell_thickness;  // m; default d_max / 4
};

// The kinematic drop-and-roll stage ([deposition]); see docs/method.md section 3.
struct DepositionStage {
  double tolerance = 1e-9;        // contact tolerance relative to the dropped sphere's diameter
  std::size_t max_events = 1000;  // events before a sphere is redropped elsewhere
  std::size_t max_redrops = 100;  // redrops of one sphere before the stage gives up
  std::optional<double> fill_height;  // m above the floor; default: the container height
};

// The DEM settling stage ([dynamics]); see docs/method.md section 5.
struct DynamicsStage {
  std::string friction_model = "mindlin";  // "mindlin" or "fu2003"
  std::optional<double> time_step;         // s; default: time_step_safety x Rayleigh time of the smallest sphere
  double time_step_safety = 0.2;
  double max_time = 2.0;                   // s of simulated time per settling run
  double sample_interval = 1e-3;           // s between time-series samples
  double quiet_window = 0.05;              // s
  double quiet_kinetic_fraction = 1e-5;    // translational kinetic energy per particle / mean (m g d)
  double density_tolerance = 5e-4;         // change of the virtual-box density over the window
  std::size_t layers = 1;                  // > 1: deposit and settle layer by layer (the paper's method)
  std::optional<double> skin;              // m; Verlet skin, default 0.1 d_min
  double gravity = 9.81;                   // m/s^2
};

struct OutputSettings {
  std::filesystem::path directory;
  bool csv = true;
  bool vtp = true;
};

struct Scenario {
  std::filesystem::path file;
  std::string title;
  std::uint64_t seed = 1;
  Container container;
  ParticleSource particles;
  Material material;
  std::optional<DepositionStage> deposition;
  std::optional<DynamicsStage> dynamics;
  AnalysisSettings analysis;
  OutputSettings output;
  std::optional<Protocol> protocol;  // [[protocol]] as given; none: the stages' default order
};

struct ScenarioOverrides {
  std::vector<std::string> set;  // "key.path=value", TOML syntax for the value (bare words are strings)
  std::optional<std::uint64_t> seed;
  std::optional<std::filesystem::path> output_directory;
};

// Reads and validates a scenario. Throws InputError naming the file, line and key.
Scenario load_scenario(const std::filesystem::path& file, const ScenarioOverrides& overrides = {});

// The scenario with every value resolved, in SI units, as written to summary.json (with
// "protocol" when the scenario gives one).
nlohmann::json to_json(const Scenario& scenario);
nlohmann::json to_json(const Protocol& protocol);

}  // namespace aggpack
