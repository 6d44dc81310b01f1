#pragma once
// How the run's reports go into a checkpoint (src/core/archive.hpp). Plain records go in as
// their bytes, so a new field of theirs is saved without a word here; the records holding
// vectors list their fields, and a new field of theirs must be added below (the resume tests
// compare a resumed run's every output with an uninterrupted one's).
#include "aggpack/run/run_report.hpp"
#include "core/archive.hpp"
#include "dynamics/loop_archive.hpp"

namespace aggpack {

template <class Archive>
void serialize(Archive& ar, LammpsExchange& x) {
  ar(x.direction, x.path, x.what, x.spheres);
}
template <class Archive>
void serialize(Archive& ar, SettlingReport& r) {
  ar(raw(r.runs));
}
template <class Archive>
void serialize(Archive& ar, DepositionReport& r) {
  ar(raw_value(r));
}
template <class Archive>
void serialize(Archive& ar, TimeSeries& t) {
  ar(raw(t.samples));
}
template <class Archive>
void serialize(Archive& ar, Profile& p) {
  ar(p.position, p.solid_fraction);
}
template <class Archive>
void serialize(Archive& ar, PackingReport& r) {
  ar(raw_value(r.bed), raw(r.density.boxes), r.density.mean, r.density.sd, r.coordination.mean,
     r.coordination.particles_counted, r.coordination.histogram, r.coordination.relative_tolerance, r.vertical, r.wall,
     r.wall_profile_z_lo, r.wall_profile_z_hi);
  // A cylinder's measure: a flag, then the plain record.
  bool has_measure = r.measure.has_value();
  ar(has_measure);
  if (!has_measure) r.measure.reset();
  else {
    if (!r.measure) r.measure.emplace();
    ar(raw_value(*r.measure));
  }
}
template <class Archive>
void serialize(Archive& ar, StageAnalysis& a) {
  ar(a.report, a.wall_clock_s);
}

}  // namespace aggpack
