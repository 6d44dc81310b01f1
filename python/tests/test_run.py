"""Runs from Python against `aggpack run` on the same scenario and seed; the bed's arrays."""
import gc
import json
import os
import pickle
import signal
import threading

import numpy as np
import pytest

import aggpack
from conftest import EXAMPLES, cli

# Example 1 cut short: deposition, then a tenth of a second of DEM.
SHORT = ["dynamics.max_time=0.1"]

# Keys of summary.json that time the machine, not the run.
TIMING = {"wall_clock_s", "particles_per_second", "particle_steps_per_second", "steps_on_fewer_threads", "threads",
          "memory_bytes_per_particle"}


def without_timing(value):
    """A summary without what times the machine, and without its output folder."""
    if isinstance(value, dict):
        return {k: without_timing(v) for k, v in value.items() if k not in TIMING and k != "directory"}
    if isinstance(value, list):
        return [without_timing(v) for v in value]
    return value


@pytest.fixture(scope="module")
def cli_run(tmp_path_factory):
    """Example 1, cut short, run by the CLI: what the Python runs must give."""
    out = tmp_path_factory.mktemp("cli") / "example1"
    cli("run", EXAMPLES / "example1.toml", "--quiet", "--threads", "1", "--set", SHORT[0], "--out", out)
    return out


def test_a_run_into_a_folder_writes_what_the_cli_writes(tmp_path, examples, cli_run):
    s = aggpack.Scenario.from_file(examples / "example1.toml", set=SHORT)
    report = aggpack.run(s, out=tmp_path / "py", threads=2)
    assert report.output_directory == tmp_path / "py"
    assert (tmp_path / "py" / "particles.csv").read_bytes() == (cli_run / "particles.csv").read_bytes()
    assert (tmp_path / "py" / "timeseries.csv").read_bytes() == (cli_run / "timeseries.csv").read_bytes()
    written = json.loads((tmp_path / "py" / "summary.json").read_text())
    assert report.summary() == written
    assert without_timing(written) == without_timing(json.loads((cli_run / "summary.json").read_text()))
    # Written again into the same folder: an earlier run's files are replaced, none left over.
    (tmp_path / "py" / "taps.csv").write_text("an earlier run's\n")
    manifest = json.loads((tmp_path / "py" / "aggpack-manifest.json").read_text())
    manifest["files"].append("taps.csv")
    (tmp_path / "py" / "aggpack-manifest.json").write_text(json.dumps(manifest))
    aggpack.write_outputs(report, tmp_path / "py")
    assert not (tmp_path / "py" / "taps.csv").exists()
    assert not (tmp_path / "py" / "checkpoint.bin").exists()  # a finished run's is removed


def test_a_run_in_memory_gives_the_clis_numbers_and_writes_its_bytes_later(tmp_path, examples, cli_run):
    report = aggpack.run(aggpack.Scenario.from_file(examples / "example1.toml", set=SHORT), threads=1)
    assert report.output_directory is None
    assert not any(tmp_path.iterdir())
    cli_summary = json.loads((cli_run / "summary.json").read_text())
    assert report.density == cli_summary["density"]["mean"]
    assert report.density_after_deposition == cli_summary["stages"]["deposition"]["density"]["mean"]
    assert report.notes == cli_summary["modelling_notes"]
    assert report.analysis["density"] == cli_summary["density"]
    summary = report.summary()
    assert without_timing(summary) == without_timing(cli_summary)
    # Every stage's time and the total, as summary.json's wall_clock_s (it had only input, sizes, ...).
    assert {"deposition", "dynamics", "analysis_after_deposition", "total"} <= set(report.wall_clock)
    assert report.wall_clock == summary["wall_clock_s"]
    written = aggpack.write_outputs(report, tmp_path / "later")
    assert (tmp_path / "later" / "particles.csv").read_bytes() == (cli_run / "particles.csv").read_bytes()
    assert without_timing(written) == without_timing(cli_summary)
    # summary.json names the folder it is in (it named the scenario's output.directory), as `run --out`.
    assert written["scenario"]["output"]["directory"] == str(tmp_path / "later")
    assert json.loads((tmp_path / "later" / "summary.json").read_text()) == written
    # A folder of someone else's files is refused, as the CLI refuses it.
    (tmp_path / "theirs").mkdir()
    (tmp_path / "theirs" / "notes.txt").write_text("mine")
    with pytest.raises(aggpack.InputError, match="notes.txt"):
        aggpack.write_outputs(report, tmp_path / "theirs")
    # A folder that cannot be made is an input error naming it (issue 55, item 11), not an
    # internal filesystem error.
    with pytest.raises(aggpack.InputError, match="/proc/x"):
        aggpack.write_outputs(report, "/proc/x")


