// Bad input of every kind (scenario, grading, particle file, command line) refused as a user
// would want: exit code 2, a message naming the file and the key or line, what is wrong and
// what is expected, and nothing written. Then interruption: SIGINT and SIGTERM stop a run at
// a safe point with exit codes 130 and 143 and a summary marked "interrupted".
#include <gtest/gtest.h>

#include "run_cli.hpp"

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

namespace {

namespace fs = std::filesystem;
using aggpack::testing::run_cli;
using aggpack::testing::signal_aggpack_when;

// One bad input: the files it needs ({name, content}, written into the test folder, where
// "@" in any text stands for that folder), the aggpack arguments, and words the message must hold.
struct BadInput {
  std::string kind;  // scenario, grading, particles, command line
  std::vector<std::pair<std::string, std::string>> files;
  std::string arguments;
  std::vector<std::string> expected;
};

const std::string kBox = "[container]\nside = 0.1\nheight = 0.1\n";
const std::string kDeposit = kBox + "[particles]\ndiameter = 0.01\ncount = 500\n[deposition]\n";
const std::string kFromFile = kBox + "[particles]\nfrom = \"@/bed.csv\"\n[analysis]\nbox_sides = [0.02]\n";
const std::string kGraded = "[container]\nside = \"6 in\"\nheight = \"6 in\"\n[particles]\ncount = 200\n"
                            "[particles.grading]\nfile = \"@/g.csv\"\n[deposition]\n";
// A 3 x 3 x 3 lattice of touching 1 cm spheres that fits kBox.
std::string lattice() {
  std::string s = "x,y,z,r\n";
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k)
        s += std::to_string(0.035 + 0.01 * i) + "," + std::to_string(0.035 + 0.01 * j) + "," +
             std::to_string(0.005 + 0.01 * k) + ",0.005\n";
  return s;
}

