#include "aggpack/specimen/gmsh_geometry.hpp"

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <vector>

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>
#ifdef __linux__
#include <sys/prctl.h>
#endif

#include <fmt/format.h>
#include <fmt/ostream.h>

#include "aggpack/core/error.hpp"
#include "aggpack/core/overloaded.hpp"

namespace aggpack {

namespace {

// The list `name` of each particle's solid (tags first + its spheres): a sphere as it is, a
// grain the union of its member spheres (OpenCASCADE's fuse), whose members overlap as they
// are meant to and would otherwise be meshed as separate volumes with overlapping faces.
void write_particles(std::ostream& o, const char* name, std::size_t first, const std::vector<std::size_t>& particle_of) {
  fmt::print(o, "{}() = {{}};\n", name);
  for (std::size_t k = 0; k < particle_of.size();) {
    std::size_t end = k + 1;
    while (end < particle_of.size() && particle_of[end] == particle_of[k]) ++end;
    if (end == k + 1)
      fmt::print(o, "{}() += {{{}}};\n", name, first + k);
    else
      fmt::print(o, "{0}() += BooleanUnion{{ Volume{{{1}}}; Delete; }}{{ Volume{{{2}:{3}}}; Delete; }};\n", name,
                 first + k, first + k + 1, first + end - 1);
    k = end;
  }
}

// The solids of list `name` cut by the region (tag 1): disjoint pieces (OpenCASCADE's general
// fuse splits two particles' overlap into a piece of its own, so no union across particles is
// needed, and a union of untouched ones would lose their tags).
void write_pieces_in_region(std::ostream& o, const char* name) {
  fmt::print(o, "{0}() = BooleanIntersection{{ Volume{{{0}()}}; Delete; }}{{ Volume{{1}}; }};\n", name);
}

}  // namespace

std::string gmsh_geo(const Specimen& s, const GmshMeshSizes& sizes, std::string_view provenance) {
  std::ostringstream o;
  o.precision(17);
  fmt::print(o, "// {}\n// Physical volumes: 1 aggregate, 2 mortar, 3 itz. Mesh with: gmsh THIS.geo -3\n", provenance);
  o << "SetFactory(\"OpenCASCADE\");\nGeometry.OCCBooleanPreserveNumbering = 1;\nMesh.MshFileVersion = 2.2;\n";
  fmt::print(o, "Mesh.MeshSizeFromCurvature = {};\nMesh.MeshSizeMax = {:.17g};\n", sizes.elements_per_circle,
             std::max({sizes.aggregate, sizes.mortar, sizes.itz}));
  std::visit(Overloaded{[&](const Box& b) {
                          const Vec3 d = b.size();
                          fmt::print(o, "Box(1) = {{{:.17g}, {:.17g}, {:.17g}, {:.17g}, {:.17g}, {:.17g}}};\n", b.lo.x,
                                     b.lo.y, b.lo.z, d.x, d.y, d.z);
                        },
                        [&](const VerticalCylinder& c) {
                          fmt::print(o, "Cylinder(1) = {{{:.17g}, {:.17g}, {:.17g}, 0, 0, {:.17g}, {:.17g}}};\n", c.x,
                                     c.y, c.z_lo, c.z_hi - c.z_lo, c.radius);
                        }},
             s.region);
  const std::size_t n = s.spheres.size();
  const bool itz = s.itz_thickness > 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    const MemberSphere& sphere = s.spheres[k];
    fmt::print(o, "Sphere({}) = {{{:.17g}, {:.17g}, {:.17g}, {:.17g}}};\n", 2 + k, sphere.centre.x, sphere.centre.y,
               sphere.centre.z, sphere.radius);
    if (itz)
      fmt::print(o, "Sphere({}) = {{{:.17g}, {:.17g}, {:.17g}, {:.17g}}};\n", 2 + n + k, sphere.centre.x,
                 sphere.centre.y, sphere.centre.z, sphere.radius + s.itz_thickness);
  }
  // A specimen made by hand may leave particle_of_sphere empty: each sphere its own particle.
  std::vector<std::size_t> particle_of = s.particle_of_sphere;
  if (particle_of.size() != n) {
    particle_of.resize(n);
    for (std::size_t k = 0; k < n; ++k) particle_of[k] = k;
  }
  write_particles(o, "aggregate", 2, particle_of);
  write_pieces_in_region(o, "aggregate");
  if (itz) {
    write_particles(o, "outer", 2 + n, particle_of);
    write_pieces_in_region(o, "outer");
    o << "mortar() = BooleanDifference{ Volume{1}; Delete; }{ Volume{outer()}; };\n"
         "itz() = BooleanDifference{ Volume{outer()}; Delete; }{ Volume{aggregate()}; };\n"
         "BooleanFragments{ Volume{mortar(), itz(), aggregate()}; Delete; }{}\n";
  } else {
    o << "mortar() = BooleanDifference{ Volume{1}; Delete; }{ Volume{aggregate()}; };\n"
         "BooleanFragments{ Volume{mortar(), aggregate()}; Delete; }{}\n";
  }
  o << "Physical Volume(\"aggregate\", 1) = {aggregate()};\nPhysical Volume(\"mortar\", 2) = {mortar()};\n";
  if (itz) o << "Physical Volume(\"itz\", 3) = {itz()};\n";
  // Each phase's points their size; the aggregate's last, so that its faces get the aggregate's.
  fmt::print(o, "MeshSize{{ PointsOf{{ Volume{{mortar()}}; }} }} = {:.17g};\n", sizes.mortar);
  if (itz) fmt::print(o, "MeshSize{{ PointsOf{{ Volume{{itz()}}; }} }} = {:.17g};\n", sizes.itz);
  fmt::print(o, "MeshSize{{ PointsOf{{ Volume{{aggregate()}}; }} }} = {:.17g};\n", sizes.aggregate);
  return o.str();
}

