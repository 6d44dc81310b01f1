"""aggpack.calibrate against `aggpack calibrate`: the same calibration file, analytic and by DEM."""
import json
import warnings

import pytest

import aggpack
from conftest import cli

# Two sizes deposited by drop and roll (the CLI's calibrate test): CPM's K and beta from a monosized
# bed and this mix.
BINARY = {
    "title": "binary", "seed": 1,
    "container": {"side": 0.1, "height": 0.3},
    "particles": {"order": "shuffled", "classes": [{"diameter": 0.01, "count": 600}, {"diameter": 0.005, "count": 1200}]},
    "deposition": {"method": "drop_and_roll"},
    "analysis": {"box_sides": [0.05]},
}

# 300 spheres of 1 cm poured in two batches (the CLI's calibrate --dem test): about a second a run.
POURED = {
    "seed": 1,
    "container": {"side": 0.06, "height": 0.3},
    "particles": {"diameter": 0.01, "count": 300},
    "material": {"youngs_modulus": 1e8, "wall_youngs_modulus": 1e8, "friction_particle": 0.5},
    "dynamics": {"max_time": 1.0},
    "analysis": {"box_sides": [0.025, 0.03, 0.035]},
    "pour": {"batches": 2},
}


def written(tmp_path, name, scenario):
    path = tmp_path / name
    path.write_text(aggpack.toml_text(scenario))
    return path


def test_cpm_calibration_is_the_clis_file(tmp_path):
    scenario = written(tmp_path, "binary.toml", BINARY)
    cli("calibrate", scenario, "--seeds", "2", "--quiet", "--out", tmp_path / "cli.json")
    expected = json.loads((tmp_path / "cli.json").read_text())
    got = aggpack.calibrate(aggpack.Scenario.from_file(scenario), seeds=2, out=tmp_path / "py.json")
    assert got == expected
    assert (tmp_path / "py.json").read_bytes() == (tmp_path / "cli.json").read_bytes()
    k, beta = got["cpm"]["compaction_index"], got["cpm"]["residual_packing_density"]
    assert beta / (1.0 + 1.0 / k) == pytest.approx(got["monosized"]["mean"], abs=1e-9)
    # The file is what predict takes: the calibrated model gives the simulated mix back.
    predicted = aggpack.predict(str(scenario), calibration=tmp_path / "py.json")
    assert predicted["parameters"]["cpm_compaction_index"] == pytest.approx(k, rel=1e-12)
    assert predicted["simulated"]["cpm"]["density"] == pytest.approx(got["mix"]["mean"], abs=1e-9)


def test_dem_calibration_is_the_clis_file(tmp_path):
    # The measurement lies inside the lever's reach: 0.572 at rolling_friction 0, 0.531 at 0.5
    # (since issue 55's contact lever arm, R - d/2: 0.58 was out of reach).
    scenario = written(tmp_path, "poured.toml", POURED)
    arguments = ["--dem", "--measured", "0.56", "--seeds", "2", "--max-runs", "3", "--threads", "1", "--quiet"]
    cli("calibrate", scenario, *arguments, "--out", tmp_path / "cli.json")
    expected = json.loads((tmp_path / "cli.json").read_text())
    with warnings.catch_warnings(record=True) as warned:
        warnings.simplefilter("always")
        got = aggpack.calibrate(scenario, dem=True, measured=0.56, seeds=2, max_runs=3, threads=2)
    # An unconverged search warns, as the CLI does on stderr.
    assert [str(w.message).startswith("aggpack.calibrate: NOT CONVERGED") for w in warned] == \
        ([] if expected["fit"]["converged"] else [True])
    assert got == expected
    assert got["fit"]["parameter"] == "rolling_friction"
    assert len(got["evaluations"]) == 3
    assert got["assignments"][0].startswith("material.rolling_friction=")


def test_bad_calibrations_are_refused(tmp_path):
    scenario = written(tmp_path, "poured.toml", POURED)
    with pytest.raises(aggpack.InputError, match="dem=True needs measured="):
        aggpack.calibrate(scenario, dem=True)
    with pytest.raises(aggpack.InputError, match="apply to a DEM calibration: give dem=True"):
        aggpack.calibrate(scenario, measured=0.6)
    with pytest.raises(aggpack.InputError, match="calibrate: the scenario 'binary' was not read from its file"):
        aggpack.calibrate(aggpack.Scenario.from_dict(BINARY))
    # The library's own refusals, with the CLI's words: one size class gives no K.
    code, printed = cli("calibrate", scenario, "--out", tmp_path / "c.json", check=False)
    assert code == 2
    with pytest.raises(aggpack.InputError) as raised:
        aggpack.calibrate(scenario)
    assert str(raised.value) in printed
    assert not (tmp_path / "c.json").exists()