std::vector<BadInput> bad_inputs() {
  const std::string run = "run @/s.toml";
  const auto scenario = [&](std::string text, std::vector<std::string> words) {
    return BadInput{"scenario", {{"s.toml", std::move(text)}}, run, std::move(words)};
  };
  const auto particles = [&](std::string csv, std::vector<std::string> words) {
    return BadInput{"particles", {{"s.toml", kFromFile}, {"bed.csv", std::move(csv)}}, run, std::move(words)};
  };
  const auto analyze = [&](std::string csv, std::string extra, std::vector<std::string> words) {
    return BadInput{"particles", {{"bed.csv", std::move(csv)}}, "analyze @/bed.csv" + extra, std::move(words)};
  };
  const auto grading = [&](std::string csv, std::vector<std::string> words) {
    return BadInput{"grading", {{"s.toml", kGraded}, {"g.csv", std::move(csv)}}, run, std::move(words)};
  };
  const auto grading_cli = [&](std::string csv, std::vector<std::string> words) {
    return BadInput{"grading", {{"g.csv", std::move(csv)}}, "grading @/g.csv", std::move(words)};
  };
  // A LAMMPS dump of two spheres, and a scenario checked with `protocol` as its [[protocol]].
  const std::string dump = "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n2\nITEM: BOX BOUNDS ff ff fm\n0 0.1\n0 0.1\n0 0.1\n"
                           "ITEM: ATOMS id type x y z radius\n1 1 0.02 0.02 0.005 0.005\n2 1 0.05 0.05 0.005 0.005\n";
  const auto protocol_check = [&](std::string protocol, std::vector<std::string> words) {
    return BadInput{"scenario", {{"s.toml", kDeposit + protocol}, {"d.dump", dump}, {"bed.csv", lattice()}},
                    "check @/s.toml", std::move(words)};
  };
  // A calibration file with the compaction index's range `range`, read by predict and by a run.
  const auto calibration = [&](std::string args, std::string range, std::vector<std::string> words) {
    const std::string json = R"({"kind": "aggpack CPM calibration", "cpm": {"compaction_index": 6.5, )"
                             R"("compaction_index_range": )" + range + R"(, "residual_packing_density": 0.7, )"
                             R"("residual_packing_density_range": [0.69, 0.71]}})";
    return BadInput{"calibration",
                    {{"s.toml", kDeposit}, {"m.toml", kDeposit + "[models]\ncalibration = \"@/c.json\"\n"}, {"c.json", json}},
                    std::move(args), std::move(words)};
  };
  const auto command = [&](std::string args, std::vector<std::string> words) {
    return BadInput{"command line", {{"s.toml", kDeposit}, {"bed.csv", lattice()}}, std::move(args), std::move(words)};
  };
  return {
      // Scenario files: syntax, keys, types, ranges, sections that contradict each other.
      scenario("[container\nside = 1\n", {"s.toml:1", "TOML syntax error"}),
      scenario("title = 3\n" + kDeposit, {"s.toml", "title", "string"}),
      scenario("[particles]\ndiameter = 0.01\ncount = 5\n[deposition]\n", {"s.toml", "container"}),
      scenario(kBox + "[deposition]\n", {"s.toml", "particles"}),
      scenario(kDeposit + "colour = 1\n", {"s.toml", "colour"}),
      scenario(kDeposit + "[material]\ndensty = 1\n", {"material.densty", "did you mean 'density'"}),
      scenario("[container]\nside = -1\nheight = 0.1\n[particles]\ndiameter = 0.01\ncount = 5\n[deposition]\n",
               {"s.toml", "container.side"}),
      scenario("[container]\nside = \"10 parsecs\"\nheight = 0.1\n[particles]\ndiameter = 0.01\ncount = 5\n"
               "[deposition]\n",
               {"container.side", "unit"}),
      scenario("[container]\nside = 0.1\nheight = 0.1\nsides = \"round\"\n[particles]\ndiameter = 0.01\ncount = 5\n"
               "[deposition]\n",
               {"container.sides", "walls", "periodic"}),
      scenario(kBox + "[particles]\ndiameter = 0.01\n[deposition]\n", {"particles.count"}),
      scenario(kBox + "[particles]\ndiameter = 0.01\ncount = 0\n[deposition]\n", {"particles.count"}),
      scenario(kBox + "[particles]\ndiameter = 0.01\ncount = 1.5\n[deposition]\n", {"particles.count", "integer"}),
      scenario(kBox + "[particles]\ndiameter = 0.2\ncount = 5\n[deposition]\n", {"s.toml", "largest diameter", "container"}),
      scenario("[container]\nside = 0.1\nheight = 0.005\n[particles]\ndiameter = 0.01\ncount = 5\n[deposition]\n",
               {"s.toml", "container.height", "largest diameter"}),
      scenario(kBox + "[particles]\ndiameter = 0.01\ncount = 5\n", {"s.toml", "no stage places them", "[deposition]"}),
      scenario(kBox + "[particles]\ndiameter = 0.01\ncount = 5\nfrom = \"x.csv\"\n[deposition]\n",
               {"s.toml", "exactly one of"}),
      scenario(kBox + "[particles]\nclasses = []\n[deposition]\n", {"particles.classes", "at least one"}),
      scenario(kBox + "[particles]\nsolid_volume = 1e-4\nclasses = [{diameter = 0.01, volume_fraction = 0.5}]\n"
                      "[deposition]\n",
               {"particles.classes", "add up to 1"}),
      scenario(kBox + "[particles]\ncount = 5\nclasses = [{diameter = 0.01, count = 5}]\n[deposition]\n",
               {"particles.count", "no total"}),
      scenario(kBox + "[particles]\nclasses = [{diameter = 0.01, count = 5}, {diameter = 0.02, volume_fraction = 1}]\n"
                      "[deposition]\n",
               {"classes", "all give a count or all give a volume_fraction"}),
      scenario(kBox + "[particles]\ndiameter = 1e-6\ncount = 200000000\n[deposition]\n",
               {"s.toml", "particles", "limits.max_particles"}),
      scenario(kBox + "[particles]\ndiameter = 1e-5\ncount = 90000000\n[deposition]\n[limits]\nmax_memory_gib = 1\n",
               {"s.toml", "GiB", "limits.max_memory_gib"}),
      scenario(kBox + "[particles]\nclasses = [{diameter = 1e-6, volume_fraction = 1}]\nsolid_volume = 1e-3\n"
                      "[deposition]\n",
               {"s.toml", "limits.max_particles"}),
      scenario("[container]\nside = \"1000 m\"\nheight = \"1000 m\"\n[particles]\ndiameter = 1e-4\ncount = 5\n"
               "[deposition]\n",
               {"s.toml", "container", "cells", "limits.max_grid_cells"}),
      scenario("[container]\nside = 1000\nheight = 1000\n[particles]\ndiameter = 1e-4\ncount = 5\n[deposition]\n",
               {"s.toml:2:8: container.side", "read as 1000 m", "\"1000 in\""}),
      scenario(kDeposit + "[limits]\nmax_grid_cells = 10\n", {"limits.max_grid_cells"}),
      scenario(kDeposit + "[limits]\nmax_particles = -3\n", {"limits.max_particles"}),
      scenario(kDeposit + "[limits]\nmax_memory_gib = 0\n", {"limits.max_memory_gib", "(0, "}),
      scenario(kDeposit + "[limits]\nspeed = 1\n", {"limits.speed"}),
      // What a run keeps until it ends counts against the memory limit: a copy of the bed per
      // snapshot step, the profiles of each analysis; and a particle file's bed itself.
      scenario(kDeposit + "[limits]\nmax_memory_gib = 0.001\n[[protocol]]\nstep = \"deposit\"\n" + [] {
        std::string steps;
        for (int i = 0; i < 20; ++i) steps += "[[protocol]]\nstep = \"snapshot\"\nname = \"s" + std::to_string(i) + "\"\n";
        return steps;
      }(), {"s.toml", "protocol", "20 snapshot steps", "limits.max_memory_gib"}),
      scenario(kDeposit + "[analysis]\nslice_thickness = 1e-4\n[limits]\nmax_memory_gib = 0.001\n"
                          "[[protocol]]\nstep = \"deposit\"\n" + [] {
        std::string steps;
        for (int i = 0; i < 10; ++i) steps += "[[protocol]]\nstep = \"analyse\"\nname = \"a" + std::to_string(i) + "\"\n";
        return steps;
      }(), {"s.toml", "protocol", "11 analyses", "analysis.slice_thickness", "limits.max_memory_gib"}),
      // The DEM's samples: the quiet window's, scanned at every sample, and all of them kept for
      // timeseries.csv (`check`: a run would go on for hours).
      BadInput{"scenario", {{"s.toml", kDeposit + "[dynamics]\nsample_interval = 1e-6\nquiet_window = 1\n"}},
               "check @/s.toml", {"s.toml", "dynamics.sample_interval", "quiet window", "at most 10000"}},
      BadInput{"scenario",
               {{"s.toml", kDeposit + "[dynamics]\nsample_interval = 1e-6\nquiet_window = 1e-3\nmax_time = 1e4\n"}},
               "check @/s.toml", {"s.toml", "dynamics.sample_interval", "samples for timeseries.csv", "GiB"}},
      BadInput{"scenario",
               {{"s.toml", kBox + "[particles]\nfrom = \"@/bed.csv\"\n[dynamics]\n[limits]\nmax_memory_gib = 1e-5\n"},
                {"bed.csv", lattice()}},
               "check @/s.toml",
               {"s.toml", "particles.from", "27 particles", "with the DEM", "limits.max_memory_gib"}},
      scenario(kDeposit + "[analysis]\nslice_thickness = 1e-9\n", {"s.toml", "analysis.slice_thickness", "bins"}),
      scenario(kDeposit + "[analysis]\nshell_thickness = 1e-9\n", {"s.toml", "analysis.shell_thickness", "bins"}),
      // Slices within the bins' limit, each sphere cut into 9x10^4 of them: `check` of a bed of
      // 1000 spheres took 7.5 s.
      BadInput{"scenario",
               {{"s.toml", kBox + "[particles]\nfrom = \"@/bed.csv\"\n[analysis]\nslice_thickness = 1.1e-7\n"},
                {"bed.csv", lattice()}},
               "check @/s.toml",
               {"s.toml", "analysis.slice_thickness", "into 9.091e+04 slices", "expected at least d_mean / 100 = 0.0001 m"}},
      scenario(kDeposit + "[analysis]\nshell_thickness = 1e-6\n",
               {"s.toml", "analysis.shell_thickness", "shells", "expected at least d_mean / 100"}),
      scenario(kDeposit + "[analysis]\nbox_sides = [0.2]\n", {"s.toml", "analysis.box_sides", "largest admissible"}),
      scenario(kDeposit + "[analysis]\nbox_sides = [-0.01]\n", {"analysis.box_sides"}),
      scenario(kDeposit + "[analysis]\nbox_sides = [0.02" + [] {
        std::string more;
        for (int i = 0; i < 100; ++i) more += ", 0.02";
        return more;
      }() + "]\n", {"s.toml", "analysis.box_sides", "101 sides", "at most 100"}),
      scenario(kDeposit + "[analysis]\ncontact_tolerance = 2\n", {"analysis.contact_tolerance"}),
      scenario(kDeposit + "[analysis]\nplacement = \"random\"\n", {"analysis.placement", "centered"}),
      scenario(kDeposit + "fill_height = 0.005\n", {"deposition.fill_height", "below the largest diameter"}),
      scenario(kDeposit + "fill_height = 0.5\n", {"deposition.fill_height", "above the container height"}),
      scenario(kDeposit + "method = \"rain\"\n", {"deposition.method", "drop_and_roll"}),
      scenario(kDeposit + "tolerance = 1\n", {"deposition.tolerance"}),
      scenario(kDeposit + "[dynamics]\ntime_step = 1e-3\n", {"s.toml", "dynamics.time_step", "Rayleigh",
                                                               "allow_unstable_time_step"}),
      scenario(kDeposit + "[dynamics]\ntime_step_safety = 0.75\n", {"dynamics.time_step_safety", "Rayleigh"}),
      scenario(kDeposit + "[dynamics]\ntime_step = -1\n", {"dynamics.time_step"}),
      scenario(kDeposit + "[dynamics]\nfriction_model = \"glue\"\n", {"dynamics.friction_model", "mindlin"}),
      scenario(kDeposit + "[dynamics]\nmax_time = 0\n", {"dynamics.max_time"}),
      scenario(kDeposit + "[dynamics]\nquiet_window = 0.001\nsample_interval = 0.01\n", {"dynamics.quiet_window"}),
      scenario(kDeposit + "[dynamics]\nlayers = 0\n", {"dynamics.layers"}),
      scenario(kDeposit + "[dynamics]\nallow_unstable_time_step = \"yes\"\n", {"dynamics.allow_unstable_time_step",
                                                                              "true or false"}),
      scenario(kDeposit + "[material]\npoisson_ratio = 0.7\n", {"material.poisson_ratio"}),
      scenario(kDeposit + "[material]\nrestitution = 0\n", {"material.restitution"}),
      scenario(kDeposit + "[material]\nyoungs_modulus = \"hard\"\n", {"material.youngs_modulus", "number"}),
      scenario(kBox + "[particles]\ndiameter = 0.01\ncount = 50\n[pour]\n", {"s.toml", "pour", "[dynamics]"}),
      scenario(kBox + "[particles]\ndiameter = 0.01\ncount = 50\n[pour]\nsolid_fraction = 0.5\n[dynamics]\n",
               {"pour.solid_fraction"}),
      scenario(kDeposit + "[tapping]\n", {"s.toml", "tapping", "[dynamics]"}),
      scenario(kDeposit + "[dynamics]\n[tapping]\ntaps = 0\n", {"tapping.taps"}),
      scenario(kDeposit + "[dynamics]\n[tapping]\nintensity = -2\n", {"tapping.intensity"}),
      // Dynamic set-ups that cannot work, refused before any work (issue 33): a tap that moves
      // the container by kilometres, lasts longer than its rest, or has a period of a few steps;
      // a pour slab kilometres tall, a pour that falls from too high or too fast, or that
      // max_time ends in the air.
      scenario(kDeposit + "[dynamics]\n[tapping]\nfrequency = 0.01\n",
               {"s.toml", "tapping.frequency", "half its height"}),
      scenario(kDeposit + "[dynamics]\n[tapping]\nfrequency = 1e-300\n", {"s.toml", "tapping.frequency"}),
      scenario(kDeposit + "[dynamics]\n[tapping]\nfrequency = 2\nintensity = 0.01\n",
               {"s.toml", "tapping.rest_time", "longer than"}),
      scenario(kDeposit + "[material]\nyoungs_modulus = 1e6\nwall_youngs_modulus = 1e6\n[dynamics]\n[tapping]\n"
                          "frequency = 10000\n",
               {"s.toml", "tapping.frequency", "time steps"}),
      scenario(kBox + "[particles]\ndiameter = 0.01\ncount = 50\n[pour]\nsolid_fraction = 1e-12\n[dynamics]\n",
               {"s.toml", "pour.solid_fraction", "limits.max_grid_cells"}),
      scenario(kBox + "[particles]\ndiameter = 0.01\ncount = 50\n[pour]\nvelocity = 99\n[dynamics]\n",
               {"s.toml", "pour.velocity", "rebound"}),
      scenario(kBox + "[particles]\ndiameter = 0.01\ncount = 50\n[pour]\ngap = \"1000 m\"\n[dynamics]\n",
               {"s.toml", "pour.gap", "rebound"}),
      scenario(kBox + "[particles]\ndiameter = 0.01\ncount = 50\n[pour]\nrelease_height = \"1000 m\"\n[dynamics]\n",
               {"s.toml", "pour.release_height", "rebound"}),
      scenario(kBox + "[particles]\ndiameter = 0.01\ncount = 50\n[pour]\nrelease_height = 0.2\n[dynamics]\n"
                      "engine = \"lammps\"\n",
               {"s.toml", "pour.release_height", "aggpack's own DEM"}),
      scenario(kBox + "[particles]\ndiameter = 0.01\ncount = 50\n[pour]\n[dynamics]\nmax_time = 0.001\n",
               {"s.toml", "dynamics.max_time", "in the air"}),
      // `check` refuses what `run` would refuse at a protocol step: an import_lammps file that
      // is not of the bed (format, count, timestep), a part with no sphere, a step on no bed.
      protocol_check("[[protocol]]\nstep = \"deposit\"\n[[protocol]]\nstep = \"import_lammps\"\nfile = \"bed.csv\"\n",
                     {"s.toml: protocol step 2 (import_lammps)", "bed.csv is a CSV", "expected a LAMMPS dump"}),
      protocol_check("[[protocol]]\nstep = \"deposit\"\n[[protocol]]\nstep = \"import_lammps\"\nfile = \"d.dump\"\n",
                     {"protocol step 2 (import_lammps)", "holds 2 spheres, the bed at this step 500"}),
      protocol_check("[[protocol]]\nstep = \"deposit\"\n[[protocol]]\nstep = \"import_lammps\"\nfile = \"d.dump\"\n"
                     "timestep = 7\n",
                     {"d.dump", "7"}),
      protocol_check("[[protocol]]\nstep = \"analyse\"\nname = \"early\"\n[[protocol]]\nstep = \"deposit\"\n",
                     {"protocol step 1 (early)", "the bed is empty"}),
      BadInput{"scenario", {{"s.toml", kDeposit + "[dynamics]\nlayers = 600\n"}}, "check @/s.toml",
               {"s.toml: protocol step 1 (deposition)", "part 1 of 600 holds no sphere", "at most 500 parts"}},
      scenario(kBox + "[particles]\ndiameter = 0.01\ncount = 50\n[material]\nyoungs_modulus = 1e4\n"
                      "wall_youngs_modulus = 1e4\n[pour]\ngap = 0.5\n[dynamics]\n",
               {"s.toml", "pour.velocity", "passing through"}),
      scenario(kDeposit + "[[protocol]]\nstep = \"shake\"\n", {"protocol", "shake"}),
      scenario(kDeposit + "[output]\nformats = [\"pdf\"]\n", {"output.formats", "csv", "vtp"}),
      scenario(kDeposit + "[output]\nvtp_encoding = \"base64\"\n", {"output.vtp_encoding", "binary", "ascii"}),
      scenario(kDeposit + "seed = -5\n", {"seed"}),
      scenario("seed = 18446744073709551615\n" + kDeposit, {"s.toml"}),
      scenario(kFromFile + "[deposition]\n", {"s.toml", "particles.from"}),
      scenario(kBox + "[particles]\nfrom = \"@/none.csv\"\n", {"particles.from: the particle file", "none.csv\" is not a file: looked for at"}),
      scenario(kBox + "[particles]\nfrom = \"beds/none.csv\"\n", {"particles.from", "\"beds/none.csv\" is not a file: looked for at /"}),
      scenario(kBox + "[particles]\nfrom = \"@\"\n", {"directory", "regular file"}),
      scenario(kBox + "[particles]\nfrom = \"/dev/zero\"\n", {"/dev/zero", "not a regular file"}),
      scenario(kBox + "[particles]\nfrom = \"@/bed.csv\"\nlength_unit = \"furlong\"\n", {"particles.length_unit"}),
      BadInput{"scenario", {{"s.toml", kDeposit + "[output]\ndirectory = \"\"\n"}}, "check @/s.toml",
               {"output.directory", "empty"}},
      scenario(kBox + "[particles]\ndiameter = 0.01\ncount = 20\n[deposition]\n",
               {"s.toml", "the bed will be at most", "virtual cube"}),
      // Gradings: a scenario's sieve file, and `aggpack grading FILE`.
      grading("opening_mm\n4.75\n", {"g.csv:1", "percent_passing"}),
      grading("opening_mm,percent_passing\n4.75,abc\n", {"g.csv:2", "percent passing", "not a number"}),
      grading("opening_mm,percent_passing\n4.75,\n", {"g.csv:2", "missing"}),
      grading("opening_mm,percent_passing\n4.75,100\n2.36,120\n", {"g.csv"}),
      grading("opening_mm,percent_passing\n4.75,50\n2.36,80\n", {"g.csv"}),
      grading("opening_mm,percent_passing\n-4.75,100\n2.36,10\n", {"g.csv"}),
      grading("", {"g.csv"}),
      grading_cli("sieve,percent_passing\n#4,100\n", {"g.csv:1", "opening"}),
      grading_cli(std::string("opening_mm,percent_passing\n4.75,1\0\0", 33), {"g.csv"}),
      // A bare `opening` has no unit: a sand in mm was read in inches (issue 34). Refused with
      // both readings, in a scenario, by `aggpack grading` and by `aggpack predict`.
      grading("sieve,opening,percent_passing\n#200,0.075,2\n#4,4.75,97\n3/8in,9.5,100\n",
              {"g.csv:1", "'opening'", "0.075 mm", "1.905 mm", "opening_mm", "opening_in", "length_unit"}),
      grading_cli("sieve,opening,percent_passing\n#200,0.075,2\n#4,4.75,97\n3/8in,9.5,100\n",
                  {"g.csv:1", "0.075 mm", "1.905 mm", "--length-unit"}),
      BadInput{"grading", {{"g.csv", "opening,percent_passing\n0.075,2\n9.5,100\n"}}, "predict @/g.csv",
               {"g.csv:1", "0.075 mm", "1.905 mm"}},
      // A designation that contradicts its opening: the row, the designation's opening and the file's.
      grading("sieve,opening_in,percent_passing\n#200,0.075,2\n#4,4.75,97\n3/8in,9.5,100\n",
              {"g.csv: line 2", "'#200'", "0.075 mm", "1.905 mm (0.075 in)"}),
      BadInput{"grading", {{"g.csv", "sieve,opening,percent_passing\n#200,0.075,2\n#4,4.75,97\n3/8in,9.5,100\n"}},
               "grading @/g.csv --length-unit in", {"g.csv: line 2", "'#200'", "0.075 mm", "1.905 mm"}},
      scenario(kBox + "[particles]\ncount = 10\n[particles.grading]\nsieves = [{ sieve = \"#4\", "
                      "opening = \"4.75 in\", passing = 50 }, { opening = \"10 in\", passing = 100 }]\n[deposition]\n",
               {"particles.grading.sieves[0]", "'#4'", "4.75 mm", "120.6 mm"}),
      BadInput{"grading", {}, "grading @", {"directory", "regular file"}},
      BadInput{"grading", {}, "grading /dev/zero", {"/dev/zero", "not a regular file"}},
      BadInput{"grading", {}, "grading @/missing.csv", {"missing.csv"}},
      // Particle files: format, numbers, and the physics of the bed.
      particles("", {"bed.csv", "no particles"}),
      particles("x,y,z\n0,0,0\n", {"bed.csv:1", "header", "x, y, z and r"}),
      particles("x,y,z,r\n0.05,0.05,0.05\n", {"bed.csv:2", "fields"}),
      particles("x,y,z,r\n0.05,0.05,abc,0.005\n", {"bed.csv:2", "not a number"}),
      particles("x,y,z,r\n0.05,0.05,0.05,-0.005\n", {"bed.csv:2", "radius", "positive"}),
      particles("x,y,z,r\n0.05,0.05,0.05,nan\n", {"bed.csv:2", "not a number"}),
      particles("x,y,z,r\n0.05,0.05,1e400,0.005\n", {"bed.csv:2", "not a number"}),
      particles("x,x,y,z,r\n0,0.05,0.05,0.05,0.005\n", {"bed.csv:1", "twice"}),
      particles("x,y,z,r,d\n0.05,0.05,0.05,0.005,0.01\n", {"bed.csv:1", "twice"}),
      particles("0.05 0.05 0.05 0.005 1\n", {"bed.csv:1", "exactly 4 numbers"}),
      particles("x,y,z,r\n0.05,0.05,0.005,0.005\n0.05,0.05,0.005,0.005\n", {"bed.csv", "same place", "coincident"}),
      particles("x,y,z,r\n0.05,0.05,0.005,0.005\n0.052,0.05,0.005,0.005\n",
                {"bed.csv", "overlap", "particles.overlap_tolerance", "soft_contacts"}),
      particles("x,y,z,r\n0.05,0.05,0.05,0.005\n0.05,0.05,0.5,0.005\n", {"bed.csv", "data row 2", "container"}),
      particles("x,y,z,r\n0.05,0.05,0.003,0.005\n", {"bed.csv", "floor"}),
      particles(lattice() + "0.05,0.05,1e6,0.005\n", {"bed.csv", "container"}),
      analyze("x,y,z,r\n0,0,0,0.005\n1000000,1000000,0,0.005\n", "", {"bed.csv", "cells"}),
      analyze(lattice() + "0.05,0.05,1000000,0.005\n", "", {"bed.csv", "cells", "far from the others"}),
      analyze("x,y,z,r\n0,0,0,0.5\n0,0,0,0.5\n", "", {"bed.csv", "coincident"}),
      analyze("x,y,z,r\n0,0,0,0.5\n0.1,0,0,0.5\n", "", {"bed.csv", "overlap", "--soft-contacts"}),
      analyze("x,y,z,r\n0,0,0,0.5\n0.01,0,0,0.5\n", " --soft-contacts", {"bed.csv", "centre is inside"}),
      analyze(lattice(), " --box 1,1,1,2,2,2", {"bed.csv", "does not lie inside the packing"}),
      analyze(lattice(), " --cube 1", {"bed.csv", "virtual cube"}),
      // A sphere 100 times smaller than the others looking for contacts 25 of its diameters away.
      analyze(lattice() + "0.09,0.09,0.0001,0.00005\n", " --tolerance 0.5",
              {"--tolerance 0.5", "bed.csv", "25.25 of its diameters", "at most 4"}),
      BadInput{"scenario",
               {{"s.toml", kBox + "[particles]\nfrom = \"@/bed.csv\"\n[analysis]\ncontact_tolerance = 0.5\n"},
                {"bed.csv", lattice() + "0.09,0.09,0.0001,0.00005\n"}},
               "check @/s.toml",
               {"s.toml", "analysis.contact_tolerance", "25.25 of its diameters", "at most 0.07921"}},
      // Each box is a pass over every sphere: 10^5 box sides over 8000 spheres, a 0.5 MB
      // scenario, made `check` take 8 s.
      analyze(lattice(), [] {
        std::string cubes;
        for (int i = 0; i < 101; ++i) cubes += " --cube 0.005";
        return cubes;
      }(), {"--box, --cube", "101 boxes", "at most 100"}),
      analyze(lattice(), " --box 1,2,3", {"--box", "xmin,ymin,zmin,xmax,ymax,zmax"}),
      analyze(lattice(), " --length-unit parsec", {"--length-unit", "unknown unit"}),
      BadInput{"particles", {}, "analyze @", {"directory", "regular file"}},
      BadInput{"particles", {}, "analyze /dev/zero", {"/dev/zero", "not a regular file"}},
      // Calibration files (aggpack calibrate's), read by predict --calibration and by a scenario's models.calibration.
      calibration("predict @/s.toml --calibration @/c.json", "[]",
                  {"c.json", "cpm.compaction_index_range", "an empty array", "expected [low, high]"}),
      calibration("predict @/s.toml --calibration @/c.json", "[6.0]",
                  {"c.json", "cpm.compaction_index_range", "an array of 1 element", "expected [low, high]"}),
      calibration("predict @/s.toml --calibration @/c.json", "[\"6\", null]",
                  {"c.json", "cpm.compaction_index_range[0]", "a string", "expected a number or null"}),
      calibration("run @/m.toml", "[]", {"c.json", "cpm.compaction_index_range", "an empty array"}),
      calibration("run @/m.toml", "[6.0]", {"c.json", "cpm.compaction_index_range", "an array of 1 element"}),
      // The command line.
      command("run @/s.toml --threads 100000", {"--threads", "256"}),
      command("run @/s.toml --threads 1000", {"--threads", "256"}),
      command("run @/s.toml --threads -1", {"--threads"}),
      command("run @/s.toml --seed -1", {"--seed"}),
      command("run @/s.toml --seed 18446744073709551616", {"--seed"}),
      command("run @/s.toml --seed abc", {"--seed"}),
      command("run @/s.toml --stop-after sieving", {"sieving"}),
      command("run @/s.toml --set nonsense", {"--set nonsense", "key.path=value"}),
      command("run @/s.toml --set container.side.x=1", {"--set", "not a table"}),
      command("run @/s.toml --set particles.count=-4", {"particles.count", "--set"}),
      command("run @/s.toml --out @/s.toml", {"s.toml", "is a file"}),
      command("run @/s.toml --out @/s.toml/sub", {"s.toml", "is a file"}),
      command("run @/s.toml --out ''", {"output", "empty"}),
      command("run @/s.toml --out /proc/aggpack", {"/proc/aggpack", "cannot make the output folder"}),
      command("check @/s.toml --set output.directory=\\\"@/s.toml\\\"", {"s.toml", "is a file"}),
      command("check @/s.toml --set dynamics.time_step=1", {"dynamics.time_step", "Rayleigh"}),
      command("check @/s.toml --set analysis.box_sides=[0.5]", {"analysis.box_sides", "largest admissible"}),
      command("check @/s.toml --set particles.count=900000000", {"limits.max_particles"}),
      command("run @/missing.toml", {"missing.toml", "no such file"}),
      command("run @", {"directory", "regular file"}),
      command("run /dev/zero", {"/dev/zero", "not a regular file"}),
      command("frobnicate", {"unknown subcommand", "frobnicate"}),
      command("run", {"scenario"}),
      command("analyze @/bed.csv --tolerance 5", {"--tolerance"}),
      command("analyze @/bed.csv --overlap-tolerance 2", {"--overlap-tolerance"}),
      command("grading", {"grading"}),
      command("grading nonesuch_grading", {"nonesuch_grading"}),
      command("grading astm_c33_57_mid --band nowhere", {"nowhere"}),
      command("sweep @/s.toml --fa 10:5:1", {"--fa"}),
      command("reproduce --seeds 0", {"--seeds"}),
      command("reproduce --threads 5000", {"--threads"}),
      command("run @/s.toml --checkpoint-every abc", {"--checkpoint-every abc", "seconds"}),
      command("run @/s.toml --checkpoint-every -5", {"--checkpoint-every -5", "seconds"}),
      command("run @/s.toml --checkpoint-every 5 --no-checkpoint", {"--checkpoint-every", "--no-checkpoint"}),
      command("check @/s.toml --set output.checkpoint_every=-1", {"output.checkpoint_every", "[0, 1e+09]"}),
      command("check @/s.toml --set output.checkpoint=yes", {"output.checkpoint", "true or false"}),
      command("resume", {"run_dir"}),
      command("resume @/s.toml", {"s.toml", "no such directory"}),
      command("resume @", {"no checkpoint.bin here"}),
  };
}

