#include "aggpack/run/reports.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include <fmt/format.h>

namespace aggpack {

DepositionReport& DepositionReport::operator+=(const DepositionReport& layer) {
  requested += layer.requested;
  DepositionStats& s = stats;
  const DepositionStats& t = layer.stats;
  s.placed += t.placed;
  s.events += t.events;
  s.redrops += t.redrops;
  s.ties_on_top += t.ties_on_top;
  s.ties_on_ridge += t.ties_on_ridge;
  s.resting_on_floor += t.resting_on_floor;
  s.resting_on_three += t.resting_on_three;
  s.touching_a_wall += t.touching_a_wall;
  s.max_events_one_sphere = std::max(s.max_events_one_sphere, t.max_events_one_sphere);
  s.end = t.end;  // the last layer's
  wall_clock_s += layer.wall_clock_s;
  return *this;
}

double SettlingReport::simulated_time() const {
  double t = 0.0;
  for (const SettlingRun& r : runs) t += r.simulated_time;
  return t;
}

std::size_t SettlingReport::steps() const {
  std::size_t n = 0;
  for (const SettlingRun& r : runs) n += r.steps;
  return n;
}

std::size_t SettlingReport::neighbour_list_builds() const {
  std::size_t n = 0;
  for (const SettlingRun& r : runs) n += r.neighbour_list_builds;
  return n;
}

double SettlingReport::wall_clock_s() const {
  double t = 0.0;
  for (const SettlingRun& r : runs) t += r.wall_clock_s;
  return t;
}

double SettlingReport::particle_steps_per_second() const {
  double particle_steps = 0.0;
  for (const SettlingRun& r : runs) particle_steps += r.particle_steps_per_second * r.wall_clock_s;
  const double seconds = wall_clock_s();
  return seconds > 0 ? particle_steps / seconds : 0.0;
}

double SettlingReport::memory_bytes_per_particle() const {
  double m = 0.0;
  for (const SettlingRun& r : runs) m = std::max(m, r.memory_bytes_per_particle);
  return m;
}

std::size_t SettlingReport::runs_ended_by_max_time() const {
  return static_cast<std::size_t>(
      std::count_if(runs.begin(), runs.end(), [](const SettlingRun& r) { return r.ended_by == SettleEnd::MaxTime; }));
}

nlohmann::json to_json(const DepositionReport& r) {
  const DepositionStats& st = r.stats;
  nlohmann::json j;
  j["method"] = "drop_and_roll";
  j["particles_requested"] = r.requested;
  j["particles_placed"] = st.placed;
  j["particles_not_placed"] = r.requested - st.placed;
  j["end"] = to_string(st.end);
  j["fill_height_m"] = r.fill_height;
  j["events"] = st.events;
  j["events_per_particle"] = st.placed ? static_cast<double>(st.events) / static_cast<double>(st.placed) : 0.0;
  j["max_events_one_particle"] = st.max_events_one_sphere;
  j["redrops"] = st.redrops;
  j["ties"] = {{"on_top", st.ties_on_top}, {"on_ridge", st.ties_on_ridge}};
  j["supports"] = {{"floor", st.resting_on_floor}, {"three", st.resting_on_three}, {"touching_a_wall", st.touching_a_wall}};
  j["wall_clock_s"] = r.wall_clock_s;
  j["particles_per_second"] = r.wall_clock_s > 0 ? static_cast<double>(st.placed) / r.wall_clock_s : 0.0;
  if (r.layers > 1) j["layers"] = r.layers;
  return j;
}

nlohmann::json to_json(const PourReport& r) {
  nlohmann::json j = {{"method", "random_gas"},
                      {"particles_poured", r.poured},
                      {"batches", r.batches},
                      {"solid_fraction", r.solid_fraction},
                      {"velocity_m_s", r.velocity},
                      {"gap_m", r.gap},
                      {"lowest_slab_bottom_m", r.lowest_slab_bottom},
                      {"highest_slab_top_m", r.highest_slab_top},
                      {"insertion_wall_clock_s", r.insertion_wall_clock_s}};
  if (r.release_height) j["release_height_m"] = *r.release_height;
  return j;
}

namespace {
nlohmann::json or_null(double v) { return std::isnan(v) ? nlohmann::json() : nlohmann::json(v); }
std::string shown(double d) { return std::isnan(d) ? std::string("-") : fmt::format("{:.4f}", d); }
}  // namespace

nlohmann::json to_json(const RoddingReport& r) {
  nlohmann::json depths = nlohmann::json::array(), lowest = nlohmann::json::array(),
                 forces = nlohmann::json::array();
  std::size_t stopped = 0;
  for (const RodStroke& s : r.stroke_records) {
    depths.push_back(s.depth);
    lowest.push_back(s.tip_lowest);
    forces.push_back(s.peak_force);
    stopped += s.stopped_by_force ? 1 : 0;
  }
  nlohmann::json j = {{"strokes", r.strokes},
                      {"rod_diameter_m", r.rod_diameter},
                      {"speed_m_s", r.speed},
                      {"depth", std::string(name_of(kRodDepthNames, r.depth_mode))},
                      {"target_tip_lowest_m", r.target_tip},
                      {"tip_lowest_of_each_stroke_m", lowest},
                      {"depth_of_each_stroke_m", depths},
                      {"strokes_stopped_by_force", stopped},
                      {"peak_force_of_each_stroke_n", forces},
                      {"density_before", or_null(r.density_before)},
                      {"density_after", or_null(r.density_after)},
                      {"simulated_time_s", r.simulated_time},
                      {"steps", r.steps},
                      {"time_step_s", r.time_step},
                      {"wall_clock_s", r.wall_clock_s}};
  if (r.continues_dem_system) j["continues_dem_system"] = true;
  return j;
}

nlohmann::json to_json(const JigReport& r) {
  nlohmann::json densities = nlohmann::json::array();
  for (const TapSample& s : r.samples) densities.push_back(or_null(s.density));
  nlohmann::json j = {{"drops", r.drops},
                      {"height_m", r.height},
                      {"lift_acceleration_m_s2", r.lift_acceleration},
                      {"impact_speed_m_s", r.impact_speed},
                      {"rest_time_s", r.rest_time},
                      {"rest_until_quiet", r.rest_until_quiet},
                      {"density_before", or_null(r.density_before)},
                      {"density_after_each_drop", densities},
                      {"simulated_time_s", r.simulated_time},
                      {"steps", r.steps},
                      {"time_step_s", r.time_step},
                      {"wall_clock_s", r.wall_clock_s}};
  if (r.continues_dem_system) j["continues_dem_system"] = true;
  return j;
}

std::string console_line(const TapReport& t) {
  return fmt::format("  tapping: {} taps at Gamma {:g} ({:g} Hz), density {} -> {}, {:.3g} s simulated, {:.3g} s wall\n",
                     t.taps, t.intensity, t.frequency, shown(t.density_before),
                     shown(t.samples.empty() ? std::nan("") : t.samples.back().density), t.simulated_time,
                     t.wall_clock_s);
}

// What a tapping step's numbers depend on.
std::string modelling_note(const TapReport& t) {
  return fmt::format(
        "tapping: {} taps, each the container (floor and walls together) moved up and back through half a sine "
        "period of {:g} Hz (amplitude {:.3g} m, peak acceleration Gamma = {:g} g, then stopped dead), followed by a "
        "rest of {:g} s{}; the density is measured after each rest (taps.csv). The compaction depends on this "
        "protocol (intensity, frequency, rest) as a lab's tapped density does{}",
        t.taps, t.frequency, t.amplitude, t.intensity, t.rest_time,
        t.rest_until_quiet ? " at most (less once the bed was quiet)" : "",
        t.lammps_ranks > 0 ? fmt::format("; run by LAMMPS ({} rank{}), the container a moving region of fix "
                                         "wall/gran/region whose velocity LAMMPS takes from the change of position "
                                         "over a step (aggpack: the exact derivative)",
                                         t.lammps_ranks, t.lammps_ranks == 1 ? "" : "s")
                           : std::string());
}

std::string console_line(const RoddingReport& r) {
  double peak = 0.0;
  for (const RodStroke& s : r.stroke_records) peak = std::max(peak, s.peak_force);
  return fmt::format("  rodding: {} strokes of a {:g} mm rod at {:g} m/s ({}), largest force {:.3g} N, density {} -> {}, "
                     "{:.3g} s simulated, {:.3g} s wall\n",
                     r.strokes, 1e3 * r.rod_diameter, r.speed, name_of(kRodDepthNames, r.depth_mode), peak,
                     shown(r.density_before), shown(r.density_after), r.simulated_time, r.wall_clock_s);
}

std::string console_line(const JigReport& r) {
  return fmt::format("  jigging: {} drops from {:.3g} m (impact {:.3g} m/s), density {} -> {}, {:.3g} s simulated, "
                     "{:.3g} s wall\n",
                     r.drops, r.height, r.impact_speed, shown(r.density_before),
                     shown(r.samples.empty() ? std::nan("") : r.samples.back().density), r.simulated_time,
                     r.wall_clock_s);
}

std::string modelling_note(const RoddingReport& r) {
  return fmt::format(
      "rodding: {} strokes of a {:g} mm rod with a hemispherical tip, spread evenly over the bed's section, each from "
      "just above the bed's top down to {} m ({}) and back at {:g} m/s; the rod is driven along its path whatever the "
      "bed's resistance (an infinitely massive body with the walls' contact coefficients, its force recorded in "
      "rod_strokes.csv) unless the bed pushes back with more than rodding.max_force, where the stroke stops short; "
      "moved between strokes above the bed; a hand's stroke, which slows where the bed resists, is not modelled",
      r.strokes, 1e3 * r.rod_diameter, r.target_tip,
      r.depth_mode == RodDepth::Floor ? "the floor less its clearance" : "into the layer below", r.speed);
}

std::string modelling_note(const JigReport& r) {
  return fmt::format(
      "jigging: {} drops, each the container (floor and walls together) lifted {:.3g} m at {:g} m/s^2 and dropped "
      "in free fall onto its base, where it stops dead (impact {:.3g} m/s = sqrt(2 g h)), then a rest of {:g} s{}; "
      "ASTM C29 raises one side at a time and the measure pivots on the other, so most of its floor falls less: "
      "the level drop from the full height is the raised side's, an upper bound on the energy per drop",
      r.drops, r.height, r.lift_acceleration, r.impact_speed, r.rest_time,
      r.rest_until_quiet ? " at most (less once the bed was quiet)" : "");
}

nlohmann::json to_json(const TapReport& r) {
  nlohmann::json densities = nlohmann::json::array();
  for (const TapSample& s : r.samples) densities.push_back(or_null(s.density));
  nlohmann::json j = {{"taps", r.taps},
          {"intensity", r.intensity},
          {"frequency_hz", r.frequency},
          {"amplitude_m", r.amplitude},
          {"rest_time_s", r.rest_time},
          {"rest_until_quiet", r.rest_until_quiet},
          {"density_before", or_null(r.density_before)},
          {"density_after_each_tap", densities},
          {"simulated_time_s", r.simulated_time},
          {"steps", r.steps},
          {"time_step_s", r.time_step},
          {"wall_clock_s", r.wall_clock_s}};
  if (r.continues_dem_system) j["continues_dem_system"] = true;
  if (r.lammps_ranks > 0) {
    j["engine"] = "lammps";
    j["lammps_ranks"] = r.lammps_ranks;
  }
  return j;
}

namespace {
// A run's last sample: what the bed was like when it stopped.
nlohmann::json final_sample_json(const SettleSample& s) {
  return {{"density", std::isnan(s.density) ? nlohmann::json() : nlohmann::json(s.density)},
          {"translational_energy_per_particle_mgd", s.translational_per_particle_mgd},
          {"mean_overlap_rel", s.contacts.mean_overlap},
          {"max_overlap_rel", s.contacts.max_overlap},
          {"coordination", s.contacts.coordination}};
}
}  // namespace

nlohmann::json to_json(const SettlingRun& r) {
  nlohmann::json j;
  j["layer"] = r.layer;
  j["particles_settled"] = r.particles_settled;
  j["particles_frozen"] = r.particles_frozen;
  j["ended_by"] = std::string(settle_end_name(r.ended_by));
  j["simulated_time_s"] = r.simulated_time;
  j["steps"] = r.steps;
  j["time_step_s"] = r.time_step;
  j["rayleigh_time_s"] = r.rayleigh_time;
  j["time_step_source"] = r.time_step_from_scenario ? "scenario" : "time_step_safety x Rayleigh time";
  j["skin_m"] = r.skin;
  j["neighbour_list_builds"] = r.neighbour_list_builds;
  j["final"] = final_sample_json(r.last);
  j["wall_clock_s"] = r.wall_clock_s;
  j["particle_steps_per_second"] = r.particle_steps_per_second;
  j["threads"] = r.threads;
  j["steps_on_fewer_threads"] = r.steps_on_fewer_threads;
  j["memory_bytes_per_particle"] = r.memory_bytes_per_particle;
  if (r.continues_dem_system) j["continues_dem_system"] = true;
  if (r.lammps_ranks > 0) {
    j["engine"] = "lammps";
    j["lammps_ranks"] = r.lammps_ranks;
  }
  return j;
}

// The stage's keys are the first run's, with counts and times added up over the runs and
// what describes the end (ended_by, final, the particle counts) taken from the last.
nlohmann::json to_json(const SettlingReport& report) {
  nlohmann::json total = to_json(report.runs.front());
  total.erase("layer");
  total["runs"] = nlohmann::json::array();
  for (const SettlingRun& r : report.runs) total["runs"].push_back(to_json(r));
  total["runs_ended_by_max_time"] = report.runs_ended_by_max_time();
  if (report.runs.size() == 1) return total;
  const SettlingRun& last = report.runs.back();
  total["steps"] = report.steps();
  std::size_t on_fewer = 0;
  for (const SettlingRun& r : report.runs) on_fewer += r.steps_on_fewer_threads;
  total["steps_on_fewer_threads"] = on_fewer;
  total["neighbour_list_builds"] = report.neighbour_list_builds();
  total["simulated_time_s"] = report.simulated_time();
  total["wall_clock_s"] = report.wall_clock_s();
  total["ended_by"] = std::string(settle_end_name(last.ended_by));
  total["final"] = final_sample_json(last.last);
  total["particles_settled"] = last.particles_settled + last.particles_frozen;
  total["particles_frozen"] = 0;
  total["memory_bytes_per_particle"] = report.memory_bytes_per_particle();
  total["particle_steps_per_second"] = report.particle_steps_per_second();
  return total;
}

}  // namespace aggpack
