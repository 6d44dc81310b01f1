"""Gradings and the analytic models from Python: the CLI's --json dicts, the same numbers."""
import json

import pytest

import aggpack
from conftest import cli


def test_a_grading_is_what_aggpack_grading_prints(examples):
    _, printed = cli("grading", "fu2003_table1_coarse", "--mix", "astm_c33_fine_mid", "--ca-fa", "1.5", "--d-min",
                     "0.1in", "--json")
    got = aggpack.grading("fu2003_table1_coarse", mix="astm_c33_fine_mid", ca_fa=1.5, d_min="0.1 in")
    assert got == json.loads(printed)
    assert aggpack.grading("fu2003_table1_coarse", d_min=0.00254) == aggpack.grading("fu2003_table1_coarse",
                                                                                    d_min="0.1 in")


def test_a_shape_is_measured_beside_its_target():
    got = aggpack.grading("fu2003_table1_coarse", d_min="0.1 in", shape='family="angular", spheres=4, flakiness_index=18')
    _, printed = cli("grading", "fu2003_table1_coarse", "--d-min", "0.1 in", "--shape",
                     'family="angular", spheres=4, flakiness_index=18', "--json")
    assert got == json.loads(printed)
    assert got["shape"]["measured"]["flakiness_index_percent"] == pytest.approx(18.0, abs=1.0)


def test_predictions_are_what_aggpack_predict_prints(examples):
    _, printed = cli("predict", examples / "table2_mix3.toml", "--process", "rodded", "--json")
    assert aggpack.predict(str(examples / "table2_mix3.toml"), process="rodded") == json.loads(printed)
    _, printed = cli("predict", "fu2003_table1_coarse", "--mix", "astm_c33_fine_mid", "--ca-fa", "2", "--k", "9",
                     "--json")
    assert aggpack.predict("fu2003_table1_coarse", mix="astm_c33_fine_mid", ca_fa=2, k=9) == json.loads(printed)


def test_bad_input_raises_the_clis_message():
    code, printed = cli("grading", "no_such_grading", check=False)
    assert code == 2
    with pytest.raises(aggpack.InputError) as raised:
        aggpack.grading("no_such_grading")
    assert str(raised.value) in printed
    with pytest.raises(aggpack.InputError, match="d_min 3 furlongs"):
        aggpack.grading("fu2003_table1_coarse", d_min="3 furlongs")
    for bad in (-1.0, 0.0, float("nan")):
        with pytest.raises(aggpack.InputError, match="expected a positive length"):
            aggpack.grading("fu2003_table1_coarse", d_min=bad)
    with pytest.raises(aggpack.InputError):
        aggpack.predict("fu2003_table1_coarse", process="shaken")
