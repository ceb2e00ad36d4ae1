"""viz/layers.py's colour ramps on their own (the viewers' tests compare their colours with these
functions, so the functions need checks of their own): front_colors against its docstring."""

import numpy as np
import pytest

from conecull.viz import layers as L

GREY = (215, 215, 215)


def ramp_twin(load):
    """The docstring's ramp, written independently: grey without entries, else the stops'
    piecewise-linear colour at t = 1/4 + 3/4 log(1 + load) / log(1 + max load), the stops evenly
    spaced on [0, 1]."""
    load = np.asarray(load, float)
    stops = L._FRONT_STOPS
    top = np.log1p(load.max())
    t = np.where(load > 0, 0.25 + 0.75 * np.log1p(load) / top, 0.0)
    at = np.linspace(0.0, 1.0, len(stops))
    return np.stack([np.interp(t, at, stops[:, k]) for k in range(3)], axis=1)


def test_no_entry_is_grey_and_the_maximum_is_the_last_stop():
    c = L.front_colors(np.array([0, 5, 0, 40]))
    assert c.dtype == np.uint8 and c.shape == (4, 3)
    assert tuple(c[0]) == GREY and tuple(c[2]) == GREY
    assert tuple(c[3]) == tuple(L._FRONT_STOPS[-1].astype(int))
    assert tuple(c[1]) != GREY


@pytest.mark.parametrize("seed", range(5))
def test_ramp_against_its_twin(seed):
    rng = np.random.default_rng(seed)
    load = rng.integers(0, 10 ** rng.integers(1, 6), 300)
    load[0] = 0
    load[1] = max(load.max(), 1)
    assert np.abs(L.front_colors(load).astype(int) - ramp_twin(load)).max() <= 1  # rounding to uint8


def test_one_entry_is_the_first_step_above_grey():
    """A load of 1 sits at t >= 1/4 (the second stop or beyond), never between grey and it: one
    entry must not look like none."""
    c = L.front_colors(np.array([1, 1_000_000]))
    assert np.abs(c[0].astype(int) - L._FRONT_STOPS[1]).max() <= np.abs(L._FRONT_STOPS[1] - L._FRONT_STOPS[2]).max()
    assert tuple(L.front_colors(np.array([1]))[0]) == tuple(L._FRONT_STOPS[-1].astype(int))  # alone: the maximum


def test_all_zero_and_empty():
    assert [tuple(x) for x in L.front_colors(np.zeros(3, int))] == [GREY] * 3
    assert L.front_colors(np.zeros(0, int)).shape == (0, 3)
