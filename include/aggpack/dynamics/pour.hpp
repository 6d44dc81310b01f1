#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <string_view>
#include <vector>

#include "aggpack/core/rng.hpp"
#include "aggpack/deposition/gas_insertion.hpp"
#include "aggpack/dynamics/dem_system.hpp"
#include "aggpack/dynamics/settle.hpp"

namespace aggpack {

// A pour (README, "Pouring"): the spheres come in batches, each a random gas in a slab above
// the bed's top, the next once the last has had the time to fall through its slab's height
// (as LAMMPS's fix pour times its insertions), then the whole bed falls until quiet.

// The batches of a pour, shared by aggpack's pour and the LAMMPS deck of a pour, so that the
// two cannot drift apart: equal parts of the drop sequence by count, in its order.
struct PourSchedule {
  std::size_t count = 0;    // spheres poured
  std::size_t batches = 0;  // at most the settings' batches, at least 1
  // Batch k's radii: [count k / batches, count (k + 1) / batches) of the pour's radii.
  [[nodiscard]] std::span<const double> batch(std::span<const double> radii, std::size_t k) const {
    const std::size_t begin = count * k / batches, end = count * (k + 1) / batches;
    return radii.subspan(begin, end - begin);
  }
};
PourSchedule pour_schedule(const PourSettings& settings, std::size_t count);

// The spheres' solid volume, m^3 (what a batch's slab is sized for).
double solid_volume(std::span<const double> radii);

// Seconds for a batch that enters at `velocity` (downward, m/s) to fall through a slab
// `height` tall under gravity g (0 without gravity: the next batch comes at once).
double batch_fall_time(double velocity, double g, double height);

// The downward speed (m/s) a poured particle comes in with at `height` above the floor:
// `velocity`, or with a release height H, the speed of a fall from H leaving it at `velocity`,
// sqrt(velocity^2 + 2 g max(0, H - height)).
double poured_speed(const PourSettings& settings, double g, double height);

// A batch's random gas (random_gas) in a slab of the container's footprint whose bottom is at
// `bottom`, drawn from the pour's stream. Throws PourInsertionError when the batch finds no room.
struct BatchGas {
  InsertionRegion slab;
  std::vector<Vec3> positions;  // in the batch's order
};
class PourInsertionError : public InputError {
 public:
  using InputError::InputError;
};
BatchGas batch_gas(const Container& container, double bottom, std::span<const double> batch, double solid_fraction,
                   Rng& rng);

// What a pour did.
struct PourReport {
  std::size_t poured = 0;
  std::size_t batches = 0;
  double solid_fraction = 0.0;          // of each insertion slab
  double velocity = 0.0;                // m/s downward at insertion
  double gap = 0.0;                     // m, from the bed's top to a slab's bottom
  std::optional<double> release_height;                     // m above the floor (PourSettings)
  double lowest_slab_bottom = 0.0, highest_slab_top = 0.0;  // m, over the batches
  double insertion_wall_clock_s = 0.0;  // placing the gas (the DEM is in the settling run)
};

// A pour's loop between samples (with the system's state, all it takes to continue it): the
// batch falling or, once all are in, the settling.
struct PourLoop {
  double start = 0.0;                // s, the system's time when the pour began
  std::size_t start_steps = 0;       // the system's steps then
  std::size_t batch = 0;             // the batch in flight
  double next = 0.0;                 // s since the pour began, when the next batch comes
  Rng rng{0, 0};
  PourReport report;
  double weight = 0.0;               // weight_energy of the bed so far
  bool settling = false;             // all batches in: the bed falls until quiet
  SettleLoop settle;
  double poured_at = 0.0;            // s since the pour began, when the last batch came
  std::size_t pour_steps = 0;        // steps until then
  std::size_t block_steps_left = 0;  // of the sample interval in progress (0: at a sample)
};

// What a pour of `radii` with `settings` will be (the gap defaults to the largest diameter
// poured), before its slabs are known.
PourReport planned_pour(const PourSettings& settings, std::span<const double> radii);
// The loop of a pour of `radii` that has not begun, on `system` as it stands: its report
// planned_pour's, its stream `rng`.
PourLoop begin_pour(const DemSystem& system, const PourSettings& settings, std::span<const double> radii, Rng rng);
// Whether a loop restored from a checkpoint is one of this pour's, on this system.
bool fits(const PourLoop& loop, const PourReport& planned, const DemSystem& system);

// What a pour puts in for each of its radii: a sphere, or a rigid grain (a body of several
// spheres) of a shape of reach 1 (ParticleStore::add_body; its farthest point from its centre
// of mass at 1), scaled to the radius and turned at random. The gas is the grains' bounding
// spheres', so that no two grains touch where they come in.
struct PouredShapes {
  std::span<const RigidBodyShape* const> of;  // per radius of the pour, nullptr for a sphere; empty: all spheres
  [[nodiscard]] const RigidBodyShape* shape(std::size_t k) const { return of.empty() ? nullptr : of[k]; }
};

// Adds one poured particle to `store` at `at`, moving at `velocity`: a sphere of `radius`, or
// with a `shape` (of reach 1) a grain of it at reach `radius`, turned by `orientation`. The one
// way a pour, its LAMMPS deck, the bed LAMMPS returns and a checkpoint's check add them.
void add_poured(ParticleStore& store, const Vec3& at, double radius, const RigidBodyShape* shape,
                const Quaternion& orientation, const Vec3& velocity, double density, std::uint32_t layer,
                std::uint8_t material);

// What a pour tells its caller: every sample (its time since the pour began; `phase` says what
// the DEM is doing), and its safe points, where the caller may save the loop with the system
// or stop the run by throwing. The density probe measures the bed once all batches are in.
struct PourHooks {
  std::function<void(const SettleSample& sample, std::string_view phase)> on_sample;
  std::function<void(std::string_view phase)> at_safe_point;
  DensityProbe density;
};

// Pours `radii` onto the bed of `system` in `container` at rest (the spheres join `particles` as free particles of
// layer `part`, of `materials`, one per radius, or the grains of `shapes`), then settles the bed until `quiet` holds or its
// max_time (counted from the pour's start) is reached. `loop` is begin_pour's or a restored
// one (`resumed`): the pour continues where it stood, bit for bit. The result's times are
// since the pour began, its steps the whole pour's; `loop.next` tells whether the last batch
// had the time to fall its slab before max_time (the caller decides what a cut pour means).
SettleResult pour(DemSystem& system, ParticleStore& particles, const Container& container, std::span<const double> radii,
                  const PourSettings& settings, std::uint32_t part, const SphereMaterials& materials,
                  const PouredShapes& shapes, const QuietCriterion& quiet, PourLoop& loop, bool resumed,
                  const PourHooks& hooks);

}  // namespace aggpack