def test_the_beds_arrays_are_particles_csv(cli_run, examples):
    report = aggpack.run(aggpack.Scenario.from_file(examples / "example1.toml", set=SHORT), threads=1)
    table = np.loadtxt(cli_run / "particles.csv", delimiter=",", skiprows=1)
    bed = report.bed
    assert len(bed) == bed.count == table.shape[0] == 1733
    assert bed.positions.shape == (1733, 3) and bed.positions.dtype == np.float64
    assert bed.radii.shape == (1733,) and bed.radii.dtype == np.float64
    assert bed.velocities.shape == (1733, 3)
    assert bed.materials.dtype == np.uint8 and bed.layers.dtype == np.uint32
    assert np.array_equal(bed.positions, table[:, 1:4])
    assert np.array_equal(bed.radii, table[:, 4])
    assert bed.grains is None and bed.grain_count == 0
    assert np.array_equal(report.deposited.radii, bed.radii)
    assert not np.array_equal(report.deposited.positions, bed.positions)  # the DEM moved it


def test_a_view_is_read_only_and_outlives_its_report(examples):
    report = aggpack.run(aggpack.Scenario.from_file(examples / "example1.toml"), stop_after="deposition", threads=1)
    positions = report.bed.positions
    copies = report.bed.copy()
    assert not positions.flags.writeable and not positions.flags.owndata
    with pytest.raises(ValueError):
        positions[0, 0] = 1.0
    copies["positions"][0, 0] = 1.0  # a copy is the user's
    del report
    gc.collect()
    # Another run now, in memory the report would have freed: the view still shows its bed.
    other = aggpack.run(aggpack.Scenario.from_file(examples / "example1.toml", seed=2), stop_after="deposition")
    assert not np.array_equal(other.bed.positions, positions)
    assert positions[0, 0] != 1.0
    assert np.array_equal(positions[1:], copies["positions"][1:])
    assert positions.base is not None and isinstance(positions.base, aggpack.Bed)


# 150 rounded grains of 2 spheres (I = 8 mm) and 40 spheres of 5 mm, poured and settled.
GRAINS = {
    "title": "grains", "seed": 2,
    "container": {"side": 0.045, "height": 0.3},
    "particles": {"classes": [
        {"diameter": 0.008, "count": 150, "shape": {"family": "rounded", "spheres": 2, "templates": 3}},
        {"diameter": 0.005, "count": 40}]},
    "material": {"youngs_modulus": 1e7, "wall_youngs_modulus": 1e7, "friction_particle": 0.5},
    "pour": {"solid_fraction": 0.15},
    "dynamics": {"max_time": 0.8},
    "analysis": {"box_sides": [0.006]},
}


