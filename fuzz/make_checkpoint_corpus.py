#!/usr/bin/env python3
"""Writes the checkpoint_reader target's seed corpus, fuzz/corpus/checkpoint/*.bin, again: real
checkpoints of small runs at the safe points named below. Run it after the checkpoint format
changes (a corpus of an older format only exercises the format check).

  python3 fuzz/make_checkpoint_corpus.py build/aggpack

Each run checkpoints at every safe point (output.checkpoint_every = 0); the script copies
checkpoint.bin as soon as it holds the safe point wanted (checkpoints are written atomically,
so every copy is whole), then stops the run. "before step 1" is taken of a bed of 20 000 small
spheres, whose deposition lasts long enough to be seen. A safe point that passed between two
looks is reported as missed; the files of the others are written.
"""
import os
import pathlib
import shutil
import subprocess
import sys
import tempfile
import time

COMMON = """[dynamics]
max_time = {max_time}
quiet_kinetic_fraction = 1e-30
sample_interval = 0.002
quiet_window = 0.004{extra_dynamics}
[material]
youngs_modulus = 1e8
wall_youngs_modulus = 1e8
[analysis]
box_sides = [0.004]
"""

SCENARIOS = {
    "deposit_settle": "seed = 1\n[container]\nside = 0.04\nheight = 0.2\n[particles]\ndiameter = 0.01\ncount = 50\n"
                      "[deposition]\n" + COMMON.format(max_time=2, extra_dynamics=""),
    # Only its first checkpoint is kept: the deposition of 20 000 spheres lets it be seen.
    "deposit_settle_many": "seed = 1\n[container]\nside = 0.04\nheight = 0.2\n[particles]\ndiameter = 0.002\n"
                           "count = 20000\n[deposition]\n" + COMMON.format(max_time=2, extra_dynamics=""),
    "layered": "seed = 2\n[container]\nside = 0.04\nheight = 0.3\n[particles]\ndiameter = 0.01\ncount = 60\n"
               "[deposition]\n" + COMMON.format(max_time=2, extra_dynamics="\nlayers = 2"),
    "periodic_binary": "seed = 3\n[container]\nside = 0.045\nheight = 0.2\nsides = \"periodic\"\n[particles]\n"
                       "classes = [{diameter = 0.01, count = 40}, {diameter = 0.006, count = 60}]\n[deposition]\n"
                       + COMMON.format(max_time=2, extra_dynamics=""),
    "pour": "seed = 4\n[container]\nside = 0.04\nheight = 0.3\n[particles]\ndiameter = 0.01\ncount = 40\n"
            "[pour]\nbatches = 2\n" + COMMON.format(max_time=2, extra_dynamics=""),
    "pour_tap": "seed = 7\n[container]\nside = 0.04\nheight = 0.3\n[particles]\ndiameter = 0.01\ncount = 40\n"
                "[pour]\nbatches = 2\n[tapping]\ntaps = 2\nintensity = 3\nrest_time = 0.05\n"
                + COMMON.format(max_time=0.5, extra_dynamics="").replace("quiet_kinetic_fraction = 1e-30\n", ""),
    # Two materials and the spring-dashpot rolling law: the rolling history and the materials.
    "materials_rolling": "seed = 8\n[container]\nside = 0.04\nheight = 0.3\n[particles]\nclasses = [{diameter = 0.01, "
                         "count = 30, material = \"stone\"}, {diameter = 0.007, count = 40, material = \"sand\"}]\n"
                         "[materials.stone]\ndensity = 2700\nrolling_friction = 0.2\n[materials.sand]\n"
                         "density = 2600\nfriction_particle = 0.4\n[pour]\nbatches = 2\n"
                         + COMMON.format(max_time=2, extra_dynamics="").replace(
                             "[material]\n", "[material]\nrolling_model = \"spring_dashpot\"\nrolling_friction = 0.1\n"
                                             "rolling_stiffness = 50\nrolling_damping = 0.01\n"),
    "tap": "seed = 6\n[container]\nside = 0.04\nheight = 0.2\n[particles]\ndiameter = 0.01\ncount = 40\n"
           "[deposition]\n[tapping]\ntaps = 3\nintensity = 3\nrest_time = 0.5\n"
           + COMMON.format(max_time=0.05, extra_dynamics="").replace("quiet_kinetic_fraction = 1e-30\n", ""),
}

# corpus file -> (scenario, the safe point's words in the checkpoint's header)
TARGETS = {
    "deposit_settle_before_step_1": ("deposit_settle_many", b"before step 1 of"),
    "deposit_settle_before_step_2": ("deposit_settle", b"before step 2 of"),
    "deposit_settle_while_settling": ("deposit_settle", b"while settling at"),
    "layered_while_settling": ("layered", b"while settling at"),
    "periodic_binary_while_settling": ("periodic_binary", b"while settling at"),
    "pour_while_pouring": ("pour", b"while pouring,"),
    "pour_while_settling": ("pour", b"while settling at"),
    "tap_while_tap_2": ("tap", b"while tap 2 of"),
    "materials_rolling_while_pouring": ("materials_rolling", b"while pouring,"),
    "materials_rolling_while_settling": ("materials_rolling", b"while settling at"),
    # Between a pour and its taps: the run state holds the DEM system the taps continue.
    "pour_tap_before_step_3": ("pour_tap", b"before step 3 of"),
}


def capture(aggpack, folder, scenario, wanted):
    """The first checkpoint.bin of `scenario` whose bytes hold `wanted`, or None."""
    out = folder / ("out_" + scenario)
    shutil.rmtree(out, ignore_errors=True)
    command = [aggpack, "run", f"{scenario}.toml", "--set", "output.checkpoint_every=0", "--threads", "1",
               "--quiet", "--out", out.name]
    process = subprocess.Popen(command, cwd=folder, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    found, deadline = None, time.monotonic() + 60
    try:
        while time.monotonic() < deadline:
            try:
                data = (out / "checkpoint.bin").read_bytes()
            except OSError:
                data = b""
            if wanted in data:
                found = data
                break
            if process.poll() is not None and not data:
                break
            time.sleep(0.0005)
    finally:
        if process.poll() is None:
            process.kill()
        process.wait()
    return found


def main(aggpack):
    aggpack = str(pathlib.Path(aggpack).resolve())
    corpus = pathlib.Path(__file__).resolve().parent / "corpus" / "checkpoint"
    missed = []
    with tempfile.TemporaryDirectory(prefix="ckcorpus") as tmp:
        folder = pathlib.Path(tmp)
        for name, text in SCENARIOS.items():
            (folder / f"{name}.toml").write_text(text)
        for target, (scenario, wanted) in TARGETS.items():
            data = capture(aggpack, folder, scenario, wanted)
            if data is None:
                missed.append(target)
                continue
            (corpus / f"{target}.bin").write_bytes(data)
            print(f"{target}.bin: {len(data)} bytes")
    if missed:
        sys.exit(f"missed (their old files are kept): {', '.join(missed)}")


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
