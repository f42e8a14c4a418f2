"""Crowning and helix slope on a spur pair (issue 24): the spur face is sliced when a lead
modification is present, so they change the loaded contact as the closed-form line load
predicts (before, the single mid-face slice saw no lead separation at all)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from gearsim.model import load
from gearsim.stiffness.contacts import FlankState, contact_grid
from gearsim.stiffness.ltca import loaded_contact
from gearsim.stiffness.modifications import Modification


def _loaded(**mod):
    tr = load("spur-19-48").train
    force = tr.static_mesh_force(0)  # 100 N m on the pinion: 3.5 kN
    flank = FlankState(modification=Modification(gear="pinion", **mod)) if mod else None
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the Sainsot fit's range warning of this pinion
        return force, loaded_contact(contact_grid(tr.pairs[0], flank1=flank), force)


def _crowned(force, k, c):
    """Line load k / b (delta - c u^2), u in [-1, 1], integrated to the force."""
    full = force / k + c / 3  # contact over the whole face: mean separation c / 3
    u0 = np.cbrt(1.5 * force / (k * c))  # else contact |u| < u0: F = 2/3 k c u0^3
    return np.where(full >= c, full, c * u0 ** 2)


def _sloped(force, k, f):
    """Line load k / b (delta - f (z / b - 1/2)), z in [0, b], integrated to the force."""
    partial = np.sqrt(2 * f * force / k) - f / 2  # contact from the leading edge: F = k d^2 / 2f
    return np.where(force / k >= f / 2, force / k, partial)


@pytest.mark.parametrize("mod,estimate", [({"crowning": 20e-6}, _crowned),
                                          ({"helix_slope": -40e-6}, _sloped)])
def test_lead_modification_on_spur_matches_the_line_load_estimate(mod, estimate):
    force, plain = _loaded()
    _, modified = _loaded(**mod)
    k = force / (plain.delta - plain.unloaded)  # unmodified mesh stiffness at each position
    expected = estimate(force, k, abs(next(iter(mod.values()))))
    # 40 slices (midpoint rule on the lead): 5e-4 measured
    assert np.nanmax(np.abs(modified.delta - expected) / np.abs(expected)) < 2e-3
    assert np.nanmean(modified.stiffness) < 0.7 * np.nanmean(plain.stiffness)


def test_crowning_raises_the_loaded_transmission_error_by_micrometres():
    force, plain = _loaded()
    _, crowned = _loaded(crowning=20e-6)
    # 20 um crowning, F / k ~ 10.4 um: partial contact, LTE 11.15 -> 17.63 um (measured)
    assert np.nanmean(crowned.delta) - np.nanmean(plain.delta) == pytest.approx(6.48e-6, rel=0.01)
    assert crowned.grid.k.shape[2] == 40 and plain.grid.k.shape[2] == 1
