#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "aggpack/core/container.hpp"
#include "aggpack/core/enum_names.hpp"
#include "aggpack/dynamics/dem_system.hpp"
#include "aggpack/dynamics/settle.hpp"
#include "aggpack/dynamics/tap.hpp"

namespace aggpack {

// Rodding (ASTM C29 / AASHTO T 19, README "Rodding"): `strokes` strokes of a tamping rod with
// a hemispherical tip (DemSystem's RodTool), at points spread evenly over the bed's surface.
// Each stroke starts `start_gap` above the bed's top, descends at `speed` to its depth (or
// until the bed pushes back with more than `max_force`, the hand's push: then the stroke stops
// there) and withdraws at `speed` to where it started; the rod then moves to the next point
// above the bed (it touches nothing there, so it is taken out of the DEM for the time that
// move takes at `speed`). After the last stroke the bed rests for rest_time, or until quiet.
// The rod is driven: along its path it goes whatever the resistance, and only the force
// checked every half millimetre of descent stops it.
enum class RodDepth : std::uint8_t {
  Auto,        // to the floor when no layer is below the top one, else into the layer below
  Floor,       // the tip to `floor_clearance` above the floor (the bottom layer, "throughout its depth")
  LayerBelow,  // the tip `penetration` into the layer below (its top: RodTargets::layer_below)
};
inline constexpr std::array kRodDepthNames{EnumName<RodDepth>{RodDepth::Auto, "auto"},
                                           EnumName<RodDepth>{RodDepth::Floor, "floor"},
                                           EnumName<RodDepth>{RodDepth::LayerBelow, "layer_below"}};

struct RoddingSettings {
  std::size_t strokes = 25;
  double rod_diameter = 0.016;  // m (5/8 in)
  // m/s, of the rod's tip, down, up and across. A brisk hand stroke: 25 strokes through a layer
  // of about 0.1 m take about 15 s at the lab's pace, a metre a second while the rod moves. Slower
  // costs simulated time in proportion; the rod is driven, so the speed sets how fast the bed
  // must make way (and the peak force it takes).
  double speed = 1.0;
  RodDepth depth = RodDepth::Auto;
  double floor_clearance = 0.005;  // m, the tip's lowest point above the floor ("without forcibly striking")
  double penetration = 0.025;      // m into the layer below (AASHTO T 19: about 1 in)
  double wall_clearance = 0.005;   // m between the rod and the side walls
  double start_gap = 0.005;        // m between the tip and the bed's top where a stroke starts and ends
  // N, the largest push of the bed on the rod a stroke goes on against: a firm push of a hand
  // (about 20 kg-force). A grain caught under the tip would otherwise be crushed by a driven
  // rod ("without forcibly striking the bottom of the measure").
  double max_force = 200.0;
  double rest_time = 0.2;          // s after the last stroke, at most
  bool rest_until_quiet = true;    // end the rest early once the quiet criterion holds
};

// One stroke: where it went and what the bed gave back.
struct RodStroke {
  std::size_t stroke = 0;
  double x = 0.0, y = 0.0;       // m, the rod's axis
  double surface = 0.0;          // m, the bed's top (highest sphere top) when the stroke began
  double tip_lowest = 0.0;       // m, the tip's lowest point reached (its target, unless max_force stopped it)
  double depth = 0.0;            // m, of the lowest point below the bed's top
  double peak_force = 0.0;       // N, the largest force of the bed on the rod during the stroke
  bool stopped_by_force = false; // the bed pushed back with more than max_force before the target
};
struct RoddingReport {
  std::size_t strokes = 0;
  double rod_diameter = 0.0, speed = 0.0;
  RodDepth depth_mode = RodDepth::Auto;  // as chosen: Floor or LayerBelow
  double target_tip = 0.0;               // m, the tip's lowest point the strokes aim at
  double density_before = 0.0, density_after = 0.0;  // NaN when the boxes do not fit
  double time_before = 0.0;              // s, when the rodding began
  std::vector<RodStroke> stroke_records;
  double simulated_time = 0.0;  // s
  std::size_t steps = 0;
  double time_step = 0.0;
  double wall_clock_s = 0.0;
  bool continues_dem_system = false;  // the caller's: the DEM system of the step before went on
  [[nodiscard]] std::string csv() const;  // rod_strokes.csv
};

// The stroke positions: `count` points spread evenly over the container's cross-section less
// `margin` from every side wall (Vogel's sunflower spiral over a round section, a golden-ratio
// lattice over a rectangular one; which, the container's planes say). Deterministic.
std::vector<Vec3> rod_stroke_positions(const Container& container, std::size_t count, double margin);

// Where the strokes are sent: the floor and, when there is one, the top of the layer below the
// bed's top layer (the caller's: it knows the layers; layer_top() below). The tip's lowest
// point a stroke aims at.
struct RodTargets {
  double floor = 0.0;                 // m
  std::optional<double> layer_below;  // m, the level of the top of the layers below
};
// The level of the top of the store's particles of a layer below `below_layer`, resting on the
// floor at `floor`: twice their centres' mean height above it (a layer of even thickness has
// its centres' mean half way up; a rough top counts by its mean, not its highest grain).
// none when no particle is below.
std::optional<double> layer_top(const ParticleStore& particles, std::uint32_t below_layer, double floor);
[[nodiscard]] double rod_target_tip(const RoddingSettings& settings, const RodTargets& targets, RodDepth& mode);

// A rodding's loop (with the system's state, all it takes to continue it).
enum class RodPhase : std::uint8_t { StrokeStart, Descend, Withdraw, Transit, Rest };
struct RodLoop {
  double start = 0.0;
  std::size_t start_steps = 0;
  std::size_t stroke = 1;             // the stroke in progress (or just done, in the rest)
  RodPhase phase = RodPhase::StrokeStart;
  std::size_t steps_left = 0;         // of the descent, the withdrawal or the move in progress
  double top = 0.0;                   // m, the tip centre's height where the stroke began
  double rest_end = 0.0;              // s, the system's time when the rest ends
  std::size_t rest_steps_left = 0;
  std::optional<double> quiet_since;
  SettleSample last;
  std::vector<Vec3> positions;        // of the strokes
  RoddingReport report;
};

RodLoop begin_rodding(const DemSystem& system, const Container& container, const RoddingSettings& settings,
                      const RodTargets& targets, double density_before);
bool fits(const RodLoop& loop, const RoddingSettings& settings, const DemSystem& system);

// Rods the bed of `system` (its container `container`, at rest): `loop` is begin_rodding's or a
// restored one (`resumed`: the system restored with it), continued bit for bit. The hooks as a
// tapping's (the density after the rest). Fills loop.report but for its wall clock.
void rod(DemSystem& system, const ParticleStore& particles, const RoddingSettings& settings,
         const QuietCriterion& quiet, RodLoop& loop, const TapHooks& hooks);

// The highest sphere top of the store's particles of a layer below `below_layer` (every
// particle by default), m; -infinity when there is none.
double highest_top(const ParticleStore& particles, std::uint32_t below_layer = 0xFFFFFFFFu);

}  // namespace aggpack
