#pragma once
#include <stdexcept>
#include <cstddef>
#include <cstdint>
#include <istream>
#include <optional>
#include <ostream>
#include <string_view>
#include <vector>

#include "aggpack/core/error.hpp"
#include "aggpack/core/container.hpp"
#include "aggpack/core/particle_store.hpp"
#include "aggpack/core/quaternion.hpp"
#include "aggpack/dynamics/contact_batch.hpp"
#include "aggpack/dynamics/contact_law.hpp"
#include "aggpack/dynamics/thread_governor.hpp"

namespace aggpack {

struct DemSettings {
  Vec3 gravity{0.0, 0.0, -9.81};  // m/s^2
  double time_step = 1e-5;        // s
  double skin = 0.0;              // m; Verlet-list skin, 0: 0.1 of the smallest diameter
  int threads = 0;                // OpenMP threads for this system's loops, at most; 0: OpenMP's default
  // Whether the steps measure their speed and take fewer threads when fewer are faster (a
  // busy machine, a small bed: ThreadGovernor); else always `threads`. Either way the same bits.
  bool adapt_threads = true;
};

// Contact statistics of the free particles (frozen ones are not counted).
struct ContactStatistics {
  double mean_overlap = 0.0;      // mean overlap / (R_i + R_j) (or / 2 R_i for a wall), particle pairs
  double max_overlap = 0.0;       // largest overlap relative to the same diameter, walls included
  double coordination = 0.0;      // particle-particle contacts per free particle
  std::size_t contacts = 0;       // particle-particle contacts (each pair once per free side)
};

// A tool the spheres touch, driven along a prescribed path (a tamping rod): a vertical
// capsule, a cylinder of `radius` whose lower end is a hemisphere of the same radius centred
// at the tip centre, its axis running `length` up from there. It is infinitely massive and
// kinematic: it follows its path whatever the bed's resistance (a hand drives the rod; the
// force it takes is recorded, not obeyed). Its contacts take the walls' coefficients.
struct RodWaypoint {
  double time = 0.0;  // s of the system's time
  Vec3 tip;           // m, the tip's centre then
};
struct RodTool {
  double radius = 0.0;  // m
  double length = 0.0;  // m, of the axis above the tip centre
  // Piecewise linear in time, times ascending; before the first point the rod stands at the
  // first, after the last at the last.
  std::vector<RodWaypoint> path;

  [[nodiscard]] Vec3 tip_at(double t) const;
  [[nodiscard]] Vec3 velocity_at(double t) const;
  // Distance from x to the capsule's surface (its axis segment's nearest point, less the
  // radius; negative inside), with the tip at `tip`; `towards` the unit normal from x
  // towards the rod (from x to the axis).
  [[nodiscard]] double distance(const Vec3& tip, const Vec3& x, Vec3& towards) const;
};

// Thrown by DemSystem::run when the bed has blown up: a free sphere moved more than its own
// radius in one step (no contact can resolve that: a time step too long for the stiffness, an
// impact too fast), or its centre went through the floor or a side wall. The bed is lost; what
// says why is the caller's to add (the settings that set the time step and the speeds).
// An InputError: the settings that made the bed blow up are the user's (a stage adds which).
class DemBlowUp : public InputError {
 public:
  using InputError::InputError;
};

// A discrete element model of the spheres in a store: Hertz contacts with the law of
// `model`, gravity, the container's floor and side walls (or periodic sides), velocity
// Verlet for positions and spins. Frozen particles neither move nor feel forces.
//
// Rigid bodies. The store's rigid bodies (grains of several spheres) move as bodies: their
// member spheres touch everything else through the same contacts (never each other: a body's
// members are not listed against one another) and feel no gravity of their own; each body
// takes its weight and the sum of its members' forces, and their torques about its centre of
// mass. Its centre moves by the same velocity Verlet; its orientation (a unit quaternion) by
// the kicks of its angular momentum and, between them, the free rotation of
// rotate_freely() (NO_SQUISH's splitting, second order and symplectic). Its members are then
// placed from its pose, with the velocity of their point of the body. A contact takes a
// member's mass as its body's (as LAMMPS's granular styles do for rigid bodies).
//
// State. The system reads the store once, when it is made, into its own packed records
// (position, radius, velocity, mass, spin, 96 bytes: what a contact reads of a grain lies
// in one or two cache lines), and writes positions and velocities back to the store at the
// end of every run(). Every index of this interface is the store's (the user's) index.
//
// Order. At every neighbour-list build the records are sorted along a Morton curve, so
// that neighbours lie close in memory; the store keeps the user's order.
//
// Sums. A half Verlet list evaluates each pair once and applies the force to both grains,
// so Newton's third law holds exactly. For the sums to be taken in one fixed order whatever
// the number of OpenMP threads, the slots are cut into fixed blocks: a block's thread adds
// the pairs inside the block directly, and writes each pair that reaches a later block into
// a slot of its own, which that grain adds afterwards in ascending order of the rows.
// Results are bit-identical for any thread count.
class DemSystem {
 public:
  // `frozen[i]` = 1: particle i does not move (it still pushes on the others); empty: none.
  DemSystem(ParticleStore& particles, const Container& container, const ContactModel& model,
            const DemSettings& settings, std::vector<std::uint8_t> frozen = {});

