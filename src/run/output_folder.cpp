#include "aggpack/run/output_folder.hpp"

#include <algorithm>
#include <fstream>
#include <set>

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

// What a run of an aggpack before manifests wrote, by name.
bool written_by_aggpack_before_manifests(const std::string& name) {
  for (const char* output : {"particles.csv", "particles.vtp", "summary.json", "timeseries.csv", "taps.csv",
                             "supports.csv", "lammps", kCheckpointFile})
    if (name == output) return true;
  return name.starts_with("particles_") && name.ends_with(".csv");
}

// The manifest's list; none when there is no manifest or it cannot be read (then the folder's
// files count as others: nothing is removed on a guess).
std::optional<std::set<std::string>> manifest_files(const fs::path& folder) {
  std::ifstream in(folder / kManifestFile);
  if (!in) return std::nullopt;
  try {
    const nlohmann::json manifest = nlohmann::json::parse(in);
    std::set<std::string> files;
    for (const auto& f : manifest.at("files")) files.insert(f.get<std::string>());
    return files;
  } catch (const nlohmann::json::exception&) {
    return std::nullopt;
  }
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
}  // namespace

OutputFolderContents output_folder_contents(const fs::path& folder) {
  OutputFolderContents contents;
  std::error_code ec;
  if (!fs::is_directory(folder, ec)) return contents;
  const auto manifest = manifest_files(folder);
  const bool legacy = !manifest && summary_of_an_aggpack_run(folder);
  for (const auto& entry : fs::directory_iterator(folder, ec)) {
    const std::string name = entry.path().filename().string();
    if (name == kManifestFile || is_aggpack_temporary(name) || name.starts_with(".aggpack-write-probe.")) continue;
    const bool ours = manifest ? manifest->contains(name) : legacy && written_by_aggpack_before_manifests(name);
    (ours ? contents.earlier_run : contents.others).push_back(name);
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
  std::vector<std::string> removed;
  for (const std::string& name : output_folder_contents(folder).earlier_run) {
    if (name == kCheckpointFile || std::find(keep.begin(), keep.end(), name) != keep.end()) continue;
    std::error_code ec;
    fs::remove_all(folder / name, ec);
    if (!ec) removed.push_back(name);
  }
  std::error_code ec;
  fs::remove(folder / kManifestFile, ec);
  return removed;
}

void write_manifest(const fs::path& folder, const std::vector<std::string>& files) {
  nlohmann::json manifest;
  manifest["aggpack_version"] = kVersion;
  manifest["note"] = "the files the last aggpack run wrote into this folder; a later run into it removes them";
  manifest["files"] = files;
  write_file_atomically(folder / kManifestFile, manifest.dump(2) + "\n");
}

}  // namespace aggpack
