"""Params: validation names the parameter and value; Table 1 presets."""

import math

import pytest

from sim import PRESETS, Params

BAD = [
    ("hc", 0.0), ("hc", -1.0), ("hc", math.nan), ("hc", math.inf), ("hc", 1e9),
    ("D", 0.0), ("D", -3.0), ("D", math.nan),
    ("humidity", 0), ("humidity", -5), ("humidity", 10**12), ("humidity", 2.5),
    ("step", 0.0), ("step", -1.0), ("step", math.inf),
    ("active_radius", 0.0), ("active_radius", math.nan),
    ("bump", -0.1), ("bump", math.nan), ("max_height", 0.0),
    ("grid_spacing", 0), ("grid_spacing", 1.5),
    ("feature_width", -1.0), ("feature_height", math.inf),
    ("neighbor_search", "octree"), ("replenish", "yes"), ("hc", "7"), ("hc", True),
]


@pytest.mark.parametrize("name,value", BAD)
def test_invalid_value_names_parameter_and_value(name, value):
    with pytest.raises(ValueError) as err:
        Params(**{name: value})
    assert name in str(err.value)
    assert repr(value) in str(err.value)


def test_step_larger_than_hc_is_refused():
    with pytest.raises(ValueError, match="step=5.0 must not exceed hc=4.0"):
        Params(hc=4.0, step=5.0)


def test_defaults_match_spec():
    p = Params()
    assert (p.hc, p.D, p.humidity, p.step, p.active_radius) == (7.0, 7.0, 3000, 5.0, 200.0)
    assert (p.bump, p.grid_spacing, p.feature_width, p.feature_height) == (1.0, 4, 1.5, 0.5)
    assert p.neighbor_search == "candidate" and p.replenish is False


def test_presets_are_table_1():
    table = {  # D, hc, humidity from the paper's Table 1
        "a-1": (1.0, 10.0, 3000), "a-2": (2.5, 10.0, 3000), "a-3": (5.0, 10.0, 3000),
        "b-1": (3.0, 3.0, 3000), "b-2": (7.0, 7.0, 3000), "b-3": (10.0, 10.0, 3000),
        "c-1": (7.0, 7.0, 500), "c-2": (7.0, 7.0, 3000), "c-3": (7.0, 7.0, 5000),
    }
    assert set(PRESETS) == set(table)
    for name, (D, hc, hum) in table.items():
        p = Params.preset(name)
        assert (p.D, p.hc, p.humidity) == (D, hc, hum)
        assert p.step <= p.hc


def test_preset_overrides_and_unknown_names():
    assert Params.preset("c-3", humidity=100).humidity == 100
    with pytest.raises(ValueError, match="unknown preset 'z-9'"):
        Params.preset("z-9")
    with pytest.raises(ValueError, match="unknown parameter"):
        Params().replace(colour=1)
    with pytest.raises(ValueError, match="hc"):
        Params().replace(hc=-2.0)


def test_every_parameter_is_described_with_its_name():
    for name, _default, doc in Params.describe():
        assert doc.startswith(name + ":")


# hc sizes the hash grid: (w / 2hc) x (h / 2hc) cells. 0.03 asked for 11 GB, 0.01 was a
# MemoryError and 1e-300 a ValueError from numpy; the floor is 1 px, named in the refusal.
@pytest.mark.parametrize("hc", [0.999, 0.5, 0.03, 0.01, 1e-300, 5e-324])
def test_hc_below_its_floor_is_refused_naming_the_floor(hc):
    with pytest.raises(ValueError, match=rf"hc={hc!r} is out of range \[1\.0, 16\.0\]"):
        Params(hc=hc, step=hc, D=hc)


def test_at_the_hc_floor_the_grid_stays_small():
    from sim import FrostSim

    sim = FrostSim(Params(hc=1.0, step=1.0, D=1.0), 760, 1280)
    assert (sim.grid.cols, sim.grid.rows) == (380, 640)  # Eq. 1: 760 / 2, 1280 / 2
    sim.touch(380, 640)
    sim.step()
