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


def test_a_blend_without_its_ratio_is_refused_as_the_cli_refuses_it():
    # A 1:1 blend nobody asked for was described without a word (ca_fa defaulted to 1).
    for call in (aggpack.grading, aggpack.predict):
        with pytest.raises(aggpack.InputError, match=r"mix= and ca_fa= go together.*no default"):
            call("fu2003_table1_coarse", mix="astm_c33_fine_mid")
        with pytest.raises(aggpack.InputError, match=r"mix= and ca_fa= go together"):
            call("fu2003_table1_coarse", ca_fa=1.5)
    for command in ("grading", "predict"):
        code, printed = cli(command, "fu2003_table1_coarse", "--mix", "astm_c33_fine_mid", check=False)
        assert code == 2 and "--mix and --ca-fa go together" in printed, printed


def test_errors_name_the_keyword_the_caller_gave_not_the_clis_flag(examples):
    cases = [
        (lambda: aggpack.grading("fu2003_table1_coarse", mix="astm_c33_fine_mid", ca_fa=-1), "ca_fa=-1: "),
        (lambda: aggpack.grading("fu2003_table1_coarse", band="no_band"), "band=no_band: unknown band"),
        (lambda: aggpack.predict("fu2003_table1_coarse", mix="astm_c33_fine_mid", ca_fa=0), "ca_fa=0: "),
        (lambda: aggpack.predict("fu2003_table1_coarse", process="shaken"), "process=shaken: expected poured"),
        (lambda: aggpack.predict("fu2003_table1_coarse", k=9, process="rodded"), "k= and process= both"),
        (lambda: aggpack.predict("fu2003_table1_coarse", beta=2), "beta=2: expected"),
        (lambda: aggpack.run(aggpack.Scenario.from_file(examples / "example1.toml"), threads=-1),
         "threads=-1: expected 0 (all cores)"),
        (lambda: aggpack.resume(examples, threads=100000), "threads=100000: expected"),
        (lambda: aggpack.calibrate(examples / "example1.toml", threads=-2), "threads=-2: expected"),
    ]
    for call, said in cases:
        with pytest.raises(aggpack.InputError) as raised:
            call()
        assert said in str(raised.value), str(raised.value)
        assert "--" not in str(raised.value), str(raised.value)


def test_a_seed_out_of_range_is_an_input_error_naming_the_range(examples):
    for bad in (-1, 2**63, 2**64, 1.5, "3", True):
        with pytest.raises(aggpack.InputError, match=r"seed=.*expected an integer from 0 to 9223372036854775807"):
            aggpack.Scenario.from_file(examples / "example1.toml", seed=bad)
    with pytest.raises(aggpack.InputError, match=r"seed=-1: expected an integer from 0"):
        aggpack.grading("fu2003_table1_coarse", seed=-1)
    s = aggpack.Scenario.from_file(examples / "example1.toml", seed=2**63 - 1)
    assert s.seed == 2**63 - 1
    with pytest.raises(aggpack.InputError, match="seed=-5"):
        s.with_overrides([], seed=-5)
    import numpy as np
    assert s.with_overrides([], seed=np.int64(4)).seed == 4
