#include "aggpack/io/lammps_data.hpp"

#include <stdexcept>

#include <fmt/format.h>

namespace aggpack {

std::string lammps_data(const ParticleStore& particles, const Container& container, double density, double z_top) {
  const Box& b = container.bounds;
  for (std::size_t i = 0; i < particles.size(); ++i)
    if (particles.position[i].z + particles.radius[i] > z_top)
      throw std::invalid_argument("lammps_data: z_top is below a sphere's top");
  fmt::memory_buffer out;
  auto o = std::back_inserter(out);
  fmt::format_to(o, "aggpack bed for LAMMPS (atom_style sphere, SI units)\n\n{} atoms\n1 atom types\n\n",
                 particles.size());
  fmt::format_to(o, "{:.17g} {:.17g} xlo xhi\n{:.17g} {:.17g} ylo yhi\n{:.17g} {:.17g} zlo zhi\n\nAtoms # sphere\n\n",
                 b.lo.x, b.hi.x, b.lo.y, b.hi.y, b.lo.z, z_top);
  for (std::size_t i = 0; i < particles.size(); ++i) {
    const Vec3& p = particles.position[i];
    fmt::format_to(o, "{} 1 {:.17g} {:.17g} {:.17g} {:.17g} {:.17g}\n", i + 1, 2.0 * particles.radius[i], density, p.x,
                   p.y, p.z);
  }
  return fmt::to_string(out);
}

}  // namespace aggpack
