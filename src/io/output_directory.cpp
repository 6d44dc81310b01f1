#include "aggpack/io/output_directory.hpp"

#include <fstream>
#include <string>

#include <fmt/format.h>
#include <unistd.h>

#include "aggpack/core/error.hpp"
#include "aggpack/io/atomic_file.hpp"

namespace aggpack {

namespace fs = std::filesystem;

void check_output_directory(const fs::path& directory, bool create, std::string_view options) {
  const std::string shown = directory.string();
  if (shown.empty()) throw InputError(fmt::format("the output folder is an empty path; expected a folder name ({})", options));
  std::error_code ec;
  // The nearest part of the path that exists must be a directory we may write into.
  fs::path existing = directory;
  while (!existing.empty() && !fs::exists(existing, ec)) existing = existing.parent_path();
  if (existing.empty()) existing = ".";
  if (!fs::is_directory(existing, ec))
    throw InputError(fmt::format("{}: cannot make the output folder: {} is a file, not a folder; expected a folder "
                                 "path ({})",
                                 shown, existing.string(), options));
  if (::access(existing.c_str(), W_OK | X_OK) != 0)
    throw InputError(fmt::format("{}: cannot write the output folder: {} is not writable; expected a folder you "
                                 "may write ({})",
                                 shown, existing.string(), options));
  if (!create) return;
  fs::create_directories(directory, ec);
  if (ec)
    throw InputError(fmt::format("{}: cannot make the output folder: {}", shown, ec.message()));
  const fs::path probe = directory / fmt::format(".aggpack-write-probe.{}", ::getpid());
  bool written = false;
  {
    std::ofstream out(probe);
    out << "probe\n";
    written = static_cast<bool>(out.flush());
  }
  fs::remove(probe, ec);
  if (!written) throw InputError(fmt::format("{}: cannot write into the output folder", shown));
  // Temporary files of an earlier run into this folder that was killed mid-write (aggpack's
  // own name pattern only: a user's `notes.tmp.txt` stays).
  for (const auto& entry : fs::directory_iterator(directory, ec))
    if (is_aggpack_temporary(entry.path()) && entry.is_regular_file(ec))
      fs::remove(entry.path(), ec);
}

}  // namespace aggpack
