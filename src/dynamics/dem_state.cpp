// DemSystem's state for a checkpoint: saved, restored, and checked against the run it
// is restored into.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <string_view>
#include <type_traits>

#include <fmt/format.h>

#include "aggpack/core/error.hpp"
#include "aggpack/dynamics/dem_system.hpp"
#include "aggpack/dynamics/rigid_rotation.hpp"
#include "core/archive.hpp"
#include "dem_system_internal.hpp"

namespace aggpack {

namespace {
constexpr std::uint32_t kStateFormat = 3;  // raise when the members below change (3: the rod, the motion's profile)
}  // namespace

// The members in one list for saving and restoring. Not saved: the model and the settings
// (the scenario's), the thread count and the per-thread batches (they do not change results),
// and what follows from the list (its cross-block slots: index_cross_block_entries()).
template <class Archive, class System>
void DemSystem::archive_state(Archive& ar, System& s) {
  ar(raw_value(s.container_), s.skin_, s.grid_bed_volume_, s.morton_cell_, s.n_, s.listed_count_, s.free_count_);
  ar(raw(s.grain_), raw(s.user_index_), raw(s.slot_of_), raw(s.frozen_), raw(s.load_), raw(s.listed_position_));
  ar(raw(s.offset_), raw(s.other_), raw(s.spring_));
  // Only a law with a rolling history has one to save (the model is the scenario's, not saved):
  // the bytes of the other laws stay what they were.
  if (s.rolling_history_) ar(raw(s.roll_));
  ar(s.time_, s.force_time_, raw_value(s.motion_), s.rest_floor_, s.rest_top_, s.listed_offset_, s.steps_,
     s.rebuilds_);
  // The rod, when there is one (its per-block forces follow from the next force pass).
  std::uint8_t has_tool = s.tool_ ? 1 : 0;
  ar(has_tool);
  if constexpr (!std::is_const_v<System>) {
    if (has_tool > 1) throw InputError("the DEM state's rod flag is neither 0 nor 1");
    if (has_tool == 0) s.tool_.reset();
    else if (!s.tool_) s.tool_.emplace();
  }
  if (has_tool != 0) ar(s.tool_->radius, s.tool_->length, raw(s.tool_->path));
  ar(raw_value(s.tool_tip_), raw_value(s.tool_velocity_), raw_value(s.listed_tool_tip_), raw_value(s.tool_force_),
     s.tool_peak_);
  // Likewise the rigid bodies: a store of spheres only keeps the bytes it had.
  if (!s.p_.bodies.empty()) ar(raw(s.body_), raw(s.body_load_), raw(s.body_of_), raw(s.arm_), raw(s.image_));
}

void DemSystem::save_state(std::ostream& out) const {
  cereal::BinaryOutputArchive ar(out);
  ar(kStateFormat, static_cast<std::uint64_t>(p_.size()));
  archive_state(ar, *this);
}

void DemSystem::restore_state(std::string_view bytes) {
  // What the system was made with (the scenario's container and settings, the store's
  // particles): the restored state must agree with it.
  MadeWith made{container_, skin_, grid_bed_volume_, morton_cell_, rest_floor_, rest_top_,
                std::vector<std::uint8_t>(n_)};
  for (std::uint32_t s = 0; s < n_; ++s) made.frozen_by_index[user_index_[s]] = frozen_[s];
  try {
    CheckedInputArchive ar(bytes);
    std::uint32_t format = 0;
    std::uint64_t particles = 0;
    ar(format, particles);
    if (format != kStateFormat || particles != p_.size())
      throw InputError(fmt::format("the DEM state is of format {} for {} particles; this system is of format {} "
                                   "with {}", format, particles, kStateFormat, p_.size()));
    archive_state(ar, *this);
    if (ar.left() > 0) throw InputError(fmt::format("the DEM state has {} bytes after its end", ar.left()));
  } catch (const cereal::Exception& e) {
    throw InputError(fmt::format("the DEM state is truncated or damaged ({})", e.what()));
  }
  check_restored(made);
  read_materials();  // the restored slots' (the store's order is the user's)
  index_cross_block_entries();
  use_threads(threads_);
  batches_.assign(static_cast<std::size_t>(governor_.most()), ContactBatch{});
}

namespace {
// Whether a restored container is of the run's kind: its periodic flag and shape read as their
// bytes first (any other value than 0 or 1 in a bool, or a stray value of an enum, is no value).
bool same_kind(const Container& restored, const Container& made) {
  unsigned char periodic = 0;
  std::memcpy(&periodic, &restored.periodic, 1);
  std::underlying_type_t<ContainerShape> shape{};
  std::memcpy(&shape, &restored.shape, sizeof shape);
  return periodic == (made.periodic ? 1 : 0) &&
         shape == static_cast<std::underlying_type_t<ContainerShape>>(made.shape) && restored.rim == made.rim;
}
}  // namespace

void DemSystem::check_restored(const MadeWith& made) const {
  const auto fail = [](std::string_view what) {
    throw InputError(fmt::format("the DEM state does not fit its run: {}", what));
  };
  const auto finite = [](const Vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); };
  const std::uint32_t n = n_;
  // The count first: every check below indexes the store and the run's flags by it.
  if (n != p_.size() || n != made.frozen_by_index.size())
    fail(fmt::format("its particle count, {}, is not the run's {}", n, p_.size()));
  // The container: the scenario's, moved up or down by its motion only.
  const Box &box = container_.bounds, &made_box = made.container.bounds;
  if (!same_kind(container_, made.container) || box.lo.x != made_box.lo.x || box.hi.x != made_box.hi.x ||
      box.lo.y != made_box.lo.y || box.hi.y != made_box.hi.y || rest_floor_ != made.rest_floor ||
      rest_top_ != made.rest_top)
    fail("its container is not the scenario's");
  check_restored_motion();
  // Time is counted in steps; the container stands where its motion has it then.
  if (time_ != static_cast<double>(steps_) * settings_.time_step || force_time_ != time_)
    fail(fmt::format("its time, {} s, is not its {} steps of {} s", time_, steps_, settings_.time_step));
  const double offset = motion_.offset(time_);
  if (box.lo.z != rest_floor_ + offset || box.hi.z != rest_top_ + offset) fail("the container's height");
  // The sizes the system chose from the store's radii (summed in another order: nearly equal).
  const auto near = [](double a, double b) { return std::abs(a - b) <= 1e-9 * std::abs(b); };
  if (skin_ != made.skin || !near(grid_bed_volume_, made.bed_volume) || !near(morton_cell_, made.morton_cell))
    fail("its skin or grid sizes are not those of its particles");