std::string substitute(std::string text, const std::string& dir) {
  for (std::size_t at = text.find('@'); at != std::string::npos; at = text.find('@', at + dir.size()))
    text.replace(at, 1, dir);
  return text;
}

class Reliability : public ::testing::Test {
 protected:
  aggpack::testing::ScratchDir scratch_{"aggpack_reliability_"};
  const fs::path& dir_ = scratch_.path();
};

TEST_F(Reliability, EveryBadInputIsRefusedWithExitTwoAClearMessageAndNothingWritten) {
  const std::vector<BadInput> cases = bad_inputs();
  std::map<std::string, int> per_kind;
  for (const BadInput& c : cases) ++per_kind[c.kind];
  EXPECT_GE(cases.size(), 80u);
  for (const auto& kind : {"scenario", "grading", "particles", "command line"}) EXPECT_GE(per_kind[kind], 10) << kind;

  const fs::path out = dir_ / "out";
  for (const BadInput& c : cases) {
    const fs::path here = dir_ / "case";
    fs::remove_all(here);
    fs::create_directories(here);
    for (const auto& [name, text] : c.files) std::ofstream(here / name, std::ios::binary) << substitute(text, here.string());
    const std::string args = substitute(c.arguments, here.string());
    // Every run writes (if it wrote anything) into `out`, unless the case names its own folder.
    const bool own_out = args.find("--out") != std::string::npos || args.rfind("run", 0) != 0;
    const auto r = run_cli(args + (own_out ? "" : " --out " + out.string()));
    SCOPED_TRACE(c.kind + ": aggpack " + args);
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_EQ(r.output.find("internal error"), std::string::npos) << r.output;
    for (const std::string& word : c.expected)
      EXPECT_NE(r.output.find(substitute(word, here.string())), std::string::npos) << "missing \"" << word << "\" in\n"
                                                                                   << r.output;
    EXPECT_FALSE(fs::exists(out)) << r.output;
    // Nothing written beside the inputs either (a refused run makes no folder, no temporary file).
    std::size_t files = 0;
    for (const auto& entry : fs::recursive_directory_iterator(here)) files += entry.is_regular_file() ? 1 : 0;
    EXPECT_EQ(files, c.files.size()) << r.output;
  }
}

