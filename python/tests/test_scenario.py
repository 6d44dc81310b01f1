"""Scenarios from a file, TOML text or a dict, and bad input raised as the CLI says it."""
import tomllib

import pytest

import aggpack
from conftest import cli


def test_a_dict_of_the_files_keys_is_the_same_scenario_as_the_file(examples):
    for name in ("example1.toml", "example2.toml", "grains_crushed_stone.toml", "table2_mix3_stone_sand.toml"):
        path = examples / name
        from_file = aggpack.Scenario.from_file(path)
        with open(path, "rb") as f:
            as_dict = tomllib.load(f)
        from_dict = aggpack.Scenario.from_dict(as_dict, name=path)
        assert from_dict == from_file, name
        assert from_dict.to_dict(resolved=True) == from_file.to_dict(resolved=True)
        from_text = aggpack.Scenario.from_toml(path.read_text(), name=path)
        assert from_text == from_file, name


def test_overrides_and_seed_are_the_clis(examples):
    s = aggpack.Scenario.from_file(examples / "example1.toml", set=["particles.count=100"], seed=7)
    assert s.seed == 7
    assert s.to_dict(resolved=True)["particles"]["classes"][0]["count"] == 100
    assert s.to_dict()["particles"]["count"] == 100 and s.to_dict()["seed"] == 7
    t = s.with_overrides(["dynamics.max_time=0.5"])
    assert t.overrides == ["particles.count=100", "dynamics.max_time=0.5"]
    assert t.seed == 7
    assert t.to_dict(resolved=True)["dynamics"]["max_time_s"] == 0.5
    assert s.to_dict(resolved=True)["dynamics"]["max_time_s"] == 2.0  # the first one unchanged


BAD = {
    "unknown_key": 'title = "t"\n[container]\nside = 0.1\nheight = 0.2\nsiez = 3\n[particles]\ndiameter = 0.01\ncount = 5\n',
    "negative_side": 'title = "t"\n[container]\nside = -0.1\nheight = 0.2\n[particles]\ndiameter = 0.01\ncount = 5\n',
    "bad_unit": 'title = "t"\n[container]\nside = "3 furlongs"\nheight = 0.2\n[particles]\ndiameter = 0.01\ncount = 5\n',
    "not_toml": 'title = "t"\n[container\n',
    "no_particles": 'title = "t"\n[container]\nside = 0.1\nheight = 0.2\n',
}


@pytest.mark.parametrize("name", sorted(BAD))
def test_bad_input_raises_input_error_with_the_clis_message(tmp_path, name):
    path = tmp_path / f"{name}.toml"
    path.write_text(BAD[name])
    code, printed = cli("check", path, check=False)
    assert code == 2, printed
    with pytest.raises(aggpack.InputError) as raised:
        aggpack.Scenario.from_file(path)
    assert isinstance(raised.value, ValueError)
    message = str(raised.value)
    assert message and message in printed, f"{message!r} not in {printed!r}"
    with pytest.raises(aggpack.InputError) as from_text:
        aggpack.Scenario.from_toml(BAD[name], name=path)
    assert str(from_text.value) == message


def test_numpy_scalars_are_their_values(examples):
    import numpy as np
    plain = aggpack.Scenario.from_dict({"title": "t", "seed": 3, "container": {"side": 0.1, "height": 0.3},
                                        "particles": {"diameter": 0.01, "count": 50}, "deposition": {}})
    numpy = aggpack.Scenario.from_dict({"title": np.str_("t"), "seed": np.int64(3),
                                        "container": {"side": np.float64(0.1), "height": 0.3},
                                        "particles": {"diameter": 0.01, "count": np.int32(50)},
                                        "deposition": {"tolerance": np.float64(1e-9)}})
    assert numpy == plain.with_overrides(["deposition.tolerance=1e-9"])
    with pytest.raises(aggpack.InputError, match="seed: 18446744073709551616 is beyond TOML's 64-bit integers"):
        aggpack.Scenario.from_dict({"title": "t", "seed": 2**64})


def test_a_dict_value_toml_cannot_hold_is_refused_naming_its_key():
    with pytest.raises(aggpack.InputError, match=r"container\.side: expected a dict, list, str, number or bool, not object"):
        aggpack.Scenario.from_dict({"title": "t", "container": {"side": object()}})