def test_grains_come_with_their_sphere_to_grain_map(tmp_path):
    report = aggpack.run(aggpack.Scenario.from_dict(GRAINS), out=tmp_path / "grains", threads=1)
    bed = report.bed
    assert bed.grain_count == 150
    grains = bed.grains
    assert grains.shape == (len(bed),) == (340,) and grains.dtype == np.uint32
    members = grains[grains != aggpack.NO_GRAIN]
    assert len(members) == 300
    assert np.array_equal(np.bincount(members), np.full(150, 2))
    # particles.csv's grain column is this + 1, 0 for a sphere of its own.
    column = np.loadtxt(tmp_path / "grains" / "particles.csv", delimiter=",", skiprows=1)[:, 5].astype(np.int64)
    assert np.array_equal(column, np.where(grains == aggpack.NO_GRAIN, 0, grains.astype(np.int64) + 1))
    table = np.loadtxt(tmp_path / "grains" / "grains.csv", delimiter=",", skiprows=1, usecols=range(9))
    assert np.array_equal(bed.grain_positions, table[:, 1:4])
    assert np.array_equal(bed.grain_orientations, table[:, 4:8])
    q = bed.grain_orientations
    assert np.allclose(np.einsum("ij,ij->i", q, q), 1.0, atol=1e-12)
    assert np.allclose(np.cbrt(6.0 / np.pi * bed.grain_volumes), table[:, 8], rtol=1e-12)
    # A starting bed is of spheres: grains are generated from sizes and poured.
    given = {key: value for key, value in GRAINS.items() if key != "pour"}
    given["particles"] = {"from": "-"}
    with pytest.raises(aggpack.InputError, match="holds grains; a starting bed is of spheres"):
        aggpack.run(aggpack.Scenario.from_dict(given), bed=bed)


def test_ctrl_c_stops_at_a_safe_point_and_resume_gives_the_uninterrupted_bytes(tmp_path, examples, cli_run):
    s = aggpack.Scenario.from_file(examples / "example1.toml", set=SHORT)
    timer = threading.Timer(0.3, os.kill, (os.getpid(), signal.SIGINT))
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt) as stopped:
            aggpack.run(s, out=tmp_path / "run", threads=1)
    finally:
        timer.cancel()
    partial = stopped.value.report
    assert partial.interrupted["signal"] == signal.SIGINT
    assert partial.interrupted["checkpoint"]
    assert f'aggpack.resume("{tmp_path / "run"}")' in str(stopped.value)
    assert "steps done" in str(stopped.value)
    assert (tmp_path / "run" / "checkpoint.bin").exists()
    assert partial.summary()["interrupted"] is True
    resumed = aggpack.resume(tmp_path / "run", threads=2)
    assert resumed.interrupted is None
    assert (tmp_path / "run" / "particles.csv").read_bytes() == (cli_run / "particles.csv").read_bytes()


def test_progress_reaches_a_callback_and_its_exception_ends_the_run(examples):
    seen = []
    aggpack.run(aggpack.Scenario.from_file(examples / "example1.toml", set=SHORT), threads=1, progress=seen.append)
    assert seen, "no progress in a run of a second or more"
    assert {u["stage"] for u in seen} <= {"deposition", "dynamics", "analysis"}
    assert all(0.0 <= u["done"] <= 1.0 and isinstance(u["fields"], list) for u in seen)

    class Enough(Exception):
        pass

    def stop(update):
        raise Enough(update["stage"])

    with pytest.raises(Enough):
        aggpack.run(aggpack.Scenario.from_file(examples / "example1.toml", set=SHORT), threads=1, progress=stop)
    with pytest.raises(TypeError, match="progress: expected a callable"):
        aggpack.run(aggpack.Scenario.from_file(examples / "example1.toml", set=SHORT), progress=3)


def test_an_interrupted_run_measured_no_density_and_says_so(examples):
    # Stopped as the DEM begins (its first progress update): no final analysis was made.
    def stop_in_dynamics(update):
        if update["stage"] == "dynamics":
            os.kill(os.getpid(), signal.SIGINT)

    with pytest.raises(KeyboardInterrupt) as stopped:
        aggpack.run(aggpack.Scenario.from_file(examples / "example1.toml", set=SHORT), threads=1,
                    progress=stop_in_dynamics)
    partial = stopped.value.report
    assert partial.interrupted["signal"] == signal.SIGINT
    assert np.isnan(partial.density)
    assert np.isnan(partial.density_after_dynamics)
    assert partial.analysis is None
    assert partial.density_after_deposition > 0.5  # measured before the stop
    assert "density not measured" in repr(partial) and "0.000000" not in repr(partial)
    summary = partial.summary()
    assert summary["interrupted"] is True
    assert "density" not in summary and "bulk_density" not in summary
    assert "density" not in summary["stages"].get("dynamics", {})  # a DEM stopped inside is not listed
    again = pickle.loads(pickle.dumps(partial))
    assert again.interrupted == partial.interrupted and np.isnan(again.density)


