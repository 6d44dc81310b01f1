#include "aggpack/run/output_folder.hpp"

#include <algorithm>
#include <fstream>
#include <regex>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <nlohmann/json.hpp>

#include "aggpack/core/error.hpp"
#include "aggpack/core/version.hpp"
#include "aggpack/io/atomic_file.hpp"
#include "aggpack/run/checkpoint.hpp"

namespace aggpack {

namespace {
namespace fs = std::filesystem;

bool is_run_folder(const std::string& name) { return name == kFramesFolder || name == kLammpsFolder; }

bool is_plain_file(const fs::path& path) {
  std::error_code ec;
  return fs::symlink_status(path, ec).type() == fs::file_type::regular;
}

// What a run of an aggpack before manifests wrote at the folder's top level, by name.
bool top_level_output_before_manifests(const std::string& name) {
  for (const char* output : {"particles.csv", "particles.vtp", "summary.json", "timeseries.csv", "taps.csv",
                             "supports.csv", "grains.csv", "particles.pvd", kCheckpointFile})
    if (name == output) return true;
  return name.starts_with("particles_") && (name.ends_with(".csv") || name.ends_with(".vtp"));
}

// What a run of an aggpack whose manifest named its folders whole (frames, lammps) wrote in them:
// the frames, the decks, and where LAMMPS ran for the run (its output in lammps.out) what it
// wrote. LAMMPS's output beside a deck that was only exported is the user's.
bool file_in_run_folder_before_per_file_manifests(const fs::path& folder, const std::string& path) {
  static const std::regex frame(R"(frames/frame_\d+\.vtp)");
  static const std::regex deck(R"(lammps/[^/]+/(settle\.in|pour\.in|tap\.in|bed\.data|bodies\.txt|pour_batch_\d+\.data))");
  static const std::regex lammps_output(R"(lammps/[^/]+/(settled\.dump|lammps\.log|lammps\.out|tap_\d+\.dump))");
  if (std::regex_match(path, frame) || std::regex_match(path, deck)) return true;
  return std::regex_match(path, lammps_output) && is_plain_file(folder / fs::path(path).parent_path() / "lammps.out");
}

// The manifest's list, in its order; none when there is no manifest or it cannot be read (then
// the folder's files count as others: nothing is removed on a guess).
std::optional<std::vector<std::string>> read_manifest_list(const fs::path& folder) {
  std::ifstream in(folder / kManifestFile);
  if (!in) return std::nullopt;
  try {
    const nlohmann::json manifest = nlohmann::json::parse(in);
    std::vector<std::string> files;
    for (const auto& f : manifest.at("files")) files.push_back(f.get<std::string>());
    return files;
  } catch (const nlohmann::json::exception&) {
    return std::nullopt;
  }
}

std::optional<std::set<std::string>> read_manifest(const fs::path& folder) {
  const auto files = read_manifest_list(folder);
  if (!files) return std::nullopt;
  return std::set<std::string>(files->begin(), files->end());
}

bool summary_of_an_aggpack_run(const fs::path& folder) {
  std::ifstream in(folder / "summary.json");
  if (!in) return false;
  try {
    return nlohmann::json::parse(in).contains("aggpack_version");
  } catch (const nlohmann::json::exception&) {
    return false;
  }
}

// The regular files (and anything else that is not a folder) under `folder`'s run folder
// `name`, by their paths relative to `folder`.
std::vector<std::string> files_under(const fs::path& folder, const std::string& name) {
  std::vector<std::string> files;
  std::error_code ec;
  for (auto it = fs::recursive_directory_iterator(folder / name, ec); !ec && it != fs::recursive_directory_iterator();
       it.increment(ec)) {
    if (it->is_directory(ec) && !it->is_symlink(ec)) continue;
    if (is_aggpack_temporary(it->path().filename())) continue;
    files.push_back(fs::relative(it->path(), folder, ec).generic_string());
  }
  return files;
}

// Removes the folders of `path`'s (relative to `folder`) parents inside a run folder that are
// now empty, innermost first.
void remove_empty_parents(const fs::path& folder, const std::string& path) {
  std::error_code ec;
  for (fs::path parent = fs::path(path).parent_path(); !parent.empty(); parent = parent.parent_path()) {
    const fs::path full = folder / parent;
    if (!fs::is_directory(full, ec) || !fs::is_empty(full, ec)) return;
    fs::remove(full, ec);
  }
}

// A path a manifest may name: inside its folder (a damaged or edited manifest never reaches out).
bool inside_folder(const std::string& path) {
  const fs::path p(path);
  if (p.empty() || p.is_absolute()) return false;
  return std::none_of(p.begin(), p.end(), [](const fs::path& part) { return part == ".."; });
}

bool remove_file(const fs::path& folder, const std::string& path) {
  if (!inside_folder(path)) return false;
  if (!is_plain_file(folder / path)) return false;  // a folder or a link bearing an output's name is the user's
  std::error_code ec;
  if (!fs::remove(folder / path, ec) || ec) return false;
  remove_empty_parents(folder, path);
  return true;
}

}  // namespace

OutputFolderContents output_folder_contents(const fs::path& folder) {
  OutputFolderContents contents;
  std::error_code ec;
  if (!fs::is_directory(folder, ec)) return contents;
  const auto manifest = read_manifest(folder);
  const bool before_manifests = !manifest && summary_of_an_aggpack_run(folder);
  const auto sort = [&](const std::string& path, bool ours) {
    (ours ? contents.earlier_run : contents.others).push_back(path);
  };
  for (const auto& entry : fs::directory_iterator(folder, ec)) {
    const std::string name = entry.path().filename().string();
    if (name == kManifestFile || is_aggpack_temporary(name) || name.starts_with(".aggpack-write-probe.")) continue;
    if (is_run_folder(name) && entry.is_directory(ec) && !entry.is_symlink(ec)) {
      // A manifest of before per-file listing named the folder whole.
      const bool named_whole = manifest ? manifest->contains(name) : before_manifests;
      for (const std::string& path : files_under(folder, name))
        sort(path, (manifest && manifest->contains(path)) ||
                       (named_whole && file_in_run_folder_before_per_file_manifests(folder, path)));
      continue;
    }
    const bool listed = manifest ? manifest->contains(name) : before_manifests && top_level_output_before_manifests(name);
    sort(name, listed && is_plain_file(entry.path()));
  }
  std::sort(contents.earlier_run.begin(), contents.earlier_run.end());
  std::sort(contents.others.begin(), contents.others.end());
  return contents;
}

void check_output_folder_contents(const fs::path& folder, bool overwrite) {
  if (overwrite) return;
  const std::vector<std::string> others = output_folder_contents(folder).others;
  if (others.empty()) return;
  constexpr std::size_t kShown = 5;
  const std::vector<std::string> shown(others.begin(), others.begin() + std::min(kShown, others.size()));
  throw InputError(fmt::format(
      "{}: the output folder holds {} that no aggpack run wrote there ({}{}); expected an empty folder, a new one, "
      "or the folder of an earlier aggpack run (whose files are replaced); give another folder (--out or "
      "output.directory), or --overwrite to write beside them (they are left alone)",
      folder.string(), others.size() == 1 ? "a file" : fmt::format("{} files", others.size()), fmt::join(shown, ", "),
      others.size() > kShown ? ", ..." : ""));
}

std::vector<std::string> remove_earlier_run(const fs::path& folder, const std::vector<std::string>& keep) {
  const auto kept = [&](const std::string& path) {
    return path == kCheckpointFile ||
           std::any_of(keep.begin(), keep.end(), [&](const std::string& k) { return path.starts_with(k + "/"); });
  };
  std::vector<std::string> removed;
  for (const std::string& path : output_folder_contents(folder).earlier_run)
    if (!kept(path) && remove_file(folder, path)) removed.push_back(path);
  return removed;
}

std::set<std::string> files_in_run_folders(const fs::path& folder) {
  std::set<std::string> files;
  for (const char* name : {kFramesFolder, kLammpsFolder})
    for (std::string& path : files_under(folder, name)) files.insert(std::move(path));
  return files;
}

std::vector<std::string> manifest_files(const fs::path& folder) {
  return read_manifest_list(folder).value_or(std::vector<std::string>{});
}

void write_manifest(const fs::path& folder, const std::vector<std::string>& files) {
  for (const std::string& earlier : manifest_files(folder))
    if (earlier != kCheckpointFile && std::find(files.begin(), files.end(), earlier) == files.end())
      (void)remove_file(folder, earlier);
  nlohmann::json manifest;
  manifest["aggpack_version"] = kVersion;
  manifest["note"] = "the files the last aggpack run wrote into this folder; a later run into it removes them";
  manifest["files"] = files;
  write_file_atomically(folder / kManifestFile, manifest.dump(2) + "\n");
}

void drop_from_manifest(const fs::path& folder, const std::string& file) {
  std::vector<std::string> files = manifest_files(folder);
  const auto at = std::find(files.begin(), files.end(), file);
  if (at == files.end()) return;
  files.erase(at);
  write_manifest(folder, files);
}

}  // namespace aggpack
