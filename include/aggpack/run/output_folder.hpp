#pragma once
// What an aggpack run leaves in its output folder, and what a later run does with it. Every run
// lists the files it wrote in a manifest (aggpack-manifest.json), each by its path in the
// folder ("summary.json", "frames/frame_00001.vtp", "lammps/cluster/settle.in"), so that a later
// run into the same folder removes exactly those (a reused folder then holds the new run's
// outputs only, never an older run's timeseries.csv beside a newer summary.json) and nothing
// else: a file a user put into one of the run's folders (LAMMPS's dump beside an exported deck,
// a picture among the frames) or a folder that merely bears an output's name is the user's. A
// folder holding anything else is refused unless told to write beside it (--overwrite).
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "aggpack/io/output_directory.hpp"  // check_output_directory

namespace aggpack {

inline constexpr const char* kManifestFile = "aggpack-manifest.json";
// The bed of a run whose final analysis was refused after a DEM (a virtual cube that does not
// fit the bed it made): kept, and listed in the manifest, so that it can be measured again.
inline constexpr const char* kUnanalysedBedFile = "particles_unanalysed.csv";
// The folders a run writes files into (the DEM's frames, the LAMMPS decks and runs).
inline constexpr const char* kFramesFolder = "frames";
inline constexpr const char* kLammpsFolder = "lammps";

// The files in `folder` (paths relative to it, '/'-separated; sorted): those an aggpack run wrote
// (listed in its manifest; in a folder of an aggpack from before manifests, one whose
// summary.json names an aggpack_version, the names aggpack writes), and the others (a file in
// one of the run's folders by its path, anything else by its name). A killed run's temporaries,
// the manifest itself and empty folders are neither. A folder that does not exist holds nothing.
struct OutputFolderContents {
  std::vector<std::string> earlier_run;
  std::vector<std::string> others;
};
OutputFolderContents output_folder_contents(const std::filesystem::path& folder);

// Refuses (InputError, before any work) a folder holding files no aggpack run wrote, naming
// them, unless `overwrite`: then the run writes beside them and leaves them alone.
void check_output_folder_contents(const std::filesystem::path& folder, bool overwrite);

// Removes an earlier run's files from `folder` (and the run's folders they leave empty) and
// returns their paths. checkpoint.bin stays: a resumed run reads it, and a new run writes over
// it (a finished run then removes it); so do the files in the folders named in `keep`.
std::vector<std::string> remove_earlier_run(const std::filesystem::path& folder,
                                            const std::vector<std::string>& keep = {});

// The files now in the run's folders (frames/, lammps/) of `folder`, by path as the manifest
// lists them: a run lists as its own those that were not there when it began.
std::set<std::string> files_in_run_folders(const std::filesystem::path& folder);

// The files the manifest of `folder` lists, in its order (none when there is none or it cannot be read).
std::vector<std::string> manifest_files(const std::filesystem::path& folder);

// Writes the manifest: `files` (paths relative to `folder`), written atomically. The files the
// manifest listed before and `files` does not (an earlier run's outputs that this run did not
// write again: a resumed run replaces the interrupted run's outputs only as it writes its own)
// are removed first, checkpoint.bin excepted.
void write_manifest(const std::filesystem::path& folder, const std::vector<std::string>& files);

// The manifest of `folder` without `file` (a file the run has removed since it listed it).
void drop_from_manifest(const std::filesystem::path& folder, const std::string& file);

}  // namespace aggpack
