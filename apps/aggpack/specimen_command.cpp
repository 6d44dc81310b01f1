// aggpack specimen: a concrete specimen cut from a run's bed for meso-model codes.
#include <algorithm>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "aggpack/core/error.hpp"
#include "aggpack/core/units.hpp"
#include "aggpack/run/preflight.hpp"
#include "aggpack/specimen/specimen_export.hpp"
#include "arguments.hpp"
#include "commands.hpp"

namespace {

struct SpecimenArguments {
  std::string source, out, box, cylinder, voxel, itz, min_size, gap, mesh_size, length_unit = "m";
  std::vector<std::string> formats;
  std::string max_voxels;
  bool json = false;
};

aggpack::SpecimenRequest request_of(const SpecimenArguments& a, long double unit) {
  aggpack::SpecimenRequest r;
  if (!a.box.empty() && !a.cylinder.empty()) throw aggpack::InputError("--box and --cylinder: give one specimen");
  if (!a.box.empty()) r.region = box_argument(a.box, unit);
  if (!a.cylinder.empty())
    r.region = aggpack::cylinder_from(lengths_argument(a.cylinder, "--cylinder", unit), "--cylinder " + a.cylinder);
  if (!a.voxel.empty()) r.voxel_size = length_argument(a.voxel, "--voxel", unit);
  if (!a.itz.empty()) r.itz_thickness = length_argument(a.itz, "--itz", unit);
  if (!a.min_size.empty()) r.min_size = length_argument(a.min_size, "--min-size", unit);
  if (!a.gap.empty()) r.gap = length_argument(a.gap, "--gap", unit);
  if (!a.mesh_size.empty())
    r.mesh_sizes =
        aggpack::mesh_sizes_from(lengths_argument(a.mesh_size, "--mesh-size", unit), "--mesh-size " + a.mesh_size);
  r.formats = a.formats;
  if (!a.max_voxels.empty()) r.max_voxels = positive_argument(a.max_voxels, "--max-voxels");
  return r;
}

int specimen_command(const SpecimenArguments& a) {
  const auto unit = aggpack::metres_per_unit(a.length_unit);
  if (!unit)
    throw aggpack::InputError(fmt::format("--length-unit {}: unknown unit; expected m, cm, mm, um, in, ft or yd",
                                          a.length_unit));
  const aggpack::SpecimenRequest request = request_of(a, *unit);
  aggpack::check_output_directory(a.out, false);
  const std::filesystem::path source(a.source);
  aggpack::SpecimenSource bed = std::filesystem::is_directory(source)
                                    ? aggpack::read_run_folder(source)
                                    : aggpack::read_packing_source(source, static_cast<double>(*unit));
  if (a.length_unit != "m") bed.length_unit = a.length_unit;  // the notes' lengths in the unit asked for
  // SIGINT and SIGTERM stop the work at its next safe point (Gmsh's group stopped, its partial
  // mesh removed) and exit 128 + the signal, as an interrupted run does.
  const aggpack::StopRequest& stop = stop_on_signals();
  nlohmann::json report;
  try {
    aggpack::SpecimenHooks hooks;
    hooks.safe_point = [&] { aggpack::stop_here_if_requested(&stop, "while the specimen was made"); };
    if (!a.json)
      hooks.say = [](const std::string& line) {
        fmt::print("aggpack specimen: {}\n", line);
        std::fflush(stdout);  // before the write it announces
      };
    report = aggpack::export_specimen(bed, request, a.out, hooks);
  } catch (const aggpack::Interrupted& e) {
    fmt::print(stderr,
               "aggpack specimen: interrupted by signal {} {}: no partial file is left (Gmsh, if it was meshing, "
               "stopped and its mesh removed); the files specimen.json lists, if any, are whole\n",
               e.signal_number(), e.where());
    return 128 + e.signal_number();
  }
  if (a.json) {
    std::cout << report.dump(2) << "\n";
    return 0;
  }
  const nlohmann::json& v = report.at("voxels");
  // The particles in the geometry, and what was left out of it and why.
  const nlohmann::json& particles = report.at("particles");
  const auto gap_out = particles.at("left_out_by_gap").get<std::size_t>();
  fmt::print("aggpack specimen: {} particles in the specimen ({} below the minimum size left to the mortar{}) of {}\n",
             particles.at("kept").get<std::size_t>(), particles.at("dropped_below_min_size").get<std::size_t>(),
             gap_out ? fmt::format("; {} reaching in by less than gap / 2 left out", gap_out) : std::string(),
             bed.description);
  fmt::print("  aggregate fraction: exact {:.4f}; voxels ({} x {} x {}) {:.4f}", 
             report.at("exact").at("aggregate_fraction").get<double>(), v.at("count")[0].get<std::size_t>(),
             v.at("count")[1].get<std::size_t>(), v.at("count")[2].get<std::size_t>(),
             v.at("aggregate_fraction").get<double>());
  if (report.contains("gmsh") && report.at("gmsh").contains("aggregate_fraction"))
    fmt::print("; Gmsh mesh {:.4f}", report.at("gmsh").at("aggregate_fraction").get<double>());
  if (report.at("itz_thickness_m").get<double>() > 0.0) {
    fmt::print("\n  ITZ fraction: voxels {:.4f}", v.at("itz_fraction").get<double>());
    if (report.contains("gmsh") && report.at("gmsh").contains("itz_fraction"))
      fmt::print("; Gmsh mesh {:.4f}", report.at("gmsh").at("itz_fraction").get<double>());
  }
  fmt::print("\n  wrote {} and specimen.json into {}\n",
             fmt::join(report.at("files").get<std::vector<std::string>>(), ", "), a.out);
  for (const auto& note : report.at("modelling_notes")) fmt::print("  note: {}\n", note.get<std::string>());
  return 0;
}

}  // namespace

