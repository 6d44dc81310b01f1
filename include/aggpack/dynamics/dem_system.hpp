#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "aggpack/core/container.hpp"
#include "aggpack/core/particle_store.hpp"
#include "aggpack/dynamics/contact_law.hpp"

namespace aggpack {

struct DemSettings {
  Vec3 gravity{0.0, 0.0, -9.81};  // m/s^2
  double time_step = 1e-5;        // s
  double skin = 0.0;              // m; Verlet-list skin, 0: 0.1 of the smallest diameter
  int threads = 0;                // OpenMP threads for this system's loops; 0: OpenMP's default
};

// Contact statistics of the free particles (frozen ones are not counted).
struct ContactStatistics {
  double mean_overlap = 0.0;      // mean overlap / (R_i + R_j) (or / 2 R_i for a wall), particle pairs
  double max_overlap = 0.0;       // largest overlap relative to the same diameter, walls included
  double coordination = 0.0;      // particle-particle contacts per free particle
  std::size_t contacts = 0;       // particle-particle contacts (each pair once per free side)
};

// A discrete element model of the spheres in a store: Hertz contacts with the law of
// `model`, gravity, the container's floor and side walls (or periodic sides), velocity
// Verlet for positions and spins. Frozen particles neither move nor get forces.
//
// Forces are gathered per particle over a full Verlet list sorted by neighbour index, so
// every sum is taken in one fixed order: results are bit-identical whatever the number of
// OpenMP threads. Each contact is evaluated from both sides with mirrored arithmetic, so
// the two forces are exact opposites and the two tangential histories stay opposite.
class DemSystem {
 public:
  // `frozen[i]` = 1: particle i does not move (it still pushes on the others); empty: none.
  DemSystem(ParticleStore& particles, const Container& container, const ContactModel& model,
            const DemSettings& settings, std::vector<std::uint8_t> frozen = {});

  // Advances n steps.
  void run(std::size_t steps);

  [[nodiscard]] double time() const { return time_; }
  [[nodiscard]] std::size_t steps() const { return steps_; }
  [[nodiscard]] std::size_t rebuilds() const { return rebuilds_; }
  [[nodiscard]] double time_step() const { return settings_.time_step; }
  [[nodiscard]] double skin() const { return skin_; }
  [[nodiscard]] const Vec3& gravity() const { return settings_.gravity; }
  // Net force and torque on each particle at the current positions (gravity included).
  [[nodiscard]] const std::vector<Vec3>& force() const { return force_; }
  [[nodiscard]] const std::vector<Vec3>& torque() const { return torque_; }
  // Kinetic energy of the free particles, J, summed in a fixed order.
  struct KineticEnergy {
    double translational = 0.0;
    double rotational = 0.0;
    [[nodiscard]] double total() const { return translational + rotational; }
  };
  [[nodiscard]] KineticEnergy kinetic_energy() const;
  [[nodiscard]] ContactStatistics contact_statistics() const;
  [[nodiscard]] std::size_t free_count() const { return free_count_; }
  [[nodiscard]] bool is_frozen(std::size_t i) const { return frozen_[i] != 0; }
  // Neighbour-list entries, for memory accounting.
  [[nodiscard]] std::size_t list_entries() const { return other_.size(); }
  [[nodiscard]] std::size_t memory_bytes() const;

  // Wraps positions into a periodic container (call before handing the store on).
  void finish();

 private:
  template <class Law>
  void compute_forces(const Law& particle_law, const Law& wall_law);
  void compute_forces();
  void build_neighbour_list();
  [[nodiscard]] bool list_is_stale() const;
  [[nodiscard]] Vec3 separation(const Vec3& from, const Vec3& to) const;
  void kick(double half_step);
  void drift();

  ParticleStore& p_;
  Container container_;
  ContactModel model_;
  DemSettings settings_;
  double skin_ = 0.0;
  double grid_bed_volume_ = 0.0;             // m^3, sizes the grid's sparse levels
  std::uint32_t n_ = 0;
  bool threaded_ = false;  // OpenMP loops for beds large enough to gain from them
  int threads_ = 1;        // threads of those loops (the results do not depend on it)

 public:
  [[nodiscard]] int threads() const { return threads_; }
  std::size_t free_count_ = 0;
  std::vector<std::uint8_t> frozen_;        // 1 per particle that does not move
  std::vector<double> inverse_inertia_;      // 1 / (2/5 m R^2), 0 when frozen
  std::vector<Vec3> force_, torque_;
  std::vector<Vec3> listed_position_;        // positions when the list was built
  // Full Verlet list in CSR form: particle i's entries are [offset_[i], offset_[i + 1]).
  // An entry is a neighbour index, or n_ + wall index for a wall; sorted ascending.
  std::vector<std::uint32_t> offset_, other_;
  std::vector<Vec3> spring_;                 // tangential history per entry
  double time_ = 0.0;
  std::size_t steps_ = 0, rebuilds_ = 0;
};

}  // namespace aggpack
