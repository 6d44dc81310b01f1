#pragma once
#include <filesystem>
#include <string_view>

namespace aggpack {

// An output folder: an existing directory that can be written, or a path where one can be
// made. With `create`, makes it and writes and removes a probe file (what `run` does before
// any work), and removes a killed run's temporaries; without, only looks (what `check` does,
// which writes nothing). InputError naming the folder and `options` (the flags or keys that
// give it) otherwise.
void check_output_directory(const std::filesystem::path& directory, bool create,
                            std::string_view options = "--out or output.directory");

}  // namespace aggpack
