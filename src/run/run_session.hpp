#pragma once
// One run of a scenario's protocol, as run() makes it (private to the run engine).

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

#include "aggpack/analysis/coordination.hpp"
#include "aggpack/core/error.hpp"
#include "aggpack/io/particle_file.hpp"
#include "aggpack/run/checkpoint.hpp"
#include "aggpack/run/generate_sizes.hpp"
#include "aggpack/run/run.hpp"
#include "aggpack/run/steps.hpp"

namespace aggpack {

// What a run starts from, every check before work passed: particles read from a file (with
// their largest overlaps of the container and of each other), or the generated sizes of an
// empty bed for the deposition and pour stages to fill.
struct InitialBed {
  ParticleStore particles;
  double largest_boundary_overlap = 0.0;
  PairOverlap largest_pair_overlap;
  std::string file_format;  // of a particle file: "CSV", "LAMMPS dump, timestep 1000", ...
  std::optional<GeneratedSizes> sizes;
};
// `starting_bed`: the caller's bed for particles.from = "-" (RunControls::starting_bed).
InitialBed initial_bed(const Scenario& sc, const ParticleStore* starting_bed = nullptr);

// The run's grains (none without a component's shape), checked before any work as the spheres
// were in initial_bed: the protocol can take them (no deposit, no frozen grain, one batch to
// LAMMPS), the sizes with each grain as the sphere that holds it, and the protocol's beds with
// each grain's spheres. What `run` and `check` both do.
RunGrains checked_grains(const Scenario& sc, const Protocol& protocol, const InitialBed& bed,
                         const LibraryWatch& watch = {});

// The final analysis refused a bed that a DEM made (a virtual cube that does not fit it, which
// is known only once the bed is made): the refusal, with the bed, for a run into a folder to keep.
class BedNotAnalysed : public InputError {
 public:
  BedNotAnalysed(const std::string& why, ParticleStore bed, double simulated_time)
      : InputError(why), bed_(std::move(bed)), simulated_time_(simulated_time) {}
  [[nodiscard]] const ParticleStore& bed() const { return bed_; }
  [[nodiscard]] double simulated_time() const { return simulated_time_; }

 private:
  ParticleStore bed_;
  double simulated_time_;
};

// A run in progress: its report (the bed in it), what its steps share (RunContext: the drop
// sequence, the time so far, the DEM system they continue), its checkpointer and its frames.
// Made, it has passed every check that can be made before work and stands before its first
// step, or where its checkpoint was taken; run_steps() runs the protocol from there, finish()
// analyses the bed.
class RunSession {
 public:
  RunSession(const Scenario& scenario, const RunControls& controls, Progress& progress);
  RunSession(const RunSession&) = delete;
  RunSession& operator=(const RunSession&) = delete;
  // The protocol's steps, each at a safe point first; a stop request ends them with
  // RunReport::interrupted set.
  void run_steps();
  // The final analysis (none for an interrupted run or when the controls ask for none).
  RunReport finish();

 private:
  [[nodiscard]] std::size_t restore(const Checkpoint& checkpoint);
  void take_frames(double time, const ParticleStore& bed);

  const Scenario& scenario_;
  const RunControls& controls_;
  Progress& progress_;
  Protocol protocol_;
  RunReport report_;
  RunContext context_;
  SampleObserver frame_taker_;
  std::optional<Checkpointer> checkpointer_;
  std::size_t completed_ = 0;  // steps done
};

}  // namespace aggpack
