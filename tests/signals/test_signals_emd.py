"""EMD through PyEMD and IMF selection by correlation or kurtosis."""

import numpy as np
import pytest
from numpy.testing import assert_allclose

from gearsim.errors import InputError
from gearsim.signals.emd import emd, imf_correlations, select_imfs

#: EMD separates two tones an octave and more apart almost exactly in the interior; the
#: record ends carry spline end effects, so compare on the central 80 % with 5 %.
RTOL_IMF = 0.05

FS = 5000.0


def _two_tones():
    t = np.arange(5000) / FS
    fast = np.sin(2 * np.pi * 400.0 * t)
    slow = 0.3 * np.sin(2 * np.pi * 20.0 * t)
    return t, fast, slow


def test_emd_separates_tones_and_correlation_selects_dominant():
    _, fast, slow = _two_tones()
    x = fast + slow
    dec = emd(x, max_imf=-1)
    assert dec.n_imfs >= 2
    assert_allclose(dec.imfs.sum(axis=0) + dec.residue, x, atol=1e-9)
    sel = select_imfs(x, dec, method="correlation", threshold="ayenu-prah")
    assert 0 in sel.indices
    mid = slice(500, 4500)
    err = np.max(np.abs(dec.imfs[0][mid] - fast[mid]))
    assert err < RTOL_IMF * np.max(np.abs(fast))
    top = sel.scores.max()
    assert_allclose(sel.threshold, min(top, top / (10 * top - 3)), rtol=1e-12)


def test_kurtosis_selection_picks_impulsive_imf():
    rng = np.random.default_rng(4)
    t = np.arange(5000) / FS
    x = 0.2 * np.sin(2 * np.pi * 30.0 * t) + 0.01 * rng.standard_normal(t.size)
    for t0 in np.arange(0.05, 1.0, 0.1):
        i0 = int(t0 * FS)
        k = np.arange(40)
        x[i0 : i0 + 40] += np.exp(-k / 6.0) * np.sin(2 * np.pi * 0.3 * k)
    dec = emd(x, max_imf=4)
    sel = select_imfs(x, dec, method="kurtosis", threshold=3.0)
    assert sel.indices  # at least one impulsive IMF
    assert all(sel.scores[i] >= 3.0 for i in sel.indices)
    assert sel.scores[0] > 3.0  # the first (highest-frequency) IMF carries the bursts


def test_imf_correlations_definition():
    x = np.array([1.0, 2.0, 3.0, 4.0])
    imfs = np.vstack([x, -x, np.array([1.0, -1.0, 1.0, -1.0])])
    rho = imf_correlations(x, imfs)
    assert_allclose(rho[:2], [1.0, -1.0], rtol=1e-12)
    assert_allclose(rho[2], np.corrcoef(x, imfs[2])[0, 1], rtol=1e-12)


def test_emd_bad_options():
    x = np.sin(np.arange(100.0))
    with pytest.raises(InputError, match="max_imf"):
        emd(x, max_imf=0)
    with pytest.raises(InputError, match="spline_kind"):
        emd(x, max_imf=2, spline_kind="bogus")
    dec = emd(x, max_imf=2)
    with pytest.raises(InputError, match="method"):
        select_imfs(x, dec, method="energy", threshold=0.1)
    with pytest.raises(InputError, match="correlation only"):
        select_imfs(x, dec, method="kurtosis", threshold="ayenu-prah")