def test_check_finds_what_reading_cannot(tmp_path):
    # A bed from a file, read without fault, whose virtual cube does not fit it: only check()
    # (as `aggpack check`) places the boxes.
    rows = ["id,x,y,z,r"]
    for k in range(8 * 9 * 9):  # a simple cubic lattice of 1 cm spheres, 16 cm deep
        i, j, l = k % 9, k // 9 % 9, k // 81
        rows.append(f"{k + 1},{0.02 + 0.02 * i},{0.02 + 0.02 * j},{0.01 + 0.02 * l},0.01")
    (tmp_path / "bed.csv").write_text("\n".join(rows) + "\n")
    text = ('title = "t"\n[container]\nside = 0.2\nheight = 0.2\n[particles]\nfrom = "bed.csv"\n'
            '[analysis]\nbox_sides = [0.5]\n')
    (tmp_path / "p.toml").write_text(text)
    p = aggpack.Scenario.from_toml(text, name=tmp_path / "p.toml")
    with pytest.raises(aggpack.InputError) as raised:
        p.check()
    code, printed = cli("check", tmp_path / "p.toml", check=False)
    assert code == 2
    assert str(raised.value) in printed
    assert aggpack.Scenario.from_toml(text.replace("[0.5]", "[0.05]"), name=tmp_path / "p.toml").check() is None


def test_a_dict_nested_beyond_tomls_bound_is_refused_not_a_crash():
    # 30 000 levels crashed the process (the stack); TOML's own bound is 256 (toml++).
    deep = leaf = {}
    for _ in range(30000):
        leaf["a"] = {}
        leaf = leaf["a"]
    with pytest.raises(aggpack.InputError, match=r"scenario dict: a\.a\.a.*nested deeper than 256 levels"):
        aggpack.Scenario.from_dict(deep)
    deep_list = []
    inner = deep_list
    for _ in range(30000):
        inner.append([])
        inner = inner[0]
    with pytest.raises(aggpack.InputError, match=r"title\[0\]\[0\].*nested deeper than 256 levels"):
        aggpack.Scenario.from_dict({"title": deep_list})
    itself = {"title": "t"}
    itself["container"] = itself
    with pytest.raises(aggpack.InputError, match="nested deeper than 256 levels"):
        aggpack.Scenario.from_dict(itself)
    # A scenario's real depth stays well inside the bound.
    shallow = leaf = {}
    for _ in range(200):
        leaf["a"] = {}
        leaf = leaf["a"]
    with pytest.raises(aggpack.InputError, match="unknown key|'a'"):
        aggpack.Scenario.from_dict(shallow)


def test_to_dict_is_read_back_by_from_dict_for_every_shipped_scenario(examples):
    # to_dict() gave summary.json's record (side_m, density_kg_m3, ...), which from_dict refused.
    paths = sorted(examples.glob("*.toml"))
    assert len(paths) > 10
    for path in paths:
        s = aggpack.Scenario.from_file(path)
        again = aggpack.Scenario.from_dict(s.to_dict(), name=s.file)
        assert again == s, path.name
        assert again.to_dict() == s.to_dict(), path.name
    # Its --set assignments and seed are in the dict.
    s = aggpack.Scenario.from_file(examples / "example1.toml", set=["dynamics.max_time=0.5"], seed=9)
    again = aggpack.Scenario.from_dict(s.to_dict(), name=s.file)
    assert again == s and again.seed == 9
    assert again.to_dict(resolved=True)["dynamics"]["max_time_s"] == 0.5


def _title_of(scenario):
    return scenario.title, scenario.seed


def test_a_scenario_pickles_and_crosses_to_another_process(examples):
    import multiprocessing
    import pickle
    s = aggpack.Scenario.from_file(examples / "example1.toml", set=["particles.count=100"], seed=7)
    again = pickle.loads(pickle.dumps(s))
    assert again == s and again.overrides == s.overrides and again.seed == 7 and again.text == s.text
    assert again.file == s.file
    with multiprocessing.get_context("spawn").Pool(1) as pool:
        assert pool.map(_title_of, [s]) == [(s.title, 7)]