Subcommand add_specimen_command(CLI::App& app) {
  const auto a = std::make_shared<SpecimenArguments>();
  auto* cmd = app.add_subcommand(
      "specimen",
      "A concrete specimen cut from a run's bed for meso-models: a voxel image (.vti), an Abaqus voxel mesh (.inp), "
      "a Gmsh geometry (.geo) and mesh (.msh), with aggregate, mortar and ITZ phases");
  cmd->add_option("source", a->source, "A run's output folder (its final bed), or a packing file")->required();
  cmd->add_option("--out", a->out, "The folder to write into")->required();
  cmd->add_option("--box", a->box, "The specimen's box XMIN,YMIN,ZMIN,XMAX,YMAX,ZMAX (default: the run's largest "
                                   "virtual box)");
  cmd->add_option("--cylinder", a->cylinder, "A vertical cylinder X,Y,ZLO,ZHI,RADIUS instead");
  cmd->add_option("--voxel", a->voxel, "The voxel's side (default: a tenth of the smallest kept sphere's diameter)");
  cmd->add_option("--itz", a->itz, "The ITZ's thickness around each kept particle (default: no ITZ)");
  cmd->add_option("--min-size", a->min_size, "Particles smaller (a grain's I) are left to the mortar (default: every particle kept)");
  cmd->add_option("--gap", a->gap, "Shrink each kept particle so that touching ones stand this far apart (default: as "
                                   "packed; Gmsh cannot mesh particles that touch)");
  cmd->add_option("--formats", a->formats, "Of vti, inp, geo, msh (default vti,inp,geo; msh: Gmsh meshes the "
                                           "geometry, minutes for hundreds of particles)")
      ->delimiter(',');
  cmd->add_option("--mesh-size", a->mesh_size, "Gmsh's element size AGGREGATE[,MORTAR[,ITZ]] (default: a quarter "
                                               "and a half of the smallest kept sphere's diameter, the ITZ's thickness)");
  cmd->add_option("--max-voxels", a->max_voxels, "Voxels at most (default 2e8: a byte each)");
  cmd->add_option("--length-unit", a->length_unit, "The unit of bare numbers, and of a packing file (default m)");
  cmd->add_flag("--json", a->json, "Print specimen.json's content");
  return {cmd, [a] { return specimen_command(*a); }};
}