  // The records: one per particle, each slot a particle of the store, the inverse table its
  // inverse, and each record the store's particle (the store is written back at every safe point).
  if (listed_count_ != n || grain_.size() != n || user_index_.size() != n || slot_of_.size() != n ||
      frozen_.size() != n || load_.size() != n || listed_position_.size() != n)
    fail("its tables are not one entry per particle");
  std::size_t free = 0;
  for (std::uint32_t s = 0; s < n; ++s) {
    const std::uint32_t i = user_index_[s];
    if (i >= n || slot_of_[i] != s) fail(fmt::format("slot {} names particle {}, not a permutation", s, i));
    if (frozen_[s] != made.frozen_by_index[i]) fail(fmt::format("particle {} is frozen where the run has it free, or the reverse", i));
    free += frozen_[s] ? 0 : 1;
    const Grain& g = grain_[s];
    // A rigid body's member has its body's mass and does not turn on its own (checked below).
    const bool member = !p_.bodies.empty() && p_.body[i] != kNoBody;
    const double inverse_inertia =
        frozen_[s] || member ? 0.0 : 1.0 / (0.4 * p_.mass[i] * p_.radius[i] * p_.radius[i]);
    // The store holds the grain's position, or it wrapped into a periodic box (by finish(), at
    // the end of a step: a state saved between steps), or the grain's wrap of it.
    const Vec3& stored = p_.position[i];
    const bool same_place = g.position == stored || g.position == made.container.wrapped(stored) ||
                            made.container.wrapped(g.position) == stored;
    if (!finite(g.position) || !same_place ||
        !(g.velocity == p_.velocity[i]) || !(g.angular_velocity == p_.angular_velocity[i]) ||
        g.radius != p_.radius[i] || g.mass != (member ? p_.bodies.mass[p_.body[i]] : p_.mass[i]) || g.inverse_inertia != inverse_inertia)
      fail(fmt::format("the record of particle {} is not the particle", i));
    if (!finite(listed_position_[s]) || !finite(load_[s].force) || !finite(load_[s].torque))
      fail(fmt::format("the forces or the listed position of particle {}", i));
  }
  if (free != free_count_) fail("its count of free particles");
  check_restored_bodies();

