#pragma once
#include <string>

#include "aggpack/core/particle_store.hpp"

namespace aggpack {

// VTK XML PolyData (ASCII): one vertex per sphere, point arrays radius, diameter and id.
// In ParaView: Glyph filter, glyph type Sphere, scale array "diameter", scale factor 1
// (the glyph sphere has diameter 1).
std::string particles_vtp(const ParticleStore& particles);

}  // namespace aggpack
