#include "aggpack/io/vtk.hpp"

#include <fmt/format.h>

#include "aggpack/core/xml_text.hpp"

namespace aggpack {

std::string particles_vtp(const ParticleStore& particles, std::string_view provenance) {
  const std::size_t n = particles.size();
  fmt::memory_buffer out;
  auto o = std::back_inserter(out);
  fmt::format_to(o,
                 "<?xml version=\"1.0\"?>\n"
                 "<!-- {} -->\n"
                 "<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
                 "  <PolyData>\n"
                 "    <Piece NumberOfPoints=\"{}\" NumberOfVerts=\"{}\" NumberOfLines=\"0\" NumberOfStrips=\"0\" "
                 "NumberOfPolys=\"0\">\n"
                 "      <PointData Scalars=\"radius\">\n",
                 xml_comment_text(provenance), n, n);
  const auto array = [&](const char* name, auto&& value) {
    fmt::format_to(o, "        <DataArray type=\"Float64\" Name=\"{}\" format=\"ascii\">\n", name);
    for (std::size_t i = 0; i < n; ++i) fmt::format_to(o, "{}\n", value(i));
    fmt::format_to(o, "        </DataArray>\n");
  };
  array("radius", [&](std::size_t i) { return particles.radius[i]; });
  array("diameter", [&](std::size_t i) { return 2.0 * particles.radius[i]; });
  fmt::format_to(o, "        <DataArray type=\"Int64\" Name=\"id\" format=\"ascii\">\n");
  for (std::size_t i = 0; i < n; ++i) fmt::format_to(o, "{}\n", i);
  fmt::format_to(o,
                 "        </DataArray>\n"
                 "      </PointData>\n"
                 "      <Points>\n"
                 "        <DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n");
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3& p = particles.position[i];
    fmt::format_to(o, "{} {} {}\n", p.x, p.y, p.z);
  }
  fmt::format_to(o,
                 "        </DataArray>\n"
                 "      </Points>\n"
                 "      <Verts>\n"
                 "        <DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n");
  for (std::size_t i = 0; i < n; ++i) fmt::format_to(o, "{}\n", i);
  fmt::format_to(o,
                 "        </DataArray>\n"
                 "        <DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n");
  for (std::size_t i = 0; i < n; ++i) fmt::format_to(o, "{}\n", i + 1);
  fmt::format_to(o,
                 "        </DataArray>\n"
                 "      </Verts>\n"
                 "    </Piece>\n"
                 "  </PolyData>\n"
                 "</VTKFile>\n");
  return fmt::to_string(out);
}

}  // namespace aggpack
