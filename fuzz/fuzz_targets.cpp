#include "fuzz_targets.hpp"

#include "aggpack/analysis/density.hpp"
#include "aggpack/core/error.hpp"
#include "aggpack/grains/grain_library.hpp"
#include "aggpack/io/material_file.hpp"
#include "aggpack/io/particle_file.hpp"
#include "aggpack/io/shape_option.hpp"
#include "aggpack/io/scenario.hpp"
#include "aggpack/run/calibration_file.hpp"
#include "aggpack/run/checkpoint.hpp"
#include "aggpack/run/generate_sizes.hpp"
#include "aggpack/run/preflight.hpp"
#include "aggpack/run/run.hpp"
#include "aggpack/sizes/grading.hpp"

namespace aggpack::fuzz {

void scenario_reader(std::string_view bytes) {
  try {
    // Relative paths in the scenario resolve beside this (absent) file.
    const Scenario sc = parse_scenario(bytes, "/nonexistent/fuzz/scenario.toml");
    if (!sc.particles.file) check_amount(sc, expected_amount(sc.particles), false);
    // Draw the sizes of small amounts and check them as a run would before its first step.
    if (!sc.particles.file && expected_particle_count(sc.particles) <= 2e4) {
      const GeneratedSizes sizes = generate_sizes(sc.particles, sc.seed);
      std::vector<double> radii;
      for (const double d : sizes.diameters) radii.push_back(0.5 * d);
      check_sizes(sc, radii);
    }
    (void)to_json(sc);
  } catch (const InputError&) {
  }
}

void grading_reader(std::string_view bytes) {
  try {
    const Grading g = parse_grading_csv(bytes, "fuzz.csv");
    (void)fineness_modulus(g);
    (void)percent_passing_at(g, 1e-3);
    (void)opening_at_percent(g, 50.0);
  } catch (const InputError&) {
  }
}

void particle_file_reader(std::string_view bytes) {
  try {
    const ParticleStore particles = parse_particle_text(bytes, "fuzz.csv", 1.0, 2650.0);
    const Container container = bounding_container(particles);
    (void)check_particle_overlaps(particles, container, 0.25, false, "fuzz.csv", RunLimits{}.max_grid_cells);
  } catch (const InputError&) {
  }
}

void calibration_reader(std::string_view bytes) {
  try {
    const ModelParameters p = parse_calibration(bytes, "fuzz.json");
    // CPM with the file's K and beta, on a binary mix, as predict and a run's predictions use them.
    const ModelDistribution mix{{{0.02, 0.02, 0.02, 0.6}, {0.005, 0.005, 0.005, 0.4}}, "fuzz"};
    (void)cpm(mix, std::vector<double>{p.beta}, p.compaction_index);
  } catch (const InputError&) {
  }
}

void checkpoint_reader(std::string_view bytes) {
  // What `aggpack resume` does, but that a stop is requested from the start: the run restores
  // the checkpoint, continues to its first safe point and stops there.
  const auto resume = [](const std::string& file) {
    try {
      const Checkpoint checkpoint = decode_checkpoint(file, "/nonexistent/fuzz/checkpoint.bin");
      const Scenario sc =
          parse_scenario(checkpoint.scenario_text, resumed_scenario_path(checkpoint), checkpoint.overrides);
      StopRequest stop;
      stop.request(2);
      RunControls controls;
      controls.threads = 1;
      controls.stop_after = checkpoint.stop_after;
      controls.stop = &stop;
      controls.resume_from = &checkpoint;
      controls.final_analysis = false;
      Progress progress;
      (void)run(sc, controls, progress);
    } catch (const InputError&) {
    }
  };
  // The bytes as they are (the checksums see any change), then with the checksums of their
  // run and step states made to match them: what the checks of the decoded values must catch.
  // The header (the scenario's text) stays sealed: the scenario reader has its own target.
  const std::string as_given(bytes), resealed = resealed_checkpoint(as_given, 1);
  resume(as_given);
  if (resealed != as_given) resume(resealed);
}

void material_reader(std::string_view bytes) {
  // The bytes as a scenario's material tables ([material], [[materials]], a component's
  // material), after a bed that uses them, read and checked as scenario_reader does.
  scenario_reader("[container]\nside = 0.05\nheight = 0.1\n[particles]\ndiameter = 0.01\ncount = 20\n[deposition]\n"
                  "[dynamics]\nmax_time = 0.01\n[analysis]\nbox_sides = [0.01]\n" +
                  std::string(bytes));
}

void shape_reader(std::string_view bytes) {
  // The bytes as a component's shape table (what `aggpack grading --shape` reads), and the
  // templates it makes when they are few.
  try {
    const GrainShapeSpec spec = read_shape_option(bytes, "--shape");
    const GrainShapeSpec* specs[] = {&spec};
    check_library_cost(specs, 0.05, "--shape", "limit");
    const std::vector<double> widths{0.006, 0.01, 0.014, 0.02};
    (void)make_grain_library(spec, widths, 1);
  } catch (const InputError&) {
  }
}

void material_file_reader(std::string_view bytes) {
  // The bytes as a material file (`aggpack material`): read, checked, and shown both ways.
  try {
    const AggregateMaterial m = parse_material_file(bytes, "/nonexistent/fuzz/material.toml");
    (void)to_json(m).dump();
    (void)describe(m);
  } catch (const InputError&) {
  }
}

}  // namespace aggpack::fuzz
