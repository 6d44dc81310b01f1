#pragma once
#include <filesystem>
#include <functional>
#include <ostream>
#include <string_view>

namespace aggpack {

// Writes `content` to a temporary file beside `path`, then renames it over `path`, so
// readers never see a half-written file. Throws std::runtime_error on failure.
void write_file_atomically(const std::filesystem::path& path, std::string_view content);
// The same, the content written by `write` straight into the file (no copy in memory).
void write_file_atomically(const std::filesystem::path& path, const std::function<void(std::ostream&)>& write);

}  // namespace aggpack