  // Advances n steps. Throws DemBlowUp when the bed blows up: a position no longer finite (at
  // any step), a sphere faster than its radius per step or through a wall (at neighbour-list builds).
  void run(std::size_t steps);

  // Moves the container (floor and walls together) from now on as `motion` says, its
  // displacement measured from where it rests (the container the system was made with).
  void set_container_motion(const ContainerMotion& motion);
  // How far the container is above its rest position now, m.
  [[nodiscard]] double container_offset() const { return container_.bounds.lo.z - rest_floor_; }

  // Puts a rod in the bed, or takes it out (nullopt): from the next step on, its contacts
  // are the list's entry after the container's planes. The list is rebuilt. Throws
  // std::invalid_argument for a path out of order or a rod of no size.
  void set_tool(std::optional<RodTool> tool);
  [[nodiscard]] const std::optional<RodTool>& tool() const { return tool_; }
  // Sends the rod along a new path from now on, its contacts kept: the path must start where
  // the rod is now (a rod stopped by the bed, sent back up). std::invalid_argument otherwise.
  void redirect_tool(std::vector<RodWaypoint> path);
  // Where the rod's tip centre is now (the system's time).
  [[nodiscard]] Vec3 tool_tip() const { return tool_tip_; }
  // The force the bed exerts on the rod at the last step (the sum of its contacts), N, and
  // its largest magnitude since reset_tool_peak() (or since the tool was set).
  [[nodiscard]] Vec3 tool_force() const { return tool_force_; }
  [[nodiscard]] double tool_peak_force() const { return tool_peak_; }
  void reset_tool_peak() { tool_peak_ = 0.0; }

  // Takes in the particles appended to the store since the system last read it (a pour's
  // new batch): free, with the store's positions and velocities. The others keep their state
  // and their contact history; the neighbour list is rebuilt.
  void admit_new_particles();

