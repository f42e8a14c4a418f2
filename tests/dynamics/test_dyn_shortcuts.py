"""Shortcuts of the result's derived records against the general formulas, bit for bit.

``DynamicModel.ste`` without harmonics and ``DynamicModel.nominal`` at constant speed
skip arithmetic whose result is known (a sum of zeros, the segment (0, 0, 1, 0)); the
result of :func:`gearsim.dynamics.simulate` must not change by a bit, so each shortcut
is held to the expression it replaces, here written out again, on the times of a run
and on edge values (zeros of either sign, huge and non-finite times, where the
shortcut must not apply).
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from gearsim.dynamics.simulate import build_model
from gearsim.model import example

TIMES = [
    0.1 + np.arange(20_000) / 50e3,
    np.array([0.0, -0.0, 1e-300, 5e-324, 1.0, 1e4, 1e300, -3.5]),
    np.array([0.0, np.inf]),
    np.array([np.nan, 1.0]),
]


def _same(a: np.ndarray, b: np.ndarray) -> bool:
    """Equal to the bit, the sign of zeros and NaN included."""
    return a.shape == b.shape and a.dtype == b.dtype and np.array_equal(
        a.view(np.int64), b.view(np.int64))


def _ste(model, t):
    t = np.atleast_1d(np.asarray(t, dtype=float))
    arg = t[:, None, None] * model.h_omega[None] + model.h_phase[None]
    return model.e0[None, :] + np.sum(model.h_amp[None] * np.sin(arg), axis=-1)


def _nominal(model, t):
    t = np.asarray(t, dtype=float)
    prof = np.array([[0.0, 0.0, 1.0, 0.0]]) if model.profile is None else model.profile
    k = np.clip(np.searchsorted(prof[:, 0], t, side="right") - 1, 0, None)
    d = t - prof[k, 0]
    tau = prof[k, 1] + prof[k, 2] * d + 0.5 * prof[k, 3] * d * d
    lam = (np.ones_like(t) if model.load is None
           else np.interp(t, model.load[:, 0], model.load[:, 1]))
    return tau, prof[k, 2] + prof[k, 3] * d, prof[k, 3] + 0.0 * t, lam


@pytest.fixture(scope="module")
def model():
    gb = example("idler-table1")
    return build_model(gb.train, gb.dynamics)


@pytest.mark.parametrize("e0", [(0.0, 0.0), (1e-6, -2e-6), (-0.0, 0.0), (np.nan, 0.0)])
@pytest.mark.parametrize("ti", range(len(TIMES)))
def test_ste_without_harmonics_is_the_sum(model, e0, ti):
    m = dataclasses.replace(model, e0=np.array(e0), h_amp=np.zeros_like(model.h_amp),
                            h_omega=np.full_like(model.h_omega, 1e3),
                            h_phase=np.full_like(model.h_phase, 0.5))
    with np.errstate(invalid="ignore"):
        assert _same(m.ste(TIMES[ti]), _ste(m, TIMES[ti]))
    assert _same(m.ste(0.25), _ste(m, 0.25))


@pytest.mark.parametrize("ti", range(len(TIMES)))
def test_ste_with_harmonics_is_unchanged(model, ti):
    m = dataclasses.replace(model, h_amp=np.full_like(model.h_amp, 1e-6),
                            h_omega=np.full_like(model.h_omega, 2e3))
    with np.errstate(invalid="ignore"):
        assert _same(m.ste(TIMES[ti]), _ste(m, TIMES[ti]))


@pytest.mark.parametrize("ti", range(len(TIMES)))
@pytest.mark.parametrize("load", [None, np.array([[0.0, 0.5], [1.0, 1.0]])])
def test_constant_speed_nominal_time_is_the_segment(model, ti, load):
    m = dataclasses.replace(model, load=load)
    with np.errstate(invalid="ignore"):
        for got, ref in zip(m.nominal(TIMES[ti]), _nominal(m, TIMES[ti]), strict=True):
            assert _same(got, ref)
    # a scalar time keeps the general path and its types
    for got, ref in zip(m.nominal(0.3), _nominal(m, 0.3), strict=True):
        assert type(got) is type(ref) and got == ref


def test_tacho_pulses_are_those_of_the_remainder():
    from gearsim.dynamics.simulate import TACHO_VOLTS, TACHO_WIDTH, tacho_variable

    rng = np.random.default_rng(3)
    turns = np.arange(-2000, 2000) * (2 * np.pi)
    edges = np.concatenate([turns, turns + TACHO_WIDTH, [1e15, 7e15, 1e16, 2.0 ** 60]])
    a = np.concatenate([
        rng.uniform(-1e3, 1e3, 200_000), rng.uniform(0.0, 400.0, 200_000),
        edges, np.nextafter(edges, np.inf), np.nextafter(edges, -np.inf),
        [0.0, -0.0, 5e-324, -5e-324, 1e300, -1e300, np.inf, -np.inf, np.nan]])
    with np.errstate(invalid="ignore"):
        ref = np.where(np.mod(a, 2 * np.pi) < TACHO_WIDTH, TACHO_VOLTS, 0.0)
        dims, got, attrs = tacho_variable(a.reshape(-1, 1))
    assert dims == ("time", "shaft") and attrs["units"] == "V"
    assert _same(got[:, 0], ref)
