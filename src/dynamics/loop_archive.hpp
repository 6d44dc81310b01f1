#pragma once
// How the dynamics' resumable loops go into a checkpoint (src/core/archive.hpp): each lists its
// fields, and a new field of a loop must be added here (the resume tests compare a resumed
// run's every output with an uninterrupted one's).
#include "aggpack/dynamics/jig.hpp"
#include "aggpack/dynamics/pour.hpp"
#include "aggpack/dynamics/rod.hpp"
#include "aggpack/dynamics/settle.hpp"
#include "aggpack/dynamics/tap.hpp"
#include "core/archive.hpp"

namespace aggpack {

template <class Archive>
void serialize(Archive& ar, SettleSample& s) {
  ar(raw_value(s));
}
template <class Archive>
void serialize(Archive& ar, SettleLoop& l) {
  ar(l.start, l.start_steps, l.window, l.block_steps_left);
}
template <class Archive>
void serialize(Archive& ar, PourLoop& l) {
  ar(l.start, l.start_steps, l.batch, l.next, raw_value(l.rng), raw_value(l.report), l.weight, l.settling, l.settle,
     l.poured_at, l.pour_steps, l.block_steps_left);
}
template <class Archive>
void serialize(Archive& ar, TapReport& t) {
  ar(t.taps, t.intensity, t.frequency, t.amplitude, t.rest_time, t.rest_until_quiet, t.density_before, t.time_before,
     raw(t.samples), t.simulated_time, t.steps, t.time_step, t.wall_clock_s, t.lammps_ranks, t.continues_dem_system);
}
template <class Archive>
void serialize(Archive& ar, TapLoop& l) {
  ar(l.start, l.start_steps, l.tap, l.tap_steps_left, l.rest_end, l.rest_steps_left, l.quiet_since, l.last, l.report);
}
template <class Archive>
void serialize(Archive& ar, RoddingReport& r) {
  ar(r.strokes, r.rod_diameter, r.speed, raw_value(r.depth_mode), r.target_tip, r.density_before, r.density_after,
     r.time_before, raw(r.stroke_records), r.simulated_time, r.steps, r.time_step, r.wall_clock_s,
     r.continues_dem_system);
}
template <class Archive>
void serialize(Archive& ar, RodLoop& l) {
  ar(l.start, l.start_steps, l.stroke, raw_value(l.phase), l.steps_left, l.top, l.rest_end, l.rest_steps_left, l.quiet_since, l.last,
     raw(l.positions), l.report);
}
template <class Archive>
void serialize(Archive& ar, JigReport& j) {
  ar(j.drops, j.height, j.lift_acceleration, j.impact_speed, j.rest_time, j.rest_until_quiet, j.density_before,
     j.time_before, raw(j.samples), j.simulated_time, j.steps, j.time_step, j.wall_clock_s, j.continues_dem_system);
}
template <class Archive>
void serialize(Archive& ar, JigLoop& l) {
  ar(l.start, l.start_steps, l.drop, l.drop_steps_left, l.rest_end, l.rest_steps_left, l.quiet_since, l.last,
     l.report);
}

}  // namespace aggpack