TINY = {"title": "tiny", "container": {"side": 0.06, "height": 0.3}, "particles": {"diameter": 0.01, "count": 300},
        "deposition": {}, "analysis": {"box_sides": [0.03]}}


def _tiny_run(seed):
    return aggpack.run(aggpack.Scenario.from_dict(TINY, seed=seed), threads=1)


def test_a_report_pickles_whole_and_comes_back_from_a_worker_process(tmp_path, examples):
    import multiprocessing
    report = aggpack.run(aggpack.Scenario.from_file(examples / "example1.toml", set=SHORT), threads=1)
    again = pickle.loads(pickle.dumps(report))
    assert again.summary() == report.summary()
    assert repr(again) == repr(report) and again.notes == report.notes and again.wall_clock == report.wall_clock
    assert np.array_equal(again.bed.positions, report.bed.positions)
    assert np.array_equal(again.deposited.positions, report.deposited.positions)
    # Its outputs are the same bytes as the original's.
    aggpack.write_outputs(report, tmp_path / "original")
    aggpack.write_outputs(again, tmp_path / "unpickled")
    for name in ("particles.csv", "timeseries.csv", "supports.csv", "particles.vtp"):
        assert (tmp_path / "unpickled" / name).read_bytes() == (tmp_path / "original" / name).read_bytes(), name
    # A run into a folder keeps the summary it wrote, and its folder.
    written = aggpack.run(aggpack.Scenario.from_dict(TINY), out=tmp_path / "tiny", threads=1)
    kept = pickle.loads(pickle.dumps(written))
    assert kept.output_directory == written.output_directory and kept.summary() == written.summary()
    # From a worker process, as multiprocessing returns it.
    with multiprocessing.get_context("spawn").Pool(2) as pool:
        reports = pool.map(_tiny_run, [3, 4])
    assert [r.density for r in reports] == [_tiny_run(3).density, _tiny_run(4).density]
    assert reports[0].bed.count == 300
    # A damaged pickle is an InputError, not a crash.
    state = list(report.__getstate__())
    state[7] = state[7][: len(state[7]) // 2]
    with pytest.raises(aggpack.InputError, match="damaged"):
        report.__class__.__new__(report.__class__).__setstate__(tuple(state))


SLOW_TEMPLATES = 'family = "angular", templates = 400, spheres = 40'


def test_ctrl_c_while_templates_are_made_stops_there(tmp_path):
    # Issue 55, item 5: the templates' fit took minutes and ignored Ctrl-C; it is checked
    # between two templates, in grading(shape=...) and in a run (nothing written then).
    for work in (
        lambda: aggpack.grading("fu2003_table1_coarse", d_min="0.187 in", d_max="1 in", shape=SLOW_TEMPLATES),
        lambda: aggpack.run(
            aggpack.Scenario.from_toml(
                "[container]\nside = 0.05\nheight = 0.3\n[particles]\ndiameter = 0.009\ncount = 300\n"
                "shape = { " + SLOW_TEMPLATES + " }\n[pour]\n[dynamics]\n[analysis]\nbox_sides = [0.005]\n"
                "[limits]\nmax_template_minutes = 100\n"),
            out=tmp_path / "slow", threads=1),
    ):
        timer = threading.Timer(1.0, os.kill, (os.getpid(), signal.SIGINT))
        timer.start()
        try:
            with pytest.raises(KeyboardInterrupt):
                work()
        finally:
            timer.cancel()
    assert not (tmp_path / "slow" / "summary.json").exists()
