#pragma once
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "aggpack/core/particle_store.hpp"

namespace aggpack {

// How the arrays of a VTP are stored. ZlibAppended: binary, zlib-compressed, in the file's
// <AppendedData> section (VTK's own writer's default; about a third of the ASCII size and
// six times faster to read for a bed of 300 000 spheres). Ascii: every value as text, for reading by eye or by a tool
// without zlib.
enum class VtpEncoding { ZlibAppended, Ascii };

// Per-sphere arrays the store does not hold, written beside the radius when given (an empty
// span leaves the array out); each has one value per sphere, in store order.
struct VtpPointArrays {
  std::span<const std::int32_t> coordination;  // sphere-sphere contacts of each sphere
  std::span<const std::int32_t> component;     // which part of the size specification it came from
  std::span<const std::int32_t> material;      // the index of its material (summary.json names them)
  std::span<const std::int32_t> grain;         // its rigid grain's id in grains.csv (1-based), 0: none
};

// VTK XML PolyData: one vertex per sphere, point arrays radius, diameter, id, velocity (m/s,
// 3 components), and coordination, component, material and grain when given.
// In ParaView: Glyph filter, glyph type Sphere, scale array "diameter", scale factor 1
// (the glyph sphere has diameter 1).
// `provenance` (version, scenario, seed) goes into an XML comment. The bytes depend only on
// the arguments (no time, no thread count).
std::string particles_vtp(const ParticleStore& particles, std::string_view provenance,
                          VtpEncoding encoding = VtpEncoding::ZlibAppended, const VtpPointArrays& extra = {});

// One file of a ParaView data collection (.pvd): a bed at a simulated time.
struct PvdFrame {
  double time = 0.0;  // s of simulated time since the run's DEM began
  std::string file;   // relative to the .pvd's folder
  std::string name;   // what the bed is ("deposited", "final", ...), an XML comment beside it
};
// A .pvd that lists `frames` in order, so that ParaView opens them as one series and its
// Animation View steps through them. Each frame's timestep is its simulated time when the
// times increase strictly; when two beds share one (two snapshots with no DEM between),
// ParaView could not tell them apart, so every frame's timestep is then its number (0, 1,
// ...) and the times are in comments.
std::string particles_pvd(std::span<const PvdFrame> frames, std::string_view provenance);

}  // namespace aggpack