  // The half neighbour list: rows of ascending entries, each a later slot or a wall.
  const std::uint32_t walls = wall_entries();
  if (offset_.size() != std::size_t{n} + 1 || offset_[0] != 0 || offset_[n] != other_.size() ||
      spring_.size() != other_.size() || roll_.size() != (rolling_history_ ? other_.size() : 0))
    fail("its neighbour list's rows");
  for (std::uint32_t i = 0; i < n; ++i) {
    // Each row within the entries (a later row's offset may not be read before it is checked).
    if (offset_[i + 1] < offset_[i] || offset_[i + 1] > other_.size())
      fail(fmt::format("its neighbour list's row {}", i));
    for (std::uint32_t k = offset_[i]; k < offset_[i + 1]; ++k) {
      const std::uint32_t j = other_[k];
      const bool both_frozen = j < n ? frozen_[i] && frozen_[j] : frozen_[i] != 0;
      if (j <= i || j >= n + walls || (k > offset_[i] && j < other_[k - 1]) || both_frozen || !finite(spring_[k]) ||
          (rolling_history_ && !finite(roll_[k])))
        fail(fmt::format("its neighbour list's entry {} of row {}", k - offset_[i], i));
    }
  }
}

void DemSystem::check_restored_motion() const {
  unsigned char profile = 0;  // read as a byte: an enum of another value is undefined behaviour
  std::memcpy(&profile, &motion_.profile, 1);
  if (!std::isfinite(motion_.start) || !std::isfinite(motion_.amplitude) || !std::isfinite(motion_.angular_frequency) ||
      !std::isfinite(motion_.cycles) || !std::isfinite(listed_offset_) || profile > 1 ||
      !std::isfinite(motion_.lift_acceleration) || !std::isfinite(motion_.fall_acceleration) ||
      (profile == 1 && motion_.amplitude != 0.0 && !(motion_.lift_acceleration > 0.0 && motion_.fall_acceleration > 0.0)))
    throw InputError("the DEM state does not fit its run: the container's motion");
  check_restored_tool();
}

void DemSystem::check_restored_tool() const {
  const auto finite = [](const Vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); };
  if (!finite(tool_tip_) || !finite(tool_velocity_) || !finite(listed_tool_tip_) || !finite(tool_force_) ||
      !std::isfinite(tool_peak_))
    throw InputError("the DEM state does not fit its run: the rod's place or force");
  if (!tool_) return;
  const auto& path = tool_->path;
  bool ordered = !path.empty() && tool_->radius > 0.0 && std::isfinite(tool_->radius) && tool_->length >= 0.0 &&
                 std::isfinite(tool_->length);
  for (std::size_t k = 0; ordered && k < path.size(); ++k)
    ordered = finite(path[k].tip) && std::isfinite(path[k].time) && (k == 0 || path[k].time > path[k - 1].time);
  if (!ordered || !(tool_->tip_at(time_) == tool_tip_))
    throw InputError("the DEM state does not fit its run: the rod's size or path");
}

