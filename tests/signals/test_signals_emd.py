"""EMD (PyEMD algorithm; pyemd_rs or PyEMD engine), segments, IMF cap and IMF selection."""

import numpy as np
import pytest
from numpy.testing import assert_allclose

from gearsim.errors import InputError
from gearsim.signals.emd import emd, imf_correlations, segment_slice, select_imfs

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


# --- engines, segment selection and IMF cap -------------------------------------------

#: Agreement of the adopted engine (pyemd_rs) with PyEMD's default EMD: normalised RMS
#: difference of each of the first three IMFs (same algorithm, so round-off only).
TOL_NRMS = 1e-6


def _gear_like(n=5000, seed=0):
    rng = np.random.default_rng(seed)
    t = np.arange(n) / FS
    x = np.sin(2 * np.pi * 390.0 * t) + 0.5 * np.sin(2 * np.pi * 780.0 * t)
    x *= 1.0 + 0.1 * np.sin(2 * np.pi * 10.0 * t)
    x += 0.1 * rng.standard_normal(n) + 5.0
    return x


def _nrms(a, b):
    return np.sqrt(np.mean((a - b) ** 2) / np.mean(b**2))


def test_pyemd_rs_agrees_with_pyemd_default():
    pytest.importorskip("pyemd_rs")
    x = _gear_like()
    ref = emd(x, engine="pyemd")
    new = emd(x, engine="auto")
    assert (ref.engine, new.engine) == ("pyemd", "pyemd-rs")
    assert new.n_imfs == ref.n_imfs
    for k in range(3):
        assert _nrms(new.imfs[k], ref.imfs[k]) < TOL_NRMS
    assert_allclose(new.residue, ref.residue, atol=1e-9 * np.abs(x).max())
    s_ref = select_imfs(x, ref, method="correlation", threshold="ayenu-prah")
    s_new = select_imfs(x, new, method="correlation", threshold="ayenu-prah")
    assert s_new.indices == s_ref.indices


@pytest.mark.parametrize("engine", ["pyemd", "auto"])
def test_segment_equals_decomposition_of_cut_record(engine):
    x = _gear_like()
    cut = emd(x[1000:3000], max_imf=3, engine=engine)
    by_time = emd(x, max_imf=3, start=0.2, stop=0.6, fs=FS, engine=engine)
    by_samples = emd(x, max_imf=3, start=1000, stop=3000, unit="samples", engine=engine)
    # 10 Hz shaft at 5 kHz: 500 samples per revolution
    by_rev = emd(x, max_imf=3, start=2, stop=6, unit="rev", fs=FS, shaft_frequency=10.0,
                 engine=engine)
    for dec in (by_time, by_samples, by_rev):
        assert dec.start == 1000
        assert_allclose(dec.imfs, cut.imfs, rtol=0, atol=0)
        assert_allclose(dec.residue, cut.residue, rtol=0, atol=0)
    # selection accepts the whole record and cuts it to the decomposed samples
    s_full = select_imfs(x, by_time, method="correlation", threshold=0.1)
    s_cut = select_imfs(x[1000:3000], cut, method="correlation", threshold=0.1)
    assert s_full.indices == s_cut.indices
    assert_allclose(s_full.scores, s_cut.scores, rtol=1e-12)
    # open-ended bounds
    assert emd(x, max_imf=1, start=4000, unit="samples").imfs.shape == (1, 1000)
    assert emd(x, max_imf=1, stop=0.1, fs=FS).imfs.shape == (1, 500)


@pytest.mark.parametrize("engine", ["pyemd", "auto"])
def test_imf_cap_respected(engine):
    x = _gear_like(3000)
    full = emd(x, engine=engine)
    assert full.n_imfs > 2
    for cap in (1, 2):
        dec = emd(x, max_imf=cap, engine=engine)
        assert dec.n_imfs == cap
        assert_allclose(dec.imfs, full.imfs[:cap], atol=1e-9)
        assert_allclose(dec.imfs.sum(axis=0) + dec.residue, x, atol=1e-9)


def test_segment_slice():
    assert segment_slice(100, start=0.1, stop=0.5, fs=100.0) == slice(10, 50)
    assert segment_slice(100) == slice(0, 100)
    assert segment_slice(1000, start=1, stop=3, unit="rev", fs=1000.0,
                         shaft_frequency=10.0) == slice(100, 300)


@pytest.mark.parametrize("kwargs, match", [
    ({"start": 0.1, "stop": 0.1, "fs": FS}, "segment"),
    ({"start": 0.15, "stop": 0.05, "fs": FS}, "segment"),
    ({"start": -0.1, "fs": FS}, "start"),
    ({"stop": 2.0, "fs": FS}, "stop"),
    ({"stop": float("nan"), "fs": FS}, "stop"),
    ({"start": "0.1", "fs": FS}, "start"),
    ({"start": 0.1}, "fs"),
    ({"start": 0.1, "fs": -1.0}, "fs"),
    ({"start": 1, "unit": "rev", "fs": FS}, "shaft_frequency"),
    ({"start": 1, "unit": "rev", "fs": FS, "shaft_frequency": 0.0}, "shaft_frequency"),
    ({"start": 10.5, "unit": "samples"}, "start"),
    ({"start": 10, "unit": "degrees"}, "unit"),
    ({"max_imf": 0}, "max_imf"),
    ({"max_imf": -2}, "max_imf"),
    ({"max_imf": 1.5}, "max_imf"),
    ({"max_imf": True}, "max_imf"),
    ({"engine": "matlab"}, "engine"),
    ({"engine": "pyemd-rs", "spline_kind": "akima"}, "spline_kind"),
])
def test_bad_segment_or_cap(kwargs, match):
    x = _gear_like(1000)
    with pytest.raises(InputError, match=match):
        emd(x, **kwargs)
