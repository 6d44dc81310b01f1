#include "aggpack/core/input_file.hpp"

#include <fstream>
#include <sstream>

#include <fmt/format.h>

#include "aggpack/core/error.hpp"

namespace aggpack {

std::string read_input_file(const std::filesystem::path& file, std::string_view what, std::uintmax_t max_bytes) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status status = fs::status(file, ec);
  if (ec || !fs::exists(status))
    throw InputError(fmt::format("{}: cannot read {}: no such file", file.string(), what));
  if (fs::is_directory(status))
    throw InputError(fmt::format("{}: cannot read {}: it is a directory; expected a regular file", file.string(), what));
  if (!fs::is_regular_file(status))
    throw InputError(fmt::format("{}: cannot read {}: it is not a regular file (a device, pipe or socket); expected "
                                 "a regular file", file.string(), what));
  const std::uintmax_t size = fs::file_size(file, ec);
  if (ec) throw InputError(fmt::format("{}: cannot read {}: {}", file.string(), what, ec.message()));
  if (size > max_bytes)
    throw InputError(fmt::format("{}: {} is {:.3g} GiB, more than the limit of {:.3g} GiB (raise it with "
                                 "limits.max_input_file_gib in the scenario)",
                                 file.string(), what, static_cast<double>(size) / (1u << 30),
                                 static_cast<double>(max_bytes) / (1u << 30)));
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(fmt::format("{}: cannot read {}: permission denied or unreadable", file.string(), what));
  std::string text(static_cast<std::size_t>(size), '\0');
  in.read(text.data(), static_cast<std::streamsize>(size));
  text.resize(static_cast<std::size_t>(in.gcount()));  // a file that shrank while being read
  return text;
}

std::string read_input_text(const std::filesystem::path& file, std::string_view what, std::uintmax_t max_bytes) {
  std::string text = read_input_file(file, what, max_bytes);
  if (text.starts_with("\xEF\xBB\xBF")) text.erase(0, 3);
  return text;
}

}  // namespace aggpack