void DemSystem::check_restored_bodies() const {
  const auto fail = [](std::string_view what) {
    throw InputError(fmt::format("the DEM state does not fit its run: {}", what));
  };
  const auto finite = [](const Vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); };
  const RigidBodies& bodies = p_.bodies;
  if (bodies.empty()) return;
  const std::uint32_t n = n_;
  if (body_.size() != bodies.size() || body_load_.size() != bodies.size() || body_of_.size() != n ||
      arm_.size() != n || image_.size() != n)
    fail("its rigid bodies' tables are not one entry per body or per particle");
  for (std::uint32_t s = 0; s < n; ++s) {
    const std::uint32_t i = user_index_[s];
    if (body_of_[s] != p_.body[i]) fail(fmt::format("particle {} is of another rigid body than the run's", i));
    if (!finite(arm_[i]) || !finite(image_[i])) fail(fmt::format("the place of particle {} in its body", i));
  }
  for (std::size_t b = 0; b < body_.size(); ++b) {
    const Body& body = body_[b];
    const Vec3& moments = bodies.principal_inertia[b];
    const Quaternion& q = body.orientation;
    const double q_norm = std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
    if (body.first_member != bodies.first_member[b] || body.member_count != bodies.member_count[b] ||
        body.mass != bodies.mass[b] || body.inverse_inertia.x != 1.0 / moments.x ||
        body.inverse_inertia.y != 1.0 / moments.y || body.inverse_inertia.z != 1.0 / moments.z)
      fail(fmt::format("the record of rigid body {} is not the body", b));
    if (!finite(body.position) || !finite(body.velocity) || !finite(body.angular_momentum) ||
        !finite(body.angular_velocity) || !(std::abs(q_norm - 1.0) < 1e-12) || !finite(body_load_[b].force) ||
        !finite(body_load_[b].torque) || !(body.rotation == rotation_matrix(body.orientation)))
      fail(fmt::format("the pose, motion or load of rigid body {}", b));
    // The store's record of the body (written back at every safe point; its centre wrapped by
    // finish() in a periodic box), and its angular velocity the momentum's.
    const Vec3& stored = bodies.position[b];
    const bool same_place = body.position == stored || container_.wrapped(body.position) == stored ||
                            body.position == container_.wrapped(stored);
    if (!same_place || !(body.velocity == bodies.velocity[b]) || !(body.orientation == bodies.orientation[b]) ||
        !(body.angular_velocity == bodies.angular_velocity[b]) ||
        !(body.angular_velocity == angular_velocity_of(body.rotation, body.angular_momentum, body.inverse_inertia)))
      fail(fmt::format("the record of rigid body {} is not the run's body", b));
    // A frozen body stands still (admit_bodies stopped it; nothing moves it after).
    if (is_frozen_body(body) && !(body.velocity == Vec3{} && body.angular_momentum == Vec3{}))
      fail(fmt::format("rigid body {} is frozen and moving", b));
    // Its members where its pose has them (to rounding: a list build wraps them into the box),
    // moving with it, each shifted by whole periods or none.
    const double size = std::max(container_.length_x(), container_.length_y());
    for (std::uint32_t i = body.first_member; i < body.first_member + body.member_count; ++i) {
      const Grain& g = grain_[slot_of_[i]];
      const Vec3& image = image_[i];
      const auto whole_periods = [&](double shift, double period) {
        return std::abs(shift - period * std::round(shift / period)) <= 1e-9 * period;
      };
      const bool images_fit = container_.periodic
                                  ? whole_periods(image.x, container_.length_x()) &&
                                        whole_periods(image.y, container_.length_y()) && image.z == 0.0
                                  : image == Vec3{};
      if (!(arm_[i] == body.rotation(body_offset_[i])) || !images_fit ||
          !(norm(g.position - (body.position + arm_[i] + image)) <= 1e-12 * size) ||
          !(g.velocity == body.velocity + cross(body.angular_velocity, arm_[i])) ||
          !(g.angular_velocity == body.angular_velocity))
        fail(fmt::format("particle {} is not where its rigid body {} has it", i, b));
    }
  }
}

}  // namespace aggpack
