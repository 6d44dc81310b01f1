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

// The temporary beside `path` that write_file_atomically writes: `<name>.aggpack-incomplete.<pid>`,
// a pattern of aggpack's own, so that a later run removes a killed run's leftovers and never a
// user's file (a `notes.tmp.txt` is not ours).
std::filesystem::path temporary_path_for(const std::filesystem::path& path);
// Whether `filename` is such a temporary (the pattern above, the pid all digits).
bool is_aggpack_temporary(const std::filesystem::path& filename);

}  // namespace aggpack
