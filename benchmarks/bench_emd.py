"""Benchmark of EMD engines and settings on 1 s of a 50 kHz synthetic gear signal.

Run: ``.venv/bin/python benchmarks/bench_emd.py [--seconds S] [--repeat N] [--full]``

Every candidate decomposes the same signal (the gear signal of ``bench_analyze.py``:
39-tooth mesh harmonics, sidebands, 8 kHz impacts, noise 0.1, offset 1e4) in the same
run; the table gives its wall and CPU (process) time, its speed ratio against PyEMD's
default ``EMD()`` (from CPU times, which a loaded machine disturbs less) and its
agreement with it: the normalised RMS difference ``rms(c_k - c_k^ref) / rms(c_k^ref)``
of each of the first three IMFs, and whether the correlation (Ayenu-Prah) selection of
:func:`gearsim.signals.emd.select_imfs` picks the same IMFs. A candidate *agrees* when all
three differences are below ``TOL_NRMS``. Candidates whose package is not installed
(``pyemd_rs``, the ``emd`` package) are reported as skipped. ``--full`` adds the slow
candidates (PyEMD with FIXE_H, parabolic extrema or pchip splines, all 3-10x slower than
the default, and PyEMD's numba ``JitEMD``, whose compilation alone takes 40-90 s); without
it the run takes about 15 s.
"""

from __future__ import annotations

import argparse
import time
import warnings

import numpy as np

from gearsim.signals.emd import emd, select_imfs
from gearsim.signals.synthetic import ImpactSpec, gear_signal

FS = 50_000.0
F_R = 1900.0 / 60.0  # seed Table 1, input shaft
TEETH = 39
#: Agreement tolerance: normalised RMS difference of each of the first 3 IMFs.
TOL_NRMS = 1e-6


def _best(fn, repeat):
    """Best wall time, best CPU time and the result of ``repeat`` calls of ``fn``."""
    wall, cpu = [], []
    out = None
    for _ in range(repeat):
        t0, c0 = time.perf_counter(), time.process_time()
        out = fn()
        wall.append(time.perf_counter() - t0)
        cpu.append(time.process_time() - c0)
    return min(wall), min(cpu), out


def _pyemd(**kw):
    from PyEMD import EMD

    def run(x):
        d = EMD(**kw)
        d.emd(x, max_imf=-1)
        return d.get_imfs_and_residue()[0]
    return run


def _jit(x):
    from PyEMD.experimental.jitemd import JitEMD, get_timeline

    d = JitEMD()
    return d.emd(x, get_timeline(x.size, x.dtype))[:-1]


def _pyemd_rs(x):
    return emd(x, engine="pyemd-rs").imfs


def _emd_sift(x):
    import emd as emd_package  # the "emd" package (Quinn et al.)

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return emd_package.sift.sift(x).T


def nrms(a, b):
    """Normalised RMS difference of ``a`` from the reference ``b``."""
    return float(np.sqrt(np.mean((a - b) ** 2) / np.mean(b**2)))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=1.0, help="signal length [s]")
    parser.add_argument("--repeat", type=int, default=1, help="best of N runs (fast candidates)")
    parser.add_argument("--full", action="store_true", help="add the slow candidates")
    args = parser.parse_args()

    x = gear_signal(
        fs=FS, duration=args.seconds, shaft_frequency=F_R, teeth=TEETH,
        mesh_amplitudes={1: 1.0, 2: 0.5, 3: 0.25, 4: 0.1},
        sidebands={(n, k): 0.03 for n in (1, 2) for k in (-3, -2, -1, 1, 2, 3)},
        impacts=ImpactSpec(amplitude=3.0, decay=5e-4, carrier=8000.0, first=0.01),
        noise=0.1, offset=1e4, seed=0,
    )
    print(f"signal: {x.size} samples ({args.seconds:g} s at {FS:g} Hz), agreement: nRMS of "
          f"IMFs 1-3 vs PyEMD default < {TOL_NRMS:g}")

    candidates = [
        ("PyEMD EMD() default", _pyemd(), args.repeat),
        ("pyemd_rs (gearsim engine)", _pyemd_rs, args.repeat),
        ("PyEMD FIXE=10", _pyemd(FIXE=10), args.repeat),
        ("PyEMD MAX_ITERATION=50", _pyemd(MAX_ITERATION=50), args.repeat),
        ("emd.sift (Quinn) default", _emd_sift, args.repeat),
    ]
    if args.full:
        candidates += [
            ("PyEMD FIXE_H=5", _pyemd(FIXE_H=5), 1),
            ("PyEMD extrema parabol", _pyemd(extrema_detection="parabol"), 1),
            ("PyEMD spline pchip", _pyemd(spline_kind="pchip"), 1),
            ("PyEMD JitEMD (compiled)", _jit, 1),
        ]
    ref_t, ref = None, None
    ref_sel = None
    print(f"{'candidate':34s} {'wall [s]':>8s} {'CPU [s]':>8s} {'ratio':>7s} {'IMFs':>5s}  "
          f"nRMS IMF1-3               selection  agrees")
    for name, fn, repeat in candidates:
        try:
            if fn is _jit:
                t0 = time.perf_counter()
                fn(x[:2000])  # numba compilation, reported separately
                t_comp = time.perf_counter() - t0
                name += f" (+{t_comp:.0f} s jit)"
            wall, t, imfs = _best(lambda fn=fn: fn(x), repeat)
        except ImportError as exc:
            print(f"{name:34s} skipped ({exc.name} not installed)")
            continue
        sel = select_imfs(x, _Dec(imfs), method="correlation", threshold="ayenu-prah").indices
        if ref is None:
            ref_t, ref, ref_sel = t, imfs, sel
        k = min(3, imfs.shape[0], ref.shape[0])
        d = [nrms(imfs[i], ref[i]) for i in range(k)]
        ok = k == 3 and max(d) < TOL_NRMS
        print(f"{name:34s} {wall:8.2f} {t:8.2f} {ref_t / t:6.1f}x {imfs.shape[0]:5d}  "
              + " ".join(f"{v:.1e}" for v in d).ljust(25)
              + f" {'same' if sel == ref_sel else 'differs':9s}  {'yes' if ok else 'no'}", flush=True)


class _Dec:
    """Minimal stand-in for a Decomposition (IMFs only) for select_imfs."""

    def __init__(self, imfs):
        self.imfs = np.atleast_2d(imfs)
        self.start = 0


if __name__ == "__main__":
    main()
