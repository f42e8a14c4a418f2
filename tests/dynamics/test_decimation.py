"""The simulation's anti-aliasing decimation and modal solve, against scipy.

The simulation makes its Kaiser low-pass with numpy and ``scipy.special.i0`` and
decimates with compiled kernels (so that ``scipy.signal`` is not imported to simulate),
and solves the modes with numpy's symmetric eigensolver in the mass-normalised form.
Each is checked here against the scipy routine it stands for: ``scipy.signal.firwin``
and ``scipy.signal.upfirdn`` (the same operations in the same order: equal to the bit),
``scipy.linalg.eigh(K, M)``. ``_kernels.decimate_linear`` filters linear combinations of
the channels and combines the filtered signals: a channel passed alone is upfirdn's to
the bit; a combination is the combination of upfirdn's outputs to :data:`MAP_RTOL` of
its largest value (linear operations in another order: rounding only).
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg
from scipy.signal import firwin, upfirdn

from gearsim.dynamics import _kernels
from gearsim.dynamics.modal import modes
from gearsim.dynamics.simulate import (
    FIR_BETA,
    FIR_CUTOFF,
    FIR_HALF_PER_R,
    anti_alias_taps,
    build_model,
)
from gearsim.model import example

#: A combination filtered as one signal against the combination of the filtered
#: channels, relative to the record's largest magnitude: rounding only (issue 26).
MAP_RTOL = 1e-12


@pytest.mark.parametrize("r", [2, 3, 4, 8])
@pytest.mark.parametrize("fs", [20e3, 50e3, 12345.6])
def test_taps_are_scipy_firwin(r: int, fs: float) -> None:
    ref = firwin(2 * FIR_HALF_PER_R * r + 1, FIR_CUTOFF * fs, window=("kaiser", FIR_BETA),
                 fs=r * fs)
    assert np.array_equal(anti_alias_taps(r, fs), ref)


@pytest.mark.parametrize("r", [2, 3, 5])
def test_decimation_is_upfirdn(r: int) -> None:
    rng = np.random.default_rng(7)
    half = FIR_HALF_PER_R * r
    n_out = 301
    x = 1e3 * rng.standard_normal((4, (n_out - 1) * r + 1 + 2 * half))
    h = anti_alias_taps(r, 1e3)
    k0 = 2 * half // r
    ref = upfirdn(h, x, up=1, down=r, axis=-1)[:, k0:k0 + n_out]
    got = _kernels.fir_decimate(h, x, r, k0, n_out)
    assert np.array_equal(got, ref)
    # the last output sample uses the last recorded one, and none beyond
    assert (k0 + n_out - 1) * r == x.shape[1] - 1


@pytest.mark.parametrize("down", [1, 2, 3, 4])
@pytest.mark.parametrize("taps", [1, 2, 3, 6, 49])
def test_decimation_is_upfirdn_across_blocks(down: int, taps: int) -> None:
    # several blocks of outputs (the last one partial) and every remainder of the taps
    # taken four at a time: still upfirdn's numbers to the bit
    rng = np.random.default_rng(taps + 10 * down)
    n_out = 2 * _kernels.FIR_BLOCK + 37
    k0 = -(-(taps - 1) // down)  # the first output whose taps are all inside the record
    x = 1e3 * rng.standard_normal((3, (k0 + n_out - 1) * down + 1))
    h = rng.standard_normal(taps)
    ref = upfirdn(h, x, up=1, down=down, axis=-1)[:, k0:k0 + n_out]
    assert np.array_equal(_kernels.fir_decimate(h, x, down, k0, n_out), ref)


def _csr(rows):
    ptr = np.zeros(len(rows) + 1, dtype=np.int64)
    ptr[1:] = np.cumsum([len(r) for r in rows])
    return (ptr, np.array([c for r in rows for c, _ in r], dtype=np.int64),
            np.array([w for r in rows for _, w in r], dtype=float))


@pytest.mark.parametrize("down", [1, 2, 3, 4])
@pytest.mark.parametrize("taps", [1, 2, 3, 7, 8, 9, 17, 49])
def test_linear_decimation_of_single_channels_is_upfirdn(down: int, taps: int) -> None:
    # signals that are channels, records that are signals: upfirdn's numbers to the bit,
    # over several blocks (the last one partial) and every remainder of eight taps a pass
    rng = np.random.default_rng(taps + 10 * down)
    n_out = 2 * _kernels.FIR_BLOCK + 37
    k0 = -(-(taps - 1) // down)
    x = 1e3 * rng.standard_normal((3, (k0 + n_out - 1) * down + 1))
    h = rng.standard_normal(taps)
    ref = upfirdn(h, x, up=1, down=down, axis=-1)[:, k0:k0 + n_out]
    pre = _csr([[(2, 1.0)], [(0, 1.0)]])
    post = _csr([[(1, 1.0)], [(0, 1.0)]])
    z = np.empty((2, n_out))
    _kernels.decimate_linear(h, x, down, k0, n_out, *pre, np.empty((0, n_out)), *post,
                             np.zeros(2), np.ones(2), z)
    assert np.array_equal(z, ref[[0, 2]])


@pytest.mark.parametrize("down", [1, 2, 3])
def test_linear_decimation_is_the_combination_of_upfirdn(down: int) -> None:
    rng = np.random.default_rng(5 + down)
    n_out = _kernels.FIR_BLOCK + 301
    h = anti_alias_taps(max(down, 2), 1e3)
    k0 = -(-(h.size - 1) // down)
    x = rng.standard_normal((4, (k0 + n_out - 1) * down + 1)) * np.array([[1e-6], [1e3],
                                                                            [2.0], [5e4]])
    extra = rng.standard_normal((1, n_out))
    # signals: 1e9 x0 + 3e3 x1 (a bearing force), x2 alone, x1 - 2 x2 + 0.5 x3, nothing
    pre = _csr([[(0, 1e9), (1, 3e3)], [(2, 1.0)], [(1, 1.0), (2, -2.0), (3, 0.5)], []])
    # records: (4 - s0 + 7 s1) / 3, the extra row plus s2, s3 + 1, a constant, s1 itself,
    # five terms / 7, three terms / 2, s1 / 5
    post = _csr([[(0, -1.0), (1, 7.0)], [(4, 2.5), (2, 1.0)], [(3, 1.0)], [], [(1, 1.0)],
                 [(0, 1.0), (1, -1.0), (2, 2.0), (3, -0.5), (4, 3.0)],
                 [(2, 1.0), (0, 1e-3), (4, -1.0)], [(1, 1.0)]])
    b = np.array([4.0, 0.0, 1.0, -2.0, 0.0, 1.5, 0.0, 0.0])
    d = np.array([3.0, 1.0, 1.0, 4.0, 1.0, 7.0, 2.0, 5.0])
    z = np.empty((b.size, n_out))
    _kernels.decimate_linear(h, x, down, k0, n_out, *pre, extra, *post, b, d, z)
    y = upfirdn(h, x, up=1, down=down, axis=-1)[:, k0:k0 + n_out]
    s = [1e9 * y[0] + 3e3 * y[1], y[2], y[1] - 2 * y[2] + 0.5 * y[3], 0 * y[0]]
    ref = [(4 - s[0] + 7 * s[1]) / 3, 2.5 * extra[0] + s[2], s[3] + 1, np.full(n_out, -0.5),
           s[1], (1.5 + s[0] - s[1] + 2 * s[2] - 0.5 * s[3] + 3 * extra[0]) / 7,
           (s[2] + 1e-3 * s[0] - extra[0]) / 2, s[1] / 5]
    np.testing.assert_array_equal(z[4], y[2])  # a channel alone: upfirdn's numbers
    for got, want in zip(z, ref, strict=True):
        assert np.max(np.abs(got - want)) <= MAP_RTOL * np.max(np.abs(want))


def test_decimated_sine_keeps_its_amplitude_and_phase() -> None:
    # a 1 kHz sine recorded at 100 kHz and decimated to 50 kHz: in the pass band the
    # linear-phase filter passes it whole (Kaiser beta 8: ripple ~1e-4), centred on the
    # output sample times; a 40 kHz tone (above 0.45 fs_out = 22.5 kHz) is removed
    r, fs = 2, 50e3
    half = FIR_HALF_PER_R * r
    n_out = 2000
    t_int = (np.arange((n_out - 1) * r + 1 + 2 * half) - half) / (r * fs)
    x = np.vstack([np.sin(2 * np.pi * 1e3 * t_int), np.sin(2 * np.pi * 40e3 * t_int)])
    y = _kernels.fir_decimate(anti_alias_taps(r, fs), x, r, 2 * half // r, n_out)
    t_out = np.arange(n_out) / fs
    np.testing.assert_allclose(y[0], np.sin(2 * np.pi * 1e3 * t_out), atol=1e-3)
    assert np.max(np.abs(y[1])) < 1e-3


@pytest.mark.parametrize("name", ["idler-table1", "two-stage-reducer"])
def test_modes_are_scipy_generalized_eigh(name: str) -> None:
    from gearsim.dynamics.modal import mean_stiffness_matrix

    gb = example(name)
    model = build_model(gb.train, gb.dynamics)
    md = modes(model)
    w2 = scipy.linalg.eigh(mean_stiffness_matrix(model), np.diag(model.mass),
                           eigvals_only=True)
    ref = np.sqrt(w2[w2 > 1e-12 * w2.max()]) / (2 * np.pi)
    np.testing.assert_allclose(md.frequencies, ref, rtol=1e-10)
    # mass-normalised shapes
    np.testing.assert_allclose(md.shapes.T @ np.diag(model.mass) @ md.shapes,
                               np.eye(md.shapes.shape[1]), atol=1e-10)