  // The skin a system chooses when its settings leave it at 0: 0.1 of the smallest diameter.
  [[nodiscard]] static double default_skin(double smallest_radius) { return 0.1 * (2.0 * smallest_radius); }
  [[nodiscard]] std::size_t particle_count() const { return n_; }
  [[nodiscard]] const DemSettings& settings() const { return settings_; }
  [[nodiscard]] double time() const { return time_; }
  [[nodiscard]] std::size_t steps() const { return steps_; }
  [[nodiscard]] std::size_t rebuilds() const { return rebuilds_; }
  [[nodiscard]] double time_step() const { return settings_.time_step; }
  [[nodiscard]] double skin() const { return skin_; }
  [[nodiscard]] int threads() const { return governor_.most(); }  // at most; see DemSettings
  // Steps run on fewer threads than threads(): the governor's choice, or a bed too small for
  // threads (kThreadedFrom).
  [[nodiscard]] std::size_t steps_on_fewer_threads() const { return steps_on_fewer_threads_; }
  [[nodiscard]] const Vec3& gravity() const { return settings_.gravity; }
  // Net force and torque on particle i at the current positions (gravity included; zero on
  // a frozen particle).
  [[nodiscard]] Vec3 force(std::size_t i) const { return load_[slot_of_[i]].force; }
  [[nodiscard]] Vec3 torque(std::size_t i) const { return load_[slot_of_[i]].torque; }
  // Net force and torque (about its centre of mass) on rigid body b, gravity included. (On
  // one of its members, force() and torque() give that member's contacts only.)
  [[nodiscard]] Vec3 body_force(std::size_t b) const { return body_load_[b].force; }
  [[nodiscard]] Vec3 body_torque(std::size_t b) const { return body_load_[b].torque; }
  [[nodiscard]] std::size_t body_count() const { return body_.size(); }
  // Kinetic energy of the free spheres and the rigid bodies, J, summed in a fixed order.
  struct KineticEnergy {
    double translational = 0.0;
    double rotational = 0.0;
    [[nodiscard]] double total() const { return translational + rotational; }
  };
  [[nodiscard]] KineticEnergy kinetic_energy() const;
  [[nodiscard]] ContactStatistics contact_statistics() const;
  [[nodiscard]] std::size_t free_count() const { return free_count_; }
  [[nodiscard]] bool is_frozen(std::size_t i) const { return frozen_[slot_of_[i]] != 0; }
  // Neighbour-list entries (each pair once, walls included), and those that reach a later
  // block of slots, for memory accounting.
  [[nodiscard]] std::size_t list_entries() const { return other_.size(); }
  [[nodiscard]] std::size_t cross_block_entries() const { return cross_.size(); }
  [[nodiscard]] std::size_t memory_bytes() const;

  // Wraps the store's positions into a periodic container (call before handing it on).
  void finish();

  // Everything that determines the system's future (records, order, lists, contact history,
  // loads, time, the container's motion), as bytes for a checkpoint; restore_state() on a
  // system made from the same store, model and settings continues bit for bit as this one
  // would have (with any thread count). Throws InputError when the bytes do not fit: a
  // length, an index, a count, a flag or a number that is not what the store, the container
  // and the settings make possible (the store as it stood when the state was saved).
  void save_state(std::ostream& out) const;
  void restore_state(std::string_view bytes);

 private:
  // What a contact reads of a grain, packed (96 bytes).
  struct Grain {
    Vec3 position;
    double radius = 0.0;
    Vec3 velocity;
    double mass = 0.0;
    Vec3 angular_velocity;
    double inverse_inertia = 0.0;  // 1 / (2/5 m R^2), 0 when frozen
  };

  // A rigid body (see the class's comment); its members are slots like any sphere's.
  struct Body {
    Vec3 position;                  // of the centre of mass
    Quaternion orientation;         // body frame to space
    RotationMatrix rotation;        // the same as a matrix
    Vec3 velocity;
    Vec3 angular_momentum;          // about the centre of mass, in space
    Vec3 angular_velocity;          // in space: of the momentum and the orientation
    double mass = 0.0;
    Vec3 inverse_inertia;           // of the principal moments, along the body frame's axes
    std::uint32_t first_member = 0;  // store indices [first_member, first_member + member_count)
    std::uint32_t member_count = 0;
  };
  // Whether slot s is a rigid body's member (a slot of no body is a sphere of its own).
  [[nodiscard]] bool is_member(std::uint32_t s) const { return !body_of_.empty() && body_of_[s] != kNoBody; }
  // Whether a body is frozen: its members are, all of them (checked when it is admitted).
  [[nodiscard]] bool is_frozen_body(const Body& body) const { return frozen_[slot_of_[body.first_member]] != 0; }
  // Kicks the bodies' momenta by their loads for half_step, and their members' velocities.
  void kick_bodies(double half_step);
  // Moves the bodies for a step and places their members.
  void drift_bodies(double dt);
  // Sums the members' loads onto their bodies, with the bodies' weights (body_load_).
  void sum_body_loads();
  // Takes in the store's bodies from body_.size() on (their members from slot `first` on).
  void admit_bodies(std::uint32_t first);
  // Puts body b's members where its pose has them, with their points' velocities.
  void place_members(const Body& body);

