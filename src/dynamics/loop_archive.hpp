#pragma once
// How the dynamics' resumable loops go into a checkpoint (src/core/archive.hpp): each lists its
// fields, and a new field of a loop must be added here (the resume tests compare a resumed
// run's every output with an uninterrupted one's).
#include "aggpack/dynamics/pour.hpp"
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

}  // namespace aggpack
