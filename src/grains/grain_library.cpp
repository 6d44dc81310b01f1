#include "aggpack/grains/grain_library.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "aggpack/core/error.hpp"
#include "aggpack/core/rng.hpp"

namespace aggpack {

std::string_view family_name(GrainFamily family) { return family == GrainFamily::Rounded ? "rounded" : "angular"; }

namespace {

LibraryGrain at_reach_one(GrainTemplate grain) {
  LibraryGrain g;
  for (const MemberSphere& s : grain.spheres) g.reach = std::max(g.reach, norm(s.centre) + s.radius);
  const double unit = 1.0 / g.reach;
  for (const MemberSphere& s : grain.spheres) {
    g.unit_centres.push_back(s.centre * unit);
    g.unit_radii.push_back(s.radius * unit);
  }
  g.unit_volume = grain.mass.volume * unit * unit * unit;
  const double unit5 = unit * unit * unit * unit * unit;
  g.unit_moments = {grain.mass.inertia[0] * unit5, grain.mass.inertia[1] * unit5, grain.mass.inertia[2] * unit5};
  g.grain = std::move(grain);
  return g;
}

}  // namespace

namespace {

// `count` templates drawn from `distribution`: the same stream for every distribution, so that a
// fit moves the templates only through their means.
// Counts the templates drawn for the watch, and stops where asked.
struct DrawCounter {
  const LibraryWatch& watch;
  std::size_t expected;
  std::size_t drawn = 0;
  void one_more() {
    ++drawn;
    if (watch.progress) watch.progress(drawn, expected);
    stop_here_if_requested(watch.stop, fmt::format("while making grain templates ({} of at most {})", drawn, expected));
  }
};

std::vector<LibraryGrain> draw_templates(const GrainShapeSpec& spec, const ProportionDistribution& distribution,
                                         std::uint64_t seed, DrawCounter& counter) {
  Rng rng = make_rng(seed, RngPurpose::Shapes);
  std::vector<LibraryGrain> grains;
  for (std::size_t k = 0; k < spec.templates; ++k) {
    counter.one_more();
    const Proportions p = distribution.draw(rng);
    const std::uint64_t hull_seed = rng.next_u64();
    grains.push_back(at_reach_one(spec.family == GrainFamily::Rounded
                                      ? rounded_grain(p.elongation, p.flatness, spec.spheres)
                                      : angular_grain(p.elongation, p.flatness, spec.corners, spec.spheres, hull_seed)));
  }
  return grains;
}

// The target's percentage over the templates as they came out (their fill's own proportions):
// every template at every size, by mass, as a component whose grains pick templates at random.
std::vector<GrainMeasure> measure_templates(const std::vector<LibraryGrain>& grains, std::span<const double> sizes) {
  std::vector<GrainMeasure> all;
  for (const double width : sizes)
    for (const LibraryGrain& g : grains) all.push_back(measure_grain(g, width, 1.0));
  return all;
}

double library_percent(const std::vector<LibraryGrain>& grains, const ShapeTarget& target,
                       std::span<const double> sizes) {
  return measured_percent(target, measure_templates(grains, sizes)).value_or(0.0);
}

}  // namespace

namespace {
// The fit's draws of the library: the ideal fit's, up to 10 steps out, up to 8 bisections.
constexpr std::size_t kMostFitDraws = 19;
constexpr int kBisections = 8;
constexpr double kSmallestStep = 0.05;
}  // namespace

std::size_t most_templates_drawn(const GrainShapeSpec& spec) {
  return spec.templates * (spec.target ? kMostFitDraws : 1);
}

double estimated_library_seconds(const GrainShapeSpec& spec) {
  // A template's member spheres cost about this each, its fills to meet its proportions
  // included (BENCHMARKS.md, "What the templates cost": 5e-3 to 1.5e-2 s measured, angular and
  // rounded, 16 to 64 spheres). With a lab measure, the most the fit can draw: an angular fit
  // often stops after one or two draws, a rounded one of 64 spheres took all of them.
  constexpr double kSecondsPerTemplateSphere = 1e-2;
  return static_cast<double>(most_templates_drawn(spec) * spec.spheres) * kSecondsPerTemplateSphere;
}

void check_library_cost(std::span<const GrainShapeSpec* const> specs, double max_minutes, std::string_view where,
                        std::string_view limit_key) {
  double seconds = 0.0;
  std::size_t templates = 0;
  for (const GrainShapeSpec* spec : specs) {
    seconds += estimated_library_seconds(*spec);
    templates += most_templates_drawn(*spec);
  }
  if (seconds <= 60.0 * max_minutes) return;
  throw InputError(fmt::format("{}: the grains' templates would take an estimated {:.3g} minutes to make (up to {} "
                               "templates drawn, a lab measure's fit drawing its library up to {} times, each "
                               "template's spheres filled one by one), more than {:.3g}; expected fewer templates or "
                               "spheres, or a larger {}",
                               where, seconds / 60.0, templates, kMostFitDraws, max_minutes, limit_key));
}

GrainLibrary make_grain_library(const GrainShapeSpec& spec, std::span<const double> intermediate_sizes,
                                std::uint64_t seed, const LibraryWatch& watch) {
  spec.proportions.check();
  if (spec.spheres < 1 || spec.spheres > 64) throw InputError(fmt::format("spheres = {}: expected 1 to 64", spec.spheres));
  if (spec.family == GrainFamily::Angular && (spec.corners < 4 || spec.corners > 200))
    throw InputError(fmt::format("corners = {}: expected 4 to 200", spec.corners));
  if (spec.templates < 1 || spec.templates > 1000)
    throw InputError(fmt::format("templates = {}: expected 1 to 1000", spec.templates));
  GrainLibrary library{spec, spec.proportions, std::nullopt, {}};
  DrawCounter counter{watch, most_templates_drawn(spec)};
  if (!spec.target) {
    library.grains = draw_templates(spec, spec.proportions, seed, counter);
    return library;
  }
  // The fit on ideal proportions first, then on the templates themselves (a fill of few
  // spheres measures other proportions than it was asked for): the parameter is bracketed
  // from the ideal fit's and bisected, the percentage falling as it grows.
  const ShapeTarget& target = *spec.target;
  ProportionFit fit = fit_proportions_to(target, spec.proportions, intermediate_sizes, seed);
  const auto [least, most] = fit_parameter_range(target.measure);
  struct Tried {
    double t, percent;
    std::vector<LibraryGrain> grains;
  };
  const auto attempt = [&](double t) {
    std::vector<LibraryGrain> grains =
        draw_templates(spec, fitted_distribution(target.measure, spec.proportions, t), seed, counter);
    const double percent = library_percent(grains, target, intermediate_sizes);
    return Tried{t, percent, std::move(grains)};
  };
  Tried best = attempt(fit.parameter);
  const auto closer = [&](Tried tried) {
    if (std::abs(tried.percent - target.percent) < std::abs(best.percent - target.percent)) best = std::move(tried);
  };
  // Step away from the ideal fit until the target lies between the two ends.
  double inner = best.t, outer = best.t;
  const double direction = best.percent > target.percent ? 1.0 : -1.0;  // too many counted: rounder, larger t
  for (double step = kSmallestStep; std::abs(best.percent - target.percent) > 0.5; step *= 2.0) {
    outer = std::clamp(inner + direction * step, least, most);
    Tried tried = attempt(outer);
    const bool crossed = (tried.percent - target.percent) * direction <= 0.0;
    closer(std::move(tried));
    if (crossed || outer == least || outer == most) break;
    inner = outer;
  }
  for (int bisection = 0; bisection < kBisections && std::abs(best.percent - target.percent) > 0.5; ++bisection) {
    const double middle = 0.5 * (inner + outer);
    Tried tried = attempt(middle);
    ((tried.percent - target.percent) * direction > 0.0 ? inner : outer) = middle;
    closer(std::move(tried));
  }
  fit.distribution = fitted_distribution(target.measure, spec.proportions, best.t);
  fit.parameter = best.t;
  fit.achieved_percent = best.percent;
  fit.reached = std::abs(best.percent - target.percent) <= 1.0;
  if (!fit.reached)
    throw InputError(fmt::format("a {} of {:.3g} % cannot be had from these proportions and sizes (the closest is "
                                 "{:.3g} %; each of the {} templates counts or not, so few sizes move the "
                                 "percentage in steps): give more templates, or widen the spreads of elongation and "
                                 "flatness",
                                 measure_name(target.measure), target.percent, fit.achieved_percent, spec.templates));
  library.distribution = fit.distribution;
  library.fit = fit;
  library.grains = std::move(best.grains);
  return library;
}

std::vector<double> library_fit_sizes(std::vector<double> sizes) {
  std::sort(sizes.begin(), sizes.end());
  constexpr std::size_t kFitSizes = 256;
  if (sizes.size() <= kFitSizes) return sizes;
  std::vector<double> quantiles;
  for (std::size_t k = 0; k < kFitSizes; ++k) quantiles.push_back(sizes[(2 * k + 1) * sizes.size() / (2 * kFitSizes)]);
  return quantiles;
}

std::vector<GrainMeasure> measure_library(const GrainLibrary& library, std::span<const double> intermediate_sizes) {
  return measure_templates(library.grains, intermediate_sizes);
}

GrainMeasure measure_body(const ParticleStore& particles, std::size_t b) {
  Vec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  const RigidBodies& bodies = particles.bodies;
  for (std::uint32_t i = bodies.first_member[b]; i < bodies.first_member[b] + bodies.member_count[b]; ++i) {
    const Vec3& c = particles.body_offset[i];
    const double r = particles.radius[i];
    lo = {std::min(lo.x, c.x - r), std::min(lo.y, c.y - r), std::min(lo.z, c.z - r)};
    hi = {std::max(hi.x, c.x + r), std::max(hi.y, c.y + r), std::max(hi.z, c.z + r)};
  }
  double extent[3] = {hi.x - lo.x, hi.y - lo.y, hi.z - lo.z};
  std::sort(extent, extent + 3);
  return {extent[2], extent[1], extent[0], bodies.mass[b]};
}

GrainMeasure measure_grain(const LibraryGrain& grain, double width, double density) {
  const double scale = width / grain.grain.dimensions.width;  // L = 1 in the template
  return {scale * grain.grain.dimensions.length, width, scale * grain.grain.dimensions.thickness,
          density * grain.grain.mass.volume * scale * scale * scale};
}

}  // namespace aggpack