  // Reads the store's particles from slot n_ on (flags by store index), then rebuilds.
  void admit(const std::vector<std::uint8_t>& frozen_by_index);
  template <class Law>
  void compute_forces(const Law& particle_law, const Law& wall_law);
  void compute_forces();
  // Gathers the contacts of whole rows from first_row on (within the block ending at
  // block_end) until the batch is full enough; returns the row after the last one gathered.
  std::uint32_t gather_contacts(ContactBatch& batch, std::uint32_t first_row, std::uint32_t block_end,
                                bool spin_needed);
  // Adds the evaluated batch to the rows [first_row, last_row), with the rows' wall contacts.
  template <class Law>
  void scatter_contacts(const ContactBatch& batch, std::uint32_t first_row, std::uint32_t last_row,
                        const Law& wall_law);
  // Sorts the records along the Morton curve, then rebuilds the lists (carrying the
  // contact history over).
  void build_neighbour_list();
  // The new list's rows in CSR form (offset, other), each row's entries in no fixed order:
  // every pair within the skin (not both frozen) in the row of its lower slot, and every wall
  // within the skin of a free slot.
  void find_pairs(std::vector<std::uint32_t>& offset, std::vector<std::uint32_t>& other) const;
  // Sorts each row of the new list and returns its springs: each contact's tangential history
  // taken from the old list (offset_, other_, spring_), whose slots were from[new slot]; the
  // rolling histories (roll_) likewise into `roll` when the law keeps them.
  [[nodiscard]] std::vector<Vec3> sort_rows_and_carry_springs(const std::vector<std::uint32_t>& from,
                                                              const std::vector<std::uint32_t>& offset,
                                                              std::vector<std::uint32_t>& other,
                                                              std::vector<Vec3>& roll) const;
  void check_not_blown_up() const;  // throws DemBlowUp
  [[nodiscard]] std::vector<std::uint32_t> morton_order() const;
  // Slot s takes what slot from[s] held (records, flags, forces); the lists are not touched.
  void reorder(const std::vector<std::uint32_t>& from);
  void write_back();  // positions and velocities to the store, in the user's order
  // Positions stay within one period of the box between list builds, so the container's
  // minimum image applies. (Inline: it is in the innermost loop.)
  [[nodiscard]] Vec3 separation(const Vec3& from, const Vec3& to) const { return container_.minimum_image(to - from); }
  void advance(std::size_t steps);  // run()'s steps, on threads_ threads
  void use_threads(int threads);    // from the next loop on
  void kick(double half_step);
  // Moves the grains; true when one has moved more than half the skin, less `slack`, since
  // the list build.
  bool drift(double slack);
  // Puts the container where its motion has it at time t.
  void place_container(double t);
  // Entry `wall` of a row (0 .. plane_count() - 1 the container's planes, plane_count() the
  // rod): the distance from x to it and the unit normal towards it, as Container::plane_distance.
  [[nodiscard]] double wall_distance(unsigned wall, const Vec3& x, Vec3& towards) const {
    return wall < container_.plane_count() ? container_.plane_distance(wall, x, towards)
                                           : tool_->distance(tool_tip_, x, towards);
  }
  [[nodiscard]] unsigned wall_entries() const { return container_.plane_count() + (tool_ ? 1u : 0u); }
  // Moves the rod to time t; returns how far it is from where it was at the list build.
  double place_tool(double t);
  // Sums the blocks' forces on the rod in block order (any thread count: the same bits).
  void sum_tool_force();
  // Derives the list's cross-block parts (cross_begin_, slot_base_, cross_, reverse_offset_,
  // reverse_) from its rows (offset_, other_).
  void index_cross_block_entries();
  // save_state()'s and restore_state()'s one list of members (System: const or not).
  template <class Archive, class System>
  static void archive_state(Archive& ar, System& system);
  // What restore_state() checks a state against: the system as made, before the state.
  struct MadeWith {
    Container container;
    double skin, bed_volume, morton_cell, rest_floor, rest_top;
    std::vector<std::uint8_t> frozen_by_index;
  };
  void check_restored(const MadeWith& made) const;
  void check_restored_bodies() const;
  void check_restored_tool() const;
  void check_restored_motion() const;  // and the tool's