// A bound is printed as a person would write it: CLI11's PositiveNumber printed its bounds as
// "0.000000 to 179769313486231570814527...000.000000" (DBL_MAX in full, 309 digits).
TEST_F(Reliability, OptionBoundsAreWrittenAsAPersonWouldWriteThem) {
  std::ofstream(dir_ / "s.toml") << kDeposit;
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"predict fu2003_table1_coarse --mix astm_c33_fine_mid --ca-fa -1", "--ca-fa -1: expected a number above 0"},
      {"predict fu2003_table1_coarse --mix astm_c33_fine_mid --ca-fa 0", "--ca-fa 0: expected a number above 0"},
      {"sweep " + (dir_ / "s.toml").string() + " --fa 30 --seeds 0", "--seeds 0: expected a whole number, 1 or more"},
      {"reproduce --seeds 0 --out " + (dir_ / "r").string(), "--seeds 0: expected a whole number, 1 or more"},
      {"reproduce --seeds 1.5 --out " + (dir_ / "r").string(), "--seeds 1.5: expected a whole number, 1 or more"},
  };
  for (const auto& [arguments, expected] : cases) {
    SCOPED_TRACE("aggpack " + arguments);
    const auto r = run_cli(arguments);
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find(expected), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("0000000000"), std::string::npos) << r.output;
  }
  EXPECT_FALSE(fs::exists(dir_ / "r"));
}

