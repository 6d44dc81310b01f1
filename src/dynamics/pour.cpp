#include "aggpack/dynamics/pour.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include <fmt/format.h>

namespace aggpack {

PourSchedule pour_schedule(const PourSettings& settings, std::size_t count) {
  return {count, std::min<std::size_t>(settings.batches, std::max<std::size_t>(1, count))};
}

double solid_volume(std::span<const double> radii) {
  double solid = 0.0;
  for (const double r : radii) solid += 4.0 / 3.0 * std::numbers::pi * r * r * r;
  return solid;
}

double batch_fall_time(double velocity, double g, double height) {
  return g > 0.0 ? (std::sqrt(velocity * velocity + 2.0 * g * height) - velocity) / g : 0.0;
}

double poured_speed(const PourSettings& settings, double g, double height) {
  if (!settings.release_height) return settings.velocity;
  const double fall = std::max(0.0, *settings.release_height - height);
  return std::sqrt(settings.velocity * settings.velocity + 2.0 * g * fall);
}

BatchGas batch_gas(const Container& container, double bottom, std::span<const double> batch, double solid_fraction,
                   Rng& rng) {
  BatchGas gas{insertion_region(container, bottom, solid_volume(batch), solid_fraction), {}};
  try {
    gas.positions = random_gas(container, gas.slab, batch, rng);
  } catch (const InputError& e) {
    throw PourInsertionError(e.what());
  }
  return gas;
}

PourReport planned_pour(const PourSettings& settings, std::span<const double> radii) {
  const double r_max = radii.empty() ? 0.0 : *std::max_element(radii.begin(), radii.end());
  PourReport planned;
  planned.poured = radii.size();
  planned.batches = pour_schedule(settings, radii.size()).batches;
  planned.solid_fraction = settings.solid_fraction;
  planned.velocity = settings.velocity;
  planned.gap = settings.gap.value_or(2.0 * r_max);
  planned.release_height = settings.release_height;
  planned.lowest_slab_bottom = std::numeric_limits<double>::infinity();
  return planned;
}

PourLoop begin_pour(const DemSystem& system, const PourSettings& settings, std::span<const double> radii, Rng rng) {
  PourLoop loop;
  loop.start = system.time();
  loop.start_steps = system.steps();
  loop.rng = rng;
  loop.report = planned_pour(settings, radii);
  return loop;
}

bool fits(const PourLoop& loop, const PourReport& planned, const DemSystem& system) {
  const PourReport& r = loop.report;
  return r.poured == planned.poured && r.batches == planned.batches && r.solid_fraction == planned.solid_fraction &&
         r.velocity == planned.velocity && r.gap == planned.gap && r.release_height == planned.release_height &&
         loop.batch < r.batches && loop.start >= 0.0 && loop.start <= system.time() &&
         loop.start_steps <= system.steps() && std::isfinite(loop.next) && std::isfinite(loop.weight) &&
         std::isfinite(loop.poured_at) && loop.pour_steps <= system.steps() - loop.start_steps && !loop.rng.stuck();
}

namespace {

using Clock = std::chrono::steady_clock;

// The highest sphere surface of the bed, m (the container's floor for an empty one).
double top_of_bed(const ParticleStore& particles, const Container& container) {
  double top = container.bounds.lo.z;
  for (std::size_t i = 0; i < particles.size(); ++i) top = std::max(top, particles.position[i].z + particles.radius[i]);
  return top;
}

// Puts batch `loop.batch` in as a gas above the bed and times the next one.
void insert_batch(DemSystem& system, ParticleStore& particles, const Container& container,
                  std::span<const double> radii, const PourSettings& settings, std::uint32_t part,
                  const SphereMaterials& materials, const PouredShapes& shapes, PourLoop& loop) {
  PourReport& report = loop.report;
  const std::span<const double> batch = pour_schedule(settings, radii.size()).batch(radii, loop.batch);
  const auto t_insert = Clock::now();
  const BatchGas gas =
      batch_gas(container, top_of_bed(particles, container) + report.gap, batch, settings.solid_fraction, loop.rng);
  const auto first = static_cast<std::size_t>(batch.data() - radii.data());  // of the batch in the pour's spheres
  const double g = norm(system.gravity()), floor = container.bounds.lo.z;
  for (std::size_t k = 0; k < batch.size(); ++k) {
    const RigidBodyShape* shape = shapes.shape(first + k);
    const double speed = poured_speed(settings, g, gas.positions[k].z - floor);
    // An orientation drawn for a grain only: a pour of spheres keeps its stream.
    add_poured(particles, gas.positions[k], batch[k], shape, shape ? random_orientation(loop.rng) : Quaternion{},
               {0.0, 0.0, -speed}, materials.density_of(first + k), part, materials.material(first + k));
  }
  report.insertion_wall_clock_s += std::chrono::duration<double>(Clock::now() - t_insert).count();
  report.lowest_slab_bottom = std::min(report.lowest_slab_bottom, gas.slab.bottom);
  report.highest_slab_top = std::max(report.highest_slab_top, gas.slab.top);
  system.admit_new_particles();
  loop.weight = weight_energy(system, particles);
  // After the last batch, this is when the pour has reached the bed (its slowest, top particles
  // through the slab).
  loop.next = (system.time() - loop.start) +
              batch_fall_time(poured_speed(settings, g, gas.slab.top - floor), g, gas.slab.top - gas.slab.bottom);
}

}  // namespace

void add_poured(ParticleStore& store, const Vec3& at, double radius, const RigidBodyShape* shape,
                const Quaternion& orientation, const Vec3& velocity, double density, std::uint32_t layer,
                std::uint8_t material) {
  if (!shape) {
    store.add(at, radius, density, layer, material);
    store.velocity.back() = velocity;
    return;
  }
  RigidBodyShape scaled = *shape;
  scaled.scale = radius;
  const std::size_t b = store.add_body(at, orientation, scaled, density, layer, material);
  store.bodies.velocity[b] = velocity;
}

SettleResult pour(DemSystem& system, ParticleStore& particles, const Container& container, std::span<const double> radii,
                  const PourSettings& settings, std::uint32_t part, const SphereMaterials& materials,
                  const PouredShapes& shapes, const QuietCriterion& quiet, PourLoop& loop, bool resumed,
                  const PourHooks& hooks) {
  if (!shapes.of.empty() && shapes.of.size() != radii.size())
    throw std::invalid_argument("pour: one shape (or none) per radius poured");
  const std::size_t steps_per_sample = quiet.steps_per_sample(system.time_step());
  const auto since_start = [&] { return system.time() - loop.start; };
  // A resumed pour continues where its batch was falling, or where the bed was settling.
  bool batch_in = resumed;
  if (!loop.settling) {
    for (; loop.batch < loop.report.batches; ++loop.batch) {
      if (!batch_in) {
        insert_batch(system, particles, container, radii, settings, part, materials, shapes, loop);
        if (loop.batch + 1 == loop.report.batches) break;
      }
      batch_in = false;
      while (loop.block_steps_left > 0 || since_start() < std::min(loop.next, quiet.max_time)) {
        // Counted as the pour's particles (a grain is one, whatever its spheres), this part's only.
        const std::span<const double> batch = pour_schedule(settings, radii.size()).batch(radii, loop.batch);
        const auto poured_in = static_cast<std::size_t>(batch.data() - radii.data()) + batch.size();
        const std::string phase = fmt::format("pouring, {} of {} in", poured_in, radii.size());
        if (loop.block_steps_left == 0) loop.block_steps_left = steps_per_sample;
        run_block(system, loop.block_steps_left, [&] { hooks.at_safe_point(phase); });
        SettleSample s = sample_system(system, particles, loop.weight, nullptr);  // no density: the bed is still being built
        s.time -= loop.start;
        hooks.on_sample(s, phase);
        hooks.at_safe_point(phase);
      }
    }
    loop.poured_at = since_start();
    loop.pour_steps = system.steps() - loop.start_steps;
  }
  QuietCriterion rest = quiet;
  rest.max_time = std::max(rest.sample_interval, quiet.max_time - loop.poured_at);
  const double poured_at = loop.poured_at;
  SettleResult result = settle(
      system, particles, rest, hooks.density,
      [&](const SettleSample& s) {
        SettleSample shifted = s;
        shifted.time += poured_at;
        hooks.on_sample(shifted, "settling");
      },
      [&](const SettleLoop& settling) {
        loop.settling = true;
        loop.settle = settling;
        hooks.at_safe_point("settling");
      },
      loop.settling ? &loop.settle : nullptr);
  result.last.time += poured_at;
  result.simulated_time += poured_at;
  result.steps += loop.pour_steps;
  return result;
}

}  // namespace aggpack