  ParticleStore& p_;
  Container container_;
  ContactModel model_;
  DemSettings settings_;
  double skin_ = 0.0;
  double grid_bed_volume_ = 0.0;  // m^3, sizes the grid's sparse levels
  double morton_cell_ = 0.0;      // m, cell of the Morton sort: the mean diameter
  std::uint32_t n_ = 0;
  std::uint32_t listed_count_ = 0;  // n_ when the neighbour list was last built
  bool threaded_ = false;  // OpenMP loops: a bed large enough to gain from them, threads_ > 1
  int threads_ = 1;        // threads of those loops now (the results do not depend on it)
  ThreadGovernor governor_{1};  // chooses threads_ from the most allowed, when it adapts
  std::size_t steps_on_fewer_threads_ = 0;
  double list_seconds_ = 0.0;   // wall clock of the list builds in run() (left out of the speeds)
  std::size_t free_count_ = 0;
  std::vector<Grain> grain_;                 // per slot
  std::vector<std::uint32_t> user_index_;    // per slot: the grain's index in the store
  std::vector<std::uint32_t> slot_of_;       // per store index: its slot
  std::vector<std::uint8_t> frozen_;         // per slot: 1 for a particle that does not move
  struct ForceTorque {
    Vec3 force, torque;
  };
  std::vector<ForceTorque> load_;            // per slot: net force and torque
  std::vector<Vec3> listed_position_;        // per slot: positions when the list was built
  // Half Verlet list in CSR form: slot i's entries are [offset_[i], offset_[i + 1]), sorted
  // ascending: first neighbours j > i in i's block, then neighbours in later blocks (from
  // cross_begin_[i]), then walls (n_ + wall index). Pairs of two frozen slots are left out.
  std::vector<std::uint32_t> offset_, cross_begin_, other_;
  std::vector<Vec3> spring_;                 // tangential history per entry, as seen from i
  // Rolling history per entry (the same seen from i or j), kept only when the law needs it
  // (rolling_history_: the spring-dashpot rolling model); empty otherwise.
  std::vector<Vec3> roll_;
  bool rolling_history_ = false;
  bool rolling_resistance_ = false;  // a law with rolling resistance: the contacts need w_i - w_j
  // Per slot, the grain's material: in a run of several materials only (model_.materials > 1),
  // whose contacts take the law of their pair of materials.
  std::vector<std::uint8_t> material_;
  void read_materials();
  // The rigid bodies, in the store's order, and their net loads; empty without bodies.
  std::vector<Body> body_;
  std::vector<ForceTorque> body_load_;
  std::vector<std::uint32_t> body_of_;  // per slot: its body, or kNoBody; empty without bodies
  std::vector<Vec3> body_offset_;       // per store index: a member's centre in its body's frame
  std::vector<Vec3> arm_;               // per store index: a member's centre from its body's, in space
  // Per store index: the whole periods a member is shifted by from its body's centre plus its
  // arm, chosen at each list build so that every member lies in the periodic box then.
  std::vector<Vec3> image_;  // material_ from the store, by the slots' user indices
  // Force and torque that a cross-block entry puts on its neighbour j; slot_base_[i] is the
  // first of row i's. Slot j gathers its own, cross_[reverse_[reverse_offset_[j] ...]], in
  // ascending order of the row they come from.
  std::vector<ForceTorque> cross_;
  std::vector<std::uint32_t> slot_base_, reverse_offset_, reverse_;
  std::vector<ContactBatch> batches_;        // one per thread: contacts gathered for the law
  double time_ = 0.0;
  double force_time_ = 0.0;          // the time of the positions the forces were computed at
  ContainerMotion motion_;           // of the container (at rest unless set)
  double rest_floor_ = 0.0, rest_top_ = 0.0;  // m, the container's floor and top at rest
  double listed_offset_ = 0.0;       // the container's offset when the list was built
  std::size_t steps_ = 0, rebuilds_ = 0;
  // The rod (README, "Rodding"): its tip now and at the list build, the force on it (per
  // block of kForceBlock slots, then summed) and its peak.
  std::optional<RodTool> tool_;
  Vec3 tool_tip_, tool_velocity_, listed_tool_tip_, tool_force_;
  std::vector<Vec3> tool_block_force_;
  double tool_peak_ = 0.0;
};

}  // namespace aggpack
