"""A bed made elsewhere (a file, numpy arrays) measured as `aggpack analyze` measures it."""
import json

import numpy as np
import pytest

import aggpack
from conftest import cli


@pytest.fixture(scope="module")
def bed_file(tmp_path_factory):
    """Example 1's deposited bed, written by the CLI."""
    from conftest import EXAMPLES
    out = tmp_path_factory.mktemp("bed") / "example1"
    cli("run", EXAMPLES / "example1.toml", "--quiet", "--stop-after", "deposition", "--out", out)
    return out / "particles.csv"


def without_source(analysis):
    return {k: v for k, v in analysis.items() if k not in ("file", "format", "source")}


def test_a_file_analysed_from_python_is_what_the_cli_prints(bed_file):
    _, printed = cli("analyze", bed_file, "--cube", "6in", "--cube", "0.2", "--json")
    expected = json.loads(printed)
    got = aggpack.analyze(bed_file, cubes=[0.1524, 0.2])
    assert without_source(got) == without_source(expected)
    assert got["file"] == str(bed_file) == expected["file"]  # the CLI's key
    assert got["source"] == got["file"]  # its deprecated former name
    assert set(got) - {"source"} == set(expected)
    assert got["format"] == expected["format"] == "CSV"
    # The same bed in millimetres: bare lengths in the file's unit, as the CLI's --length-unit.
    table = np.loadtxt(bed_file, delimiter=",", skiprows=1)
    in_mm = bed_file.parent / "particles_mm.csv"
    np.savetxt(in_mm, np.column_stack([table[:, 0], 1000 * table[:, 1:5]]), delimiter=",", header="id,x,y,z,r",
               comments="", fmt=["%d"] + ["%.17g"] * 4)
    _, printed_mm = cli("analyze", in_mm, "--length-unit", "mm", "--cube", "152.4", "--json")
    got_mm = aggpack.analyze(in_mm, length_unit="mm", cubes=[152.4])
    assert without_source(got_mm) == without_source(json.loads(printed_mm))
    assert got_mm["density"]["mean"] == pytest.approx(got["density"]["boxes"][0]["density"], rel=1e-12)


def test_arrays_are_measured_as_their_file(bed_file):
    table = np.loadtxt(bed_file, delimiter=",", skiprows=1)
    bed = aggpack.Bed.from_arrays(table[:, 1:4], table[:, 4])
    assert len(bed) == table.shape[0]
    assert np.array_equal(bed.positions, table[:, 1:4])
    read = aggpack.read_bed(bed_file)
    assert np.array_equal(read.radii, table[:, 4])
    box = [0.05, 0.05, 0.02, 0.2, 0.2, 0.17]
    from_arrays = aggpack.analyze(bed, cubes=[0.15], boxes=[box])
    from_file = aggpack.analyze(bed_file, cubes=[0.15], boxes=[box])
    assert without_source(from_arrays) == without_source(from_file)
    assert len(from_arrays["density"]["boxes"]) == 2


@pytest.mark.parametrize("positions, radii, message", [
    (np.zeros((3, 2)), np.ones(3), r"positions: an array of shape \(3, 2\); expected \(N, 3\)"),
    (np.zeros((3, 3)), np.ones(2), r"radii: an array of shape \(2,\); expected \(3,\)"),
    (np.full((2, 3), np.nan), np.ones(2), "positions: entry 0 is nan; expected finite numbers"),
    (np.zeros((2, 3)), np.array([0.1, -1.0]), "radii: entry 1 is -1; expected a positive radius"),
    ("nonsense", np.ones(2), "positions: expected an array of numbers"),
])
def test_bad_arrays_are_refused_naming_the_argument(positions, radii, message):
    with pytest.raises(aggpack.InputError, match=message):
        aggpack.Bed.from_arrays(positions, radii)


def test_a_cube_that_does_not_fit_is_refused_as_by_the_cli(bed_file):
    code, printed = cli("analyze", bed_file, "--cube", "2", check=False)
    assert code == 2
    with pytest.raises(aggpack.InputError) as raised:
        aggpack.analyze(bed_file, cubes=[2.0])
    assert str(raised.value) in printed
    with pytest.raises(aggpack.InputError, match="a box of 3 numbers"):
        aggpack.analyze(bed_file, boxes=[[0, 0, 0]])
    for side in (-1.0, 0.0, float("nan")):
        with pytest.raises(aggpack.InputError, match="cubes: .*: expected a positive side"):
            aggpack.analyze(bed_file, cubes=[side])
    for tolerance in (-1.0, float("nan"), 2.0):
        with pytest.raises(aggpack.InputError, match="expected a relative tolerance from 0 to 1"):
            aggpack.analyze(bed_file, tolerance=tolerance)
        with pytest.raises(aggpack.InputError, match="overlap tolerance .*: expected a fraction"):
            aggpack.analyze(bed_file, overlap_tolerance=tolerance)
