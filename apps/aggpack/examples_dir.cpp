#include "examples_dir.hpp"

#include <system_error>

namespace fs = std::filesystem;

namespace {

// The running binary's own path, symlinks resolved; empty when it cannot be told.
fs::path running_executable(const char* argv0) {
  std::error_code error;
  fs::path exe = fs::read_symlink("/proc/self/exe", error);
  if (!error) return exe;
  // Without /proc: argv[0], when it holds a path (a bare name was found on PATH: unknown).
  const fs::path given = argv0 ? fs::path(argv0) : fs::path();
  if (!given.has_parent_path()) return {};
  exe = fs::canonical(given, error);
  return error ? fs::path() : exe;
}

}  // namespace

fs::path default_examples_dir(const char* argv0) {
  const fs::path exe = running_executable(argv0);
  if (exe.empty()) return {};
  std::error_code error;
  // The build tree's binary reads the checkout it was built from; nothing else does, so an
  // installed binary never depends on the checkout being there.
  if (fs::equivalent(exe.parent_path(), fs::path(AGGPACK_BUILD_TREE_BINDIR), error))
    return fs::path(AGGPACK_BUILD_TREE_EXAMPLES);
  return (exe.parent_path() / AGGPACK_EXAMPLES_FROM_BINDIR).lexically_normal();
}
