#pragma once
#include <string>
#include <string_view>

#include "aggpack/core/particle_store.hpp"

namespace aggpack {

// VTK XML PolyData (ASCII): one vertex per sphere, point arrays radius, diameter and id.
// In ParaView: Glyph filter, glyph type Sphere, scale array "diameter", scale factor 1
// (the glyph sphere has diameter 1).
// `provenance` (version, scenario, seed) goes into an XML comment.
std::string particles_vtp(const ParticleStore& particles, std::string_view provenance);

}  // namespace aggpack
