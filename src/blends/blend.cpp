// CPM of a blend of materials, class by class at each material's betas.
#include "aggpack/blends/blend.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "aggpack/core/error.hpp"
#include "aggpack/core/text.hpp"

namespace aggpack {

namespace {

constexpr double kMm = 1e-3;

// Every class of every material, coarse first, with its beta and whose it is.
struct BlendClasses {
  ModelDistribution distribution;
  std::vector<double> beta, beta_sd;
  std::vector<std::string> label;
};

BlendClasses blend_classes(std::span<const MaterialBetas> materials, std::span<const double> fractions) {
  struct Entry {
    ModelClass c;
    double beta, sd;
    std::string label;
  };
  std::vector<Entry> entries;
  for (std::size_t m = 0; m < materials.size(); ++m) {
    if (fractions[m] == 0.0) continue;
    for (const ClassBeta& k : materials[m].classes)
      entries.push_back({{k.diameter, k.d_lo, k.d_hi, fractions[m] * k.volume_fraction, m > 0},
                         k.beta,
                         k.beta_sd,
                         fmt::format("{}, {:g}-{:g} mm", materials[m].material, k.d_lo / kMm, k.d_hi / kMm)});
  }
  std::stable_sort(entries.begin(), entries.end(),
                   [](const Entry& a, const Entry& b) { return a.c.diameter > b.c.diameter; });
  BlendClasses out;
  for (Entry& e : entries) {
    out.distribution.classes.push_back(e.c);
    out.beta.push_back(e.beta);
    out.beta_sd.push_back(e.sd);
    out.label.push_back(std::move(e.label));
  }
  return out;
}

std::vector<double> shifted(const BlendClasses& c, double sds) {
  std::vector<double> out(c.beta.size());
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = std::clamp(c.beta[i] + sds * c.beta_sd[i], 1e-3, 0.999);
  return out;
}

}  // namespace

void check_volume_fractions(std::size_t materials, std::span<const double> f) {
  if (materials == 0) throw InputError("a blend needs at least one material");
  if (f.size() != materials)
    throw InputError(fmt::format("{} fractions for {} materials; expected one a material", f.size(), materials));
  double sum = 0.0;
  for (const double x : f) {
    if (!(x >= 0.0 && x <= 1.0)) throw InputError(fmt::format("a volume fraction of {} is not between 0 and 1", x));
    sum += x;
  }
  if (std::abs(sum - 1.0) > 1e-6) throw InputError(fmt::format("the volume fractions sum to {:.6g}; expected 1", sum));
}

BlendPoint predict_blend(std::span<const MaterialBetas> materials, std::span<const double> fractions, double k,
                         const CpmInteraction& interaction) {
  check_volume_fractions(materials.size(), fractions);
  const BlendClasses c = blend_classes(materials, fractions);
  const CpmResult r = cpm(c.distribution, c.beta, k, interaction);
  BlendPoint p;
  p.volume_fractions.assign(fractions.begin(), fractions.end());
  p.packing = r.density;
  p.virtual_packing = r.virtual_density;
  p.dominant = c.label[r.dominant];
  p.packing_low = cpm(c.distribution, shifted(c, -1.0), k, interaction).density;
  p.packing_high = cpm(c.distribution, shifted(c, +1.0), k, interaction).density;
  for (std::size_t m = 0; m < materials.size(); ++m)
    p.particle_density_kg_m3 += fractions[m] * materials[m].particle_density_kg_m3;
  for (std::size_t m = 0; m < materials.size(); ++m)
    p.mass_fractions.push_back(fractions[m] * materials[m].particle_density_kg_m3 / p.particle_density_kg_m3);
  p.voids_percent = 100.0 * (1.0 - p.packing);
  p.bulk_density_kg_m3 = p.packing * p.particle_density_kg_m3;
  return p;
}

DensestBlend densest(std::span<const BlendPoint> curve) {
  if (curve.empty()) throw InputError("an empty curve has no densest blend");
  DensestBlend d;
  for (std::size_t i = 1; i < curve.size(); ++i)
    if (curve[i].packing > curve[d.index].packing) d.index = i;
  const BlendPoint& top = curve[d.index];
  // The contiguous runs around the densest point that meet each test.
  const auto run = [&](auto&& meets, std::size_t& first, std::size_t& last) {
    first = last = d.index;
    while (first > 0 && meets(curve[first - 1])) --first;
    while (last + 1 < curve.size() && meets(curve[last + 1])) ++last;
  };
  run([&](const BlendPoint& p) { return p.packing_high >= top.packing_low; }, d.spread_first, d.spread_last);
  run([&](const BlendPoint& p) { return p.packing >= top.packing - DensestBlend::kPlateau; }, d.plateau_first,
      d.plateau_last);
  return d;
}

std::vector<BlendPoint> sweep_binary(std::span<const MaterialBetas> materials, std::span<const double> percents,
                                     double k, const CpmInteraction& interaction) {
  if (materials.size() != 2)
    throw InputError(
        fmt::format("--sweep: a sweep takes two materials (the second's volume percent), {} given; "
                    "expected --fractions for more",
                    materials.size()));
  std::vector<BlendPoint> out;
  for (const double pc : percents) {
    if (!(pc >= 0.0 && pc <= 100.0)) throw InputError(fmt::format("--sweep: {} % is not between 0 and 100", pc));
    const double fractions[2] = {1.0 - pc / 100.0, pc / 100.0};
    out.push_back(predict_blend(materials, fractions, k, interaction));
  }
  return out;
}

std::vector<double> parse_sweep(const std::string& text, const std::string& option) {
  std::vector<std::string> parts{""};
  for (const char ch : text) {
    if (ch == ':')
      parts.emplace_back();
    else
      parts.back().push_back(ch);
  }
  const auto fail = [&](const std::string& why) {
    return InputError(
        fmt::format("{} {}: {}; expected FROM:TO:STEP in volume percent, e.g. 20:60:1", option, text, why));
  };
  if (parts.size() != 3) throw fail("not three numbers");
  double v[3];
  for (int i = 0; i < 3; ++i) {
    const std::optional<double> x = parse_finite_number(trim(parts[i]));
    if (!x) throw fail(fmt::format("'{}' is not a number", parts[i]));
    v[i] = *x;
  }
  if (!(v[2] > 0.0)) throw fail("the step is not positive");
  if (v[1] < v[0]) throw fail("TO is below FROM");
  const double n = std::floor((v[1] - v[0]) / v[2] + 1e-9) + 1.0;
  if (n > 10001.0) throw fail(fmt::format("{:.0f} points; at most 10001", n));
  std::vector<double> out;
  for (int i = 0; i < static_cast<int>(n); ++i) out.push_back(v[0] + i * v[2]);
  return out;
}

}  // namespace aggpack