// whole-grading and sweep try each cut-off as the finest grading's d_min: a cut-off the
// scenario refuses is quoted as the user typed it, not as the internal --set that carries it.
TEST_F(Reliability, ACutOffIsQuotedAsTyped) {
  const std::string mix = std::string(AGGPACK_EXAMPLES) + "/table2_mix3.toml";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"whole-grading " + mix + " --cut-offs 0.1in,-0.07in,0.04in",
       "--cut-offs -0.07in: particles.fine.d_min: expected a positive number"},
      {"whole-grading " + mix + " --cut-offs 0.1in,5in,0.04in", "--cut-offs 5in: particles.fine: the cut-offs"},
      {"sweep " + mix + " --fa 30,35 --cut-offs 0.1in,0.07in,-2mm --out " + (dir_ / "sweep").string(),
       "--cut-offs -2mm: particles.fine.d_min: expected a positive number"},
  };
  for (const auto& [arguments, expected] : cases) {
    SCOPED_TRACE("aggpack " + arguments);
    const auto r = run_cli(arguments);
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find(expected), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("--set"), std::string::npos) << r.output;
  }
  EXPECT_FALSE(fs::exists(dir_ / "sweep"));
}

// A settling run stopped by a signal: it stops at the next sample, writes the bed as it stood,
// its samples and a summary marked interrupted, and exits with 128 + the signal.
std::optional<int> run_and_signal(const fs::path& scenario, const fs::path& out, int signal_number) {
  // The folder appears once every check has passed; the DEM is then under way within a second.
  std::optional<std::chrono::steady_clock::time_point> began;
  return signal_aggpack_when(
      {"run", scenario.string(), "--quiet", "--threads", "1", "--out", out.string()},
      [&] {
        if (!began && fs::exists(out)) began = std::chrono::steady_clock::now();
        return began && std::chrono::steady_clock::now() - *began >= std::chrono::milliseconds(1500);
      },
      signal_number, std::chrono::seconds(30));
}

