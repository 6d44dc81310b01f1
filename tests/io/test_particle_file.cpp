#include "aggpack/io/particle_file.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "aggpack/core/error.hpp"
#include "aggpack/core/rng.hpp"

#include <fmt/format.h>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include "aggpack/io/vtk.hpp"

namespace aggpack {
namespace {

namespace fs = std::filesystem;

fs::path write_temp(const std::string& name, const std::string& text) {
  const fs::path f = fs::temp_directory_path() / ("aggpack_pf_" + std::to_string(::getpid()) + "_" + name);
  std::ofstream(f) << text;
  return f;
}

TEST(ParticleFile, CsvColumnsInAnyOrderWithDiameterAndUnits) {
  const auto f = write_temp("a.csv", "# made elsewhere\nid, Diameter ,z,y,x,extra\n0,2,3,2,1,foo\n\n1,1,6,5,4,bar\n");
  const ParticleStore p = read_particle_file(f, 0.0254, 1000.0);
  ASSERT_EQ(p.size(), 2u);
  EXPECT_DOUBLE_EQ(p.position[0].x, 0.0254);
  EXPECT_DOUBLE_EQ(p.position[0].z, 3 * 0.0254);
  EXPECT_DOUBLE_EQ(p.radius[0], 0.0254);
  EXPECT_DOUBLE_EQ(p.position[1].y, 5 * 0.0254);
  fs::remove(f);
}

TEST(ParticleFile, WhitespaceXyzr) {
  const auto f = write_temp("b.txt", "# x y z r\n1 2 3 0.5\n  4\t5 6 0.25 \n");
  const ParticleStore p = read_particle_file(f, 1.0, 1.0);
  ASSERT_EQ(p.size(), 2u);
  EXPECT_DOUBLE_EQ(p.radius[1], 0.25);
  EXPECT_DOUBLE_EQ(p.position[1].y, 5.0);
  fs::remove(f);
}

// Reading `text` as the file `name` fails with a message that contains `part`.
void expect_refused(const std::string& name, const std::string& text, const std::string& part) {
  const auto f = write_temp(name, text);
  try {
    read_particle_file(f, 1.0, 1.0);
    ADD_FAILURE() << "accepted: " << text;
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
  }
  fs::remove(f);
}

TEST(ParticleFile, WhitespaceRowsOfOtherThanFourNumbersAreRefused) {
  const auto refused = [](const std::string& text, const std::string& part) { expect_refused("w.txt", text, part); };
  // A LAMMPS dump body (id type x y z radius) was read as x y z r from its first four columns.
  refused("1 1 0.1 0.2 0.3 0.05\n2 1 0.4 0.5 0.6 0.05\n", "w.txt:1: expected exactly 4 numbers per row (x y z r), got 6");
  refused("1 2 3 0.5\n1 2 3 0.5 7\n", "w.txt:2: expected exactly 4 numbers per row (x y z r), got 5");
  refused("1 2 3\n", "w.txt:1: expected exactly 4 numbers per row (x y z r), got 3");
  refused("id type x y z radius\n1 1 0.1 0.2 0.3\n", "w.txt:2: expected 6 fields per row, as the header names, got 5");
  refused("id type x y z\n1 1 0.1 0.2 0.3\n", "w.txt:1: a whitespace-separated particle file needs a header");
}

TEST(ParticleFile, WhitespaceHeaderNamesTheColumns) {
  const auto f = write_temp("h.txt", "id type x y z radius\n1 1 0.1 0.2 0.3 0.05\n2 1 0.4 0.5 0.6 0.025\n");
  const ParticleStore p = read_particle_file(f, 1.0, 1.0);
  ASSERT_EQ(p.size(), 2u);
  EXPECT_DOUBLE_EQ(p.position[1].x, 0.4);
  EXPECT_DOUBLE_EQ(p.position[1].z, 0.6);
  EXPECT_DOUBLE_EQ(p.radius[1], 0.025);
  fs::remove(f);
}

TEST(ParticleFile, RoundTripThroughOurCsvIsExact) {
  ParticleStore p;
  p.add({0.1, 1.0 / 3.0, 2.0 / 7.0}, 0.0127, 1.0);
  p.add({1e-17, 5.5, 0.75}, 3e-5, 1.0);
  const auto f = write_temp("c.csv", particles_csv(p));
  const ParticleStore q = read_particle_file(f, 1.0, 1.0);
  ASSERT_EQ(q.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(q.position[i], p.position[i]);
    EXPECT_EQ(q.radius[i], p.radius[i]);
  }
  fs::remove(f);
}

// Editors on Windows start UTF-8 files with a byte order mark: every format is still known
// by its first line (a dump by "ITEM: TIMESTEP", a CSV by its header) and read.
TEST(ParticleFile, AUtf8ByteOrderMarkIsSkipped) {
  const std::string bom = "\xEF\xBB\xBF";
  const std::vector<std::pair<std::string, std::string>> files = {
      {"bom.dump", "ITEM: TIMESTEP\n5\nITEM: NUMBER OF ATOMS\n1\nITEM: BOX BOUNDS ff ff ff\n0 1\n0 1\n0 1\n"
                   "ITEM: ATOMS id x y z radius\n1 0.5 0.25 0.125 0.1\n"},
      {"bom.csv", "x,y,z,r\n0.5,0.25,0.125,0.1\n"},
      {"bom.data", "title\n\n1 atoms\n0 1 xlo xhi\n0 1 ylo yhi\n0 1 zlo zhi\n\nAtoms # sphere\n\n"
                   "1 1 0.2 2650 0.5 0.25 0.125\n"}};
  for (const auto& [name, text] : files) {
    SCOPED_TRACE(name);
    const fs::path f = write_temp(name, bom + text), plain = write_temp("no_" + name, text);
    const PackingFile read = read_packing_file(f, 1.0, 2650.0);
    EXPECT_EQ(read.format, read_packing_file(plain, 1.0, 2650.0).format);
    ASSERT_EQ(read.particles.size(), 1u);
    EXPECT_EQ(read.particles.position[0], (Vec3{0.5, 0.25, 0.125}));
    EXPECT_EQ(read.particles.radius[0], 0.1);
    fs::remove(f);
    fs::remove(plain);
  }
}

TEST(ParticleFile, ErrorsNameTheFileAndLine) {
  const auto expect_error = [](const std::string& text, const std::string& part) { expect_refused("e.csv", text, part); };
  expect_error("x,y,r\n1,2,3\n", "e.csv:1: a CSV particle file needs a header");
  expect_error("x,y,z,r\n1,2,3,0.5\n1,2,oops,0.5\n", "e.csv:3: field 3 (\"oops\") is not a number");
  expect_error("x,y,z,r\n1,2,3\n", "e.csv:2: expected 4 comma-separated fields");
  expect_error("1 2 3 -1\n", "e.csv:1: the radius must be positive");
  expect_error("# nothing\n", "no particles");
}

// The overlap check on its grid finds the same worst pair as a brute-force pass over all
// pairs, in a walled and in a periodic container (where pairs meet across the sides).
TEST(ParticleOverlaps, TheWorstPairMatchesBruteForce) {
  for (const bool periodic : {false, true}) {
    const Container container = Container::square(0.1, 0.1, periodic);
    Rng rng = make_rng(7, RngPurpose::Sizes);
    const auto unit = [](Rng& g) { return g.uniform(); };
    ParticleStore store;
    for (int k = 0; k < 400; ++k) {
      const double r = 0.002 + 0.004 * unit(rng);
      store.add({0.1 * unit(rng), 0.1 * unit(rng), r + 0.08 * unit(rng)}, r, 2650.0);
    }
    double worst = 0.0;
    for (std::size_t i = 0; i < store.size(); ++i)
      for (std::size_t j = 0; j < i; ++j) {
        const Vec3 d = container.minimum_image(store.position[i] - store.position[j]);
        const double depth = (store.radius[i] + store.radius[j] - std::sqrt(norm2(d))) /
                             std::min(store.radius[i], store.radius[j]);
        worst = std::max(worst, depth);
      }
    ASSERT_GT(worst, 0.1);  // random spheres do overlap: the comparison means something
    const PairOverlap found = check_particle_overlaps(store, container, 10.0, false, "random", 1e8);
    EXPECT_NEAR(found.depth_over_radius, worst, 1e-12) << (periodic ? "periodic" : "walls");
    // Below the worst depth, the same bed is refused, naming the pair.
    try {
      (void)check_particle_overlaps(store, container, 0.5 * worst, false, "random", 1e8);
      ADD_FAILURE() << "an overlap beyond the tolerance was accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(fmt::format("particles {} and {}", found.i, found.j)), std::string::npos)
          << e.what();
    }
  }
}

TEST(ParticleOverlaps, CoincidentSpheresAndHugeGridsAreRefused) {
  ParticleStore store;
  store.add({0.05, 0.05, 0.01}, 0.01, 2650.0);
  store.add({0.05, 0.05, 0.01}, 0.005, 2650.0);
  const Container box = Container::square(0.1, 0.1, false);
  EXPECT_THROW((void)check_particle_overlaps(store, box, 1.0, true, "same", 1e8), InputError);
  ParticleStore far;
  far.add({0.0, 0.0, 0.01}, 0.01, 2650.0);
  far.add({1e6, 1e6, 0.01}, 0.01, 2650.0);
  Container wide = Container::square(1e6 + 1.0, 0.1, false);
  EXPECT_THROW((void)check_particle_overlaps(far, wide, 0.25, false, "far", 1e8), InputError);
}

TEST(Vtk, ProvenanceCommentStaysValidXmlWhateverThePath) {
  ParticleStore p;
  p.add({1, 2, 3}, 0.5, 1.0);
  const std::string vtp = particles_vtp(p, "aggpack, scenario runs--old/a---b.toml-");
  const auto open = vtp.find("<!--"), close = vtp.find("-->", open + 4);
  ASSERT_NE(close, std::string::npos);
  const std::string body = vtp.substr(open + 4, close - open - 4);
  EXPECT_EQ(body.find("--"), std::string::npos) << body;
  EXPECT_NE(body.back(), '-') << body;
  EXPECT_NE(body.find("runs-=old/a-=-b.toml"), std::string::npos) << body;
}

TEST(Vtk, AsciiPolyDataHasRadiusDiameterIdAndVelocityArrays) {
  ParticleStore p;
  p.add({1, 2, 3}, 0.5, 1.0);
  p.velocity[0] = {0.25, -1, 0};
  const std::string vtp = particles_vtp(p, "aggpack test, seed 3", VtpEncoding::Ascii);
  EXPECT_NE(vtp.find("<!-- aggpack test, seed 3 -->"), std::string::npos);
  EXPECT_NE(vtp.find("type=\"PolyData\""), std::string::npos);
  EXPECT_NE(vtp.find("Name=\"radius\""), std::string::npos);
  EXPECT_NE(vtp.find("Name=\"diameter\""), std::string::npos);
  EXPECT_NE(vtp.find("Name=\"id\""), std::string::npos);
  EXPECT_NE(vtp.find("Name=\"velocity\" NumberOfComponents=\"3\" format=\"ascii\">\n0.25 -1 0\n"), std::string::npos);
  EXPECT_NE(vtp.find("NumberOfPoints=\"1\""), std::string::npos);
  EXPECT_NE(vtp.find("1 2 3\n"), std::string::npos);
  EXPECT_EQ(vtp.find("AppendedData"), std::string::npos);
  EXPECT_EQ(vtp.find("Name=\"coordination\""), std::string::npos);  // not given: left out
}

// The default: every array in the appended section, zlib-compressed, as VTK's own writer
// does (tests/tools/check_outputs.py decodes the bytes against particles.csv).
TEST(Vtk, BinaryPolyDataIsZlibAppendedWithTheGivenArrays) {
  ParticleStore p;
  for (int i = 0; i < 5000; ++i) p.add({0.01 * i, 0, 0}, 0.004, 2650.0);  // more than one 32 KiB block
  const std::vector<std::int32_t> coordination(p.size(), 2), component(p.size(), 1);
  const std::string vtp = particles_vtp(p, "t", VtpEncoding::ZlibAppended, {coordination, component, {}, {}});
  EXPECT_NE(vtp.find("header_type=\"UInt64\" compressor=\"vtkZLibDataCompressor\""), std::string::npos);
  EXPECT_NE(vtp.find("<DataArray type=\"Float64\" Name=\"radius\" format=\"appended\" offset=\"0\"/>"),
            std::string::npos);
  EXPECT_NE(vtp.find("<DataArray type=\"Int32\" Name=\"coordination\" format=\"appended\""), std::string::npos);
  EXPECT_NE(vtp.find("<DataArray type=\"Int32\" Name=\"component\" format=\"appended\""), std::string::npos);
  EXPECT_NE(vtp.find("<AppendedData encoding=\"raw\">\n   _"), std::string::npos);
  EXPECT_EQ(vtp.substr(vtp.size() - 30), "\n  </AppendedData>\n</VTKFile>\n");
  // The radius array: 40000 bytes, one full block of 32768 and one of 7232.
  const std::size_t data = vtp.find('_', vtp.find("<AppendedData")) + 1;
  std::uint64_t header[3];
  std::memcpy(header, vtp.data() + data, sizeof header);
  EXPECT_EQ(header[0], 2u);
  EXPECT_EQ(header[1], 32768u);
  EXPECT_EQ(header[2], 40000u - 32768u);
  EXPECT_LT(vtp.size(), particles_vtp(p, "t", VtpEncoding::Ascii, {coordination, component, {}, {}}).size() / 3);
  EXPECT_EQ(vtp, particles_vtp(p, "t", VtpEncoding::ZlibAppended, {coordination, component, {}, {}}));  // deterministic
  const std::vector<std::int32_t> short_array(3, 0);
  EXPECT_THROW(particles_vtp(p, "t", VtpEncoding::ZlibAppended, {short_array, {}, {}, {}}), std::invalid_argument);
}

TEST(Vtk, PvdListsTheFramesWithTheirTimesOrTheirNumbersWhenTimesRepeat) {
  const std::vector<PvdFrame> frames{{0.0, "particles_loose.vtp", "snapshot loose"},
                                     {0.25, "particles.vtp", "the final bed"}};
  const std::string pvd = particles_pvd(frames, "aggpack test");
  EXPECT_NE(pvd.find("<VTKFile type=\"Collection\""), std::string::npos);
  EXPECT_NE(pvd.find("<DataSet timestep=\"0\" group=\"\" part=\"0\" file=\"particles_loose.vtp\"/>"),
            std::string::npos);
  EXPECT_NE(pvd.find("<DataSet timestep=\"0.25\" group=\"\" part=\"0\" file=\"particles.vtp\"/>"),
            std::string::npos);
  const std::vector<PvdFrame> same_time{{0.0, "a.vtp", "a"}, {0.0, "b.vtp", "b"}};
  const std::string numbered = particles_pvd(same_time, "aggpack test");
  EXPECT_NE(numbered.find("timestep=\"1\" group=\"\" part=\"0\" file=\"b.vtp\""), std::string::npos);
  EXPECT_NE(numbered.find("each timestep is the frame's number"), std::string::npos);
}

}  // namespace
}  // namespace aggpack
