#pragma once
// What an aggpack run leaves in its output folder, and what a later run does with it. Every run
// lists the files it wrote in a manifest (aggpack-manifest.json), so that a later run into the
// same folder removes exactly those (a reused folder then holds the new run's outputs only,
// never an older run's timeseries.csv beside a newer summary.json), and refuses a folder
// holding anything else unless told to write beside it (--overwrite).
#include <filesystem>
#include <string>
#include <vector>

namespace aggpack {

inline constexpr const char* kManifestFile = "aggpack-manifest.json";
// The bed of a run whose final analysis was refused after a DEM (a virtual cube that does not
// fit the bed it made): kept, and listed in the manifest, so that it can be measured again.
inline constexpr const char* kUnanalysedBedFile = "particles_unanalysed.csv";

// The entries of `folder` (names, not paths; sorted): those an aggpack run wrote (listed in its
// manifest; in a folder of an aggpack from before manifests, one whose summary.json names an
// aggpack_version, the names aggpack writes), and the others. A killed run's temporaries and
// the manifest itself are neither. A folder that does not exist holds nothing.
struct OutputFolderContents {
  std::vector<std::string> earlier_run;
  std::vector<std::string> others;
};
OutputFolderContents output_folder_contents(const std::filesystem::path& folder);

// Refuses (InputError, before any work) a folder holding files no aggpack run wrote, naming
// them, unless `overwrite`: then the run writes beside them and leaves them alone.
void check_output_folder_contents(const std::filesystem::path& folder, bool overwrite);

// Removes an earlier run's files from `folder` and returns their names. checkpoint.bin stays:
// a resumed run reads it, and a new run writes over it (a finished run then removes it); so do
// the files named in `keep` (a resumed run's frames).
std::vector<std::string> remove_earlier_run(const std::filesystem::path& folder,
                                            const std::vector<std::string>& keep = {});

// Writes the manifest: `files` (names relative to `folder`), written atomically.
void write_manifest(const std::filesystem::path& folder, const std::vector<std::string>& files);

}  // namespace aggpack
