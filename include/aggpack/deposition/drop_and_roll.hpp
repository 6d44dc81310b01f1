#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <span>
#include <vector>

#include "aggpack/core/enum_names.hpp"
#include "aggpack/core/container.hpp"
#include "aggpack/core/particle_store.hpp"
#include "aggpack/core/rng.hpp"
#include "aggpack/deposition/contact_geometry.hpp"
#include "aggpack/spatial/multilevel_grid.hpp"

namespace aggpack {

struct DepositionSettings {
  double tolerance = 1e-9;         // contact tolerance, relative to the dropped sphere's diameter
  std::size_t max_events = 1000;   // events before a sphere is given up and redropped elsewhere
  std::size_t max_redrops = 100;   // redrops of one sphere before the stage ends
  double fill_height = std::numeric_limits<double>::infinity();  // above the floor, m
  bool record_paths = false;       // keep every event position in DropResult::path (for tests and tracing)
};

enum class DepositionEnd {
  AllPlaced,     // every sphere asked for is in the bed
  FillHeight,    // a sphere would have rested with its top above the fill height
  Unplaceable,   // a sphere found no rest in max_redrops drops
};
inline constexpr std::array kDepositionEndNames{EnumName<DepositionEnd>{DepositionEnd::AllPlaced, "all_placed"},
                                                EnumName<DepositionEnd>{DepositionEnd::FillHeight, "fill_height"},
                                                EnumName<DepositionEnd>{DepositionEnd::Unplaceable, "unplaceable"}};

struct DepositionStats {
  std::size_t requested = 0;
  std::size_t placed = 0;
  std::size_t events = 0;           // falls, contacts and roll-offs of the placed spheres
  std::size_t max_events_one_sphere = 0;
  std::size_t redrops = 0;          // drops abandoned after max_events (or a stuck sequence)
  std::size_t ties_on_top = 0;      // landed exactly on top of one sphere: rolled off at random
  std::size_t ties_on_ridge = 0;    // balanced on top of a two-support circle: rolled off at random
  std::size_t resting_on_floor = 0;
  std::size_t resting_on_three = 0;  // three supports (spheres or walls)
  std::size_t touching_a_wall = 0;   // resting with a wall among its supports
  DepositionEnd end = DepositionEnd::AllPlaced;
};

// Where a single drop ended.
struct DropResult {
  bool rested = false;       // false: max_events reached without rest
  Vec3 position;
  Supports supports;
  std::size_t events = 0;
  int ties_on_top = 0, ties_on_ridge = 0;
  std::vector<Vec3> path;    // the centre after the first fall and after each event (record_paths)
};

// Who watches a deposit: `on_placed(placed so far in this call)` after every `every`
// spheres placed (for a progress line; it sees nothing it could change).
struct DepositionObserver {
  std::size_t every = 1000;
  std::function<void(std::size_t placed)> on_placed;
};

// The kinematic drop-and-roll deposition of docs/method.md section 3: each sphere falls
// from above the bed, then rolls on one support (a great circle) or two (their circle),
// event by event in closed form, until the upward vertical lies in the cone of its contact
// normals. No time stepping. Works on top of an existing bed, so deposition can stop after
// some particles and resume later (the layer-by-layer method).
class DropAndRoll {
 public:
  // `bed` may already hold spheres (they become obstacles); `radii_to_come` are all radii
  // that will be deposited (they size the grid levels).
  DropAndRoll(ParticleStore& bed, const Container& container, std::span<const double> radii_to_come,
              const DepositionSettings& settings, Rng rng);

  // Drops spheres of the given radii (of `materials`, one per radius) one by one at uniformly
  // random (x, y) and adds each to the bed where it comes to rest. Stops early at the fill
  // height; returns how many it placed.
  std::size_t deposit(std::span<const double> radii, const SphereMaterials& materials, std::uint32_t layer = 0,
                      const DepositionObserver& observer = {});

  // One drop of a sphere of radius r at (x, y), without adding it to the bed.
  DropResult drop(double x, double y, double r);

  [[nodiscard]] const DepositionStats& stats() const { return stats_; }
  // Supports of every sphere in the bed, by particle index (none for spheres not placed here).
  [[nodiscard]] const std::vector<Supports>& supports() const { return supports_; }

 private:
  void collect_contacts(const Vec3& p, double r, double tol);
  bool fall(Vec3& p, double r, double skip);
  ArcAngle first_event_on_arc(const Arc& arc, double r, double skip);
  [[nodiscard]] Obstacle sphere_obstacle(std::uint32_t k, const Vec3& p, double r) const;
  // The container's planes (the floor, and the four walls unless the sides are periodic) as
  // obstacles for a sphere of radius r: its centre stays r inside each.
  template <class Visit>
  void for_each_wall_and_floor(double r, Visit&& visit) const {
    static constexpr std::array<std::uint32_t, 5> kIds{kFloor, kWallXLow, kWallXHigh, kWallYLow, kWallYHigh};
    for (unsigned w = 0; w < container_.plane_count(); ++w) {
      const Container::PlaneEquation p = container_.plane(w);
      visit(Obstacle{kIds[w], true, p.inward, p.offset + r});
    }
  }

  ParticleStore& bed_;
  Container container_;
  DepositionSettings settings_;
  Rng rng_;
  MultilevelGrid grid_;
  DepositionStats stats_;
  std::vector<Supports> supports_;
  std::vector<Obstacle> contacts_;  // scratch: objects touching the dropped sphere
  std::vector<Obstacle> near_;      // scratch: spheres near the last path step
  std::vector<Vec3> normals_;       // scratch: contact normals
};

[[nodiscard]] std::string_view to_string(DepositionEnd end);

// The random stream of the drops of layer `layer` (0 for a single pass): each layer has its
// own, so a layer's drops do not depend on how the others went.
[[nodiscard]] Rng deposition_stream(std::uint64_t seed, std::uint32_t layer);

}  // namespace aggpack
