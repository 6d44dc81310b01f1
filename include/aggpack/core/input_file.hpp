#pragma once
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

namespace aggpack {

// The largest input file (scenario, grading, particle file) read by default: 2 GiB, about
// 25 million particle rows. Scenario files raise it with limits.max_input_file_gib.
inline constexpr std::uintmax_t kDefaultMaxInputFileBytes = std::uintmax_t{2} << 30;

// The whole text of a user's input file. Refuses at once, with an InputError naming the file
// and `what` it is ("the particle file", ...): a missing file, a directory, a device or a
// pipe (such as /dev/zero, which would be read for ever), and a file over `max_bytes`.
[[nodiscard]] std::string read_input_file(const std::filesystem::path& file, std::string_view what,
                                          std::uintmax_t max_bytes = kDefaultMaxInputFileBytes);
// The same for a text file (scenario, particle, grading, LAMMPS and JSON files): without the
// UTF-8 byte order mark some editors put first, which would hide the first line's words.
[[nodiscard]] std::string read_input_text(const std::filesystem::path& file, std::string_view what,
                                          std::uintmax_t max_bytes = kDefaultMaxInputFileBytes);

}  // namespace aggpack