TEST_F(Reliability, SigintAndSigtermStopAtASafePointWithAnInterruptedSummary) {
  const fs::path scenario = dir_ / "long.toml";
  // A bed that settles for far longer than the test waits.
  std::ofstream(scenario) << "[container]\nside = 0.1\nheight = 0.2\n[particles]\ndiameter = 0.008\ncount = 1500\n"
                             "[material]\nyoungs_modulus = 1e8\nwall_youngs_modulus = 1e8\n[deposition]\n"
                             "[dynamics]\nmax_time = 100\n";
  for (const auto& [signal_number, code] : {std::pair{SIGINT, 130}, std::pair{SIGTERM, 143}}) {
    const fs::path out = dir_ / ("stopped_" + std::to_string(signal_number));
    const std::optional<int> got = run_and_signal(scenario, out, signal_number);
    ASSERT_TRUE(got.has_value()) << "the run ended before it was signalled";
    EXPECT_EQ(*got, code);
    const auto summary = nlohmann::json::parse(std::ifstream(out / "summary.json"));
    EXPECT_TRUE(summary.at("interrupted").get<bool>());
    EXPECT_EQ(summary.at("interruption").at("signal").get<int>(), signal_number);
    EXPECT_EQ(summary.at("seed").get<int>(), 1);
    EXPECT_TRUE(summary.contains("aggpack_version"));
    EXPECT_TRUE(fs::exists(out / "particles.csv"));
    // The stop's own checkpoint, for aggpack resume (tests/cli/test_resume.cpp resumes one).
    EXPECT_TRUE(fs::exists(out / "checkpoint.bin"));
    EXPECT_EQ(summary.at("interruption").at("checkpoint").at("taken"), summary.at("interruption").at("stopped"));
    for (const auto& entry : fs::directory_iterator(out))
      EXPECT_EQ(entry.path().filename().string().find(".aggpack-incomplete."), std::string::npos) << entry.path();
  }
}

