#include "aggpack/io/vtk.hpp"
#include "aggpack/io/vtk_compress.hpp"

#include <algorithm>
#include <bit>
#include <cstring>
#include <stdexcept>
#include <variant>

#include <fmt/format.h>
#include <zlib.h>

#include "aggpack/core/xml_text.hpp"

namespace aggpack {

namespace {

// Uncompressed bytes per zlib block: VTK's own writer's block size, so that a reader's
// memory for one block is what it expects.
constexpr std::size_t kBlockSize = 32768;

// One DataArray: its VTK word type, name (empty for the points), components and values.
struct Array {
  const char* type;
  std::string name;
  int components = 1;
  std::variant<std::vector<double>, std::vector<std::int64_t>, std::vector<std::int32_t>> values;
};

// VTK's compressed layout (vtkXMLWriter::CreateCompressionHeader): UInt64 header
// [number of blocks, uncompressed block size, uncompressed size of the last block (0 when
// it is full), compressed size of each block], then the blocks, each one zlib stream.
void append_compressed(std::string& out, const void* data, std::size_t size) {
  const std::size_t last = size % kBlockSize;
  const std::size_t blocks = size / kBlockSize + (last ? 1 : 0);
  std::vector<std::uint64_t> header{blocks, kBlockSize, last};
  std::string packed;
  const auto* bytes = static_cast<const Bytef*>(data);
  for (std::size_t b = 0; b < blocks; ++b) {
    const std::size_t length = std::min(kBlockSize, size - b * kBlockSize);
    uLongf packed_size = compressBound(static_cast<uLong>(length));
    const std::size_t at = packed.size();
    packed.resize(at + packed_size);
    if (compress2(reinterpret_cast<Bytef*>(packed.data() + at), &packed_size, bytes + b * kBlockSize,
                  static_cast<uLong>(length), Z_DEFAULT_COMPRESSION) != Z_OK)
      throw std::runtime_error("particles.vtp: zlib compression failed");
    packed.resize(at + packed_size);
    header.push_back(packed_size);
  }
  out.append(reinterpret_cast<const char*>(header.data()), header.size() * sizeof(std::uint64_t));
  out += packed;
}

}  // namespace

void append_vtk_zlib_blocks(std::string& out, const void* data, std::size_t size) {
  append_compressed(out, data, size);
}

namespace {

std::vector<Array> vtp_arrays(const ParticleStore& particles, const VtpPointArrays& extra) {
  const std::size_t n = particles.size();
  const auto check_length = [n](std::span<const std::int32_t> values, const char* name) {
    if (!values.empty() && values.size() != n)
      throw std::invalid_argument(
          fmt::format("particles_vtp: {} values of \"{}\" for {} spheres", values.size(), name, n));
  };
  check_length(extra.coordination, "coordination");
  check_length(extra.component, "component");
  check_length(extra.material, "material");
  check_length(extra.grain, "grain");
  std::vector<double> diameter(n), velocity, points;
  // ids 1..N, the numbering of particles.csv and of LAMMPS; the connectivity is 0-based.
  std::vector<std::int64_t> ids(n), connectivity(n), offsets(n);
  velocity.reserve(3 * n);
  points.reserve(3 * n);
  for (std::size_t i = 0; i < n; ++i) {
    diameter[i] = 2.0 * particles.radius[i];
    ids[i] = static_cast<std::int64_t>(i + 1);
    connectivity[i] = static_cast<std::int64_t>(i);
    offsets[i] = static_cast<std::int64_t>(i + 1);
    const Vec3 &v = particles.velocity[i], &p = particles.position[i];
    velocity.insert(velocity.end(), {v.x, v.y, v.z});
    points.insert(points.end(), {p.x, p.y, p.z});
  }
  std::vector<Array> arrays;
  arrays.push_back({"Float64", "radius", 1, particles.radius});
  arrays.push_back({"Float64", "diameter", 1, std::move(diameter)});
  arrays.push_back({"Int64", "id", 1, std::move(ids)});
  arrays.push_back({"Float64", "velocity", 3, std::move(velocity)});
  if (!extra.coordination.empty())
    arrays.push_back({"Int32", "coordination", 1, std::vector<std::int32_t>(extra.coordination.begin(),
                                                                             extra.coordination.end())});
  if (!extra.component.empty())
    arrays.push_back(
        {"Int32", "component", 1, std::vector<std::int32_t>(extra.component.begin(), extra.component.end())});
  if (!extra.material.empty())
    arrays.push_back({"Int32", "material", 1, std::vector<std::int32_t>(extra.material.begin(), extra.material.end())});
  if (!extra.grain.empty())
    arrays.push_back({"Int32", "grain", 1, std::vector<std::int32_t>(extra.grain.begin(), extra.grain.end())});
  arrays.push_back({"Float64", "", 3, std::move(points)});
  arrays.push_back({"Int64", "connectivity", 1, std::move(connectivity)});
  arrays.push_back({"Int64", "offsets", 1, std::move(offsets)});
  return arrays;
}

}  // namespace

std::string particles_vtp(const ParticleStore& particles, std::string_view provenance, VtpEncoding encoding,
                          const VtpPointArrays& extra) {
  const std::size_t n = particles.size();
  const std::vector<Array> arrays = vtp_arrays(particles, extra);
  const std::size_t point_data = arrays.size() - 3;  // the last three: points, connectivity, offsets
  const bool binary = encoding == VtpEncoding::ZlibAppended;
  // The arrays are written in the machine's byte order, which the header declares.
  const char* byte_order = std::endian::native == std::endian::little ? "LittleEndian" : "BigEndian";

  fmt::memory_buffer out;
  auto o = std::back_inserter(out);
  fmt::format_to(o,
                 "<?xml version=\"1.0\"?>\n"
                 "<!-- {} -->\n"
                 "<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"{}\" header_type=\"UInt64\"{}>\n"
                 "  <PolyData>\n"
                 "    <Piece NumberOfPoints=\"{}\" NumberOfVerts=\"{}\" NumberOfLines=\"0\" NumberOfStrips=\"0\" "
                 "NumberOfPolys=\"0\">\n"
                 "      <PointData Scalars=\"radius\">\n",
                 xml_comment_text(provenance), byte_order, binary ? " compressor=\"vtkZLibDataCompressor\"" : "", n, n);
  std::string appended;
  for (std::size_t a = 0; a < arrays.size(); ++a) {
    const Array& array = arrays[a];
    if (a == point_data) fmt::format_to(o, "      </PointData>\n      <Points>\n");
    if (a == point_data + 1) fmt::format_to(o, "      </Points>\n      <Verts>\n");
    fmt::format_to(o, "        <DataArray type=\"{}\"", array.type);
    if (!array.name.empty()) fmt::format_to(o, " Name=\"{}\"", array.name);
    if (array.components > 1) fmt::format_to(o, " NumberOfComponents=\"{}\"", array.components);
    if (binary) {
      fmt::format_to(o, " format=\"appended\" offset=\"{}\"/>\n", appended.size());
      std::visit([&](const auto& v) { append_compressed(appended, v.data(), v.size() * sizeof(v[0])); }, array.values);
      continue;
    }
    fmt::format_to(o, " format=\"ascii\">\n");
    std::visit(
        [&](const auto& v) {
          // One sphere a line: its value, or its components separated by spaces.
          const auto k = static_cast<std::size_t>(array.components);
          for (std::size_t i = 0; i < v.size(); i += k) {
            fmt::format_to(o, "{}", v[i]);
            for (std::size_t c = 1; c < k; ++c) fmt::format_to(o, " {}", v[i + c]);
            fmt::format_to(o, "\n");
          }
        },
        array.values);
    fmt::format_to(o, "        </DataArray>\n");
  }
  fmt::format_to(o, "      </Verts>\n    </Piece>\n  </PolyData>\n");
  // The raw bytes start right after the underscore; the offsets above count from there.
  if (binary) fmt::format_to(o, "  <AppendedData encoding=\"raw\">\n   _{}\n  </AppendedData>\n", appended);
  fmt::format_to(o, "</VTKFile>\n");
  return fmt::to_string(out);
}

std::string particles_pvd(std::span<const PvdFrame> frames, std::string_view provenance) {
  bool increasing = true;
  for (std::size_t f = 1; f < frames.size(); ++f) increasing = increasing && frames[f].time > frames[f - 1].time;
  fmt::memory_buffer out;
  auto o = std::back_inserter(out);
  fmt::format_to(o,
                 "<?xml version=\"1.0\"?>\n"
                 "<!-- {} -->\n",
                 xml_comment_text(provenance));
  if (!increasing)
    fmt::format_to(o, "<!-- two beds share a simulated time: each timestep is the frame's number, and the simulated "
                      "times are in the comments -->\n");
  fmt::format_to(o,
                 "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
                 "  <Collection>\n");
  for (std::size_t f = 0; f < frames.size(); ++f) {
    const PvdFrame& frame = frames[f];
    fmt::format_to(o, "    <!-- {}: {} s simulated -->\n", xml_comment_text(frame.name), frame.time);
    if (increasing)
      fmt::format_to(o, "    <DataSet timestep=\"{}\" group=\"\" part=\"0\" file=\"{}\"/>\n", frame.time,
                     xml_escape(frame.file));
    else
      fmt::format_to(o, "    <DataSet timestep=\"{}\" group=\"\" part=\"0\" file=\"{}\"/>\n", f,
                     xml_escape(frame.file));
  }
  fmt::format_to(o, "  </Collection>\n</VTKFile>\n");
  return fmt::to_string(out);
}

}  // namespace aggpack