std::optional<std::filesystem::path> gmsh_executable() {
  const char* path = std::getenv("PATH");
  std::string_view dirs = path ? path : "/usr/bin:/bin";
  while (!dirs.empty()) {
    const std::size_t colon = dirs.find(':');
    const std::filesystem::path candidate = std::filesystem::path(dirs.substr(0, colon)) / "gmsh";
    if (::access(candidate.c_str(), X_OK) == 0) return candidate;
    dirs = colon == std::string_view::npos ? std::string_view() : dirs.substr(colon + 1);
  }
  return std::nullopt;
}

bool gmsh_available() { return gmsh_executable().has_value(); }

namespace {

// Whether a mesh of format 2.2 holds a tetrahedron (Gmsh writes a file of no element when its
// 3-D mesh failed).
bool msh_has_elements(const std::filesystem::path& msh) {
  std::ifstream in(msh);
  std::string line;
  while (std::getline(in, line) && line != "$Elements") {
  }
  std::size_t count = 0;
  if (!(in >> count)) return false;
  std::getline(in, line);
  for (std::size_t e = 0; e < count && std::getline(in, line); ++e) {
    std::istringstream fields(line);
    int id = 0, type = 0;
    if (fields >> id >> type && type == 4) return true;
  }
  return false;
}

// Gmsh as a child in a process group of its own (a terminal's Ctrl-C reaches aggpack alone,
// which decides), started without a shell. The group is stopped when this ends early (an
// exception, a stop request) and, through PR_SET_PDEATHSIG, when aggpack dies.
class GmshChild {
 public:
  GmshChild(const std::filesystem::path& gmsh, const std::vector<std::string>& arguments,
            const std::filesystem::path& log) {
    std::vector<char*> argv{const_cast<char*>(gmsh.c_str())};
    for (const std::string& a : arguments) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    const int log_fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (log_fd < 0) throw InputError(fmt::format("{}: cannot write Gmsh's log: {}", log.string(), std::strerror(errno)));
    const pid_t parent = ::getpid();
    pid_ = ::fork();
    if (pid_ == 0) {  // the child: only async-signal-safe calls until exec
      ::setpgid(0, 0);
#ifdef __linux__
      ::prctl(PR_SET_PDEATHSIG, SIGTERM);
      if (::getppid() != parent) ::_exit(127);  // aggpack died before the line above
#endif
      ::dup2(log_fd, STDOUT_FILENO);
      ::dup2(log_fd, STDERR_FILENO);
      const int null_fd = ::open("/dev/null", O_RDONLY);
      if (null_fd >= 0) ::dup2(null_fd, STDIN_FILENO);
      ::signal(SIGINT, SIG_DFL);
      ::signal(SIGTERM, SIG_DFL);
      ::execv(argv[0], argv.data());
      ::_exit(127);
    }
    const int fork_error = errno;
    ::close(log_fd);
    if (pid_ < 0) throw std::runtime_error(fmt::format("cannot start gmsh: {}", std::strerror(fork_error)));
    ::setpgid(pid_, pid_);  // also here: whichever runs first, the group exists before a killpg
  }
  ~GmshChild() {
    if (pid_ <= 0) return;
    ::killpg(pid_, SIGTERM);
    int status = 0;
    // Gmsh ends at SIGTERM at once; a group that lingers is killed.
    for (int waited = 0; waited < 100 && ::waitpid(pid_, &status, WNOHANG) == 0; ++waited) ::usleep(20000);
    if (::waitpid(pid_, &status, WNOHANG) == 0) {
      ::killpg(pid_, SIGKILL);
      ::waitpid(pid_, &status, 0);
    }
  }
  GmshChild(const GmshChild&) = delete;
  GmshChild& operator=(const GmshChild&) = delete;