// A killed run's temporary files are removed by the next run into the same folder; a user's
// files whose names merely look temporary are not (issue 33: they were deleted).
TEST_F(Reliability, ANewRunRemovesAKilledRunsTemporaryFilesAndNoUserFile) {
  const fs::path out = dir_ / "out";
  fs::create_directories(out);
  std::ofstream(out / "particles.csv.aggpack-incomplete.99999") << "half a file";
  const std::vector<std::string> users = {"notes.tmp.txt", "data.tmp.1.csv", "particles.csv.tmp.99999",
                                          "x.aggpack-incomplete.12a", ".aggpack-incomplete.1"};
  for (const auto& name : users) std::ofstream(out / name) << "mine";
  std::ofstream(dir_ / "s.toml") << kDeposit;
  // The user's files are not an earlier run's: the run is refused (naming them) unless --overwrite.
  const auto refused = run_cli("run " + (dir_ / "s.toml").string() + " --quiet --out " + out.string());
  EXPECT_EQ(refused.exit_code, 2) << refused.output;
  EXPECT_NE(refused.output.find("--overwrite"), std::string::npos) << refused.output;
  const auto r = run_cli("run " + (dir_ / "s.toml").string() + " --quiet --overwrite --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_FALSE(fs::exists(out / "particles.csv.aggpack-incomplete.99999"));
  for (const auto& name : users) EXPECT_EQ(aggpack::testing::slurp(out / name), "mine") << name;
  EXPECT_TRUE(fs::exists(out / "summary.json"));
}

}  // namespace