  // Waits for Gmsh, calling `safe_point` every 50 ms (what it throws stops Gmsh). Its exit
  // status, or -N when signal N ended it.
  int wait(const std::function<void()>& safe_point) {
    int status = 0;
    while (true) {
      const pid_t done = ::waitpid(pid_, &status, WNOHANG);
      if (done == pid_) break;
      if (done < 0 && errno != EINTR) throw std::runtime_error(fmt::format("waiting for gmsh: {}", std::strerror(errno)));
      if (safe_point) safe_point();
      ::usleep(50000);
    }
    pid_ = 0;  // reaped: nothing left for the destructor to stop
    return WIFEXITED(status) ? WEXITSTATUS(status) : -WTERMSIG(status);
  }

 private:
  pid_t pid_ = 0;
};

}  // namespace

void run_gmsh(const std::filesystem::path& geo, const std::filesystem::path& msh, const std::filesystem::path& log,
              const std::function<void()>& safe_point) {
  const std::optional<std::filesystem::path> gmsh = gmsh_executable();
  if (!gmsh) throw InputError("gmsh is not installed (Debian package gmsh); the .geo file can be meshed elsewhere");
  std::error_code ec;
  std::filesystem::remove(msh, ec);
  int status = 0;
  try {
    GmshChild child(*gmsh, {geo.string(), "-3", "-nt", "1", "-format", "msh22", "-o", msh.string()}, log);
    status = child.wait(safe_point);
  } catch (...) {  // stopped: Gmsh's group is gone (GmshChild), and its partial mesh with it
    std::filesystem::remove(msh, ec);
    throw;
  }
  // A mesh Gmsh wrote whole: it exits 0, and a mesh of no element is no mesh (Gmsh writes one
  // when its 3-D mesh failed on a boundary it could not recover).
  bool meshed = status == 0 && std::filesystem::is_regular_file(msh, ec);
  std::string first_error;
  {
    std::ifstream in(log);
    std::string line;
    while (first_error.empty() && std::getline(in, line))
      if (line.find("Error") != std::string::npos) first_error = line;
  }
  if (meshed && !msh_has_elements(msh)) meshed = false;
  if (meshed) return;
  std::filesystem::remove(msh, ec);
  throw InputError(fmt::format("gmsh could not mesh {} ({}){}; its log: {}", geo.string(),
                               status >= 0 ? fmt::format("exit status {}", status)
                                           : fmt::format("ended by signal {}", -status),
                               first_error.empty() ? "" : ": " + first_error, log.string()));
}

}  // namespace aggpack
