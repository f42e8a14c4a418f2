"""The compiled active-set solve of the mesh law (issue 25, cost of the calibrated model).

:func:`gearsim.stiffness.mesh.extended_law` solves the pairs' compliance systems and the
tip-corner active set in compiled kernels (:mod:`gearsim.stiffness._kernels`:
``tridiagonal_solve``, ``extended_law_solve`` and its threaded form). They repeat the
numpy implementation they replaced operation for operation, so the tables must be the
same to the last bit; that numpy implementation is kept here, as the reference only.
The Thomas solve is also checked against an independent banded LU (LAPACK gbsv through
``scipy.linalg.solve_banded``).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable

import numpy as np
import pytest
from scipy.linalg import solve_banded

import gearsim as gs
from gearsim.stiffness import _kernels
from gearsim.stiffness import mesh as mesh_mod
from gearsim.stiffness.mesh import (
    CORNER_PASSES,
    LINE_ITERATIONS,
    _tridiagonal_solve,
    mesh_stiffness,
)
from gearsim.stiffness.settings import MODELS
from gearsim.system.train import body_coupling, tooth_compliance

#: Relative residual allowed between the Thomas solve and LAPACK's banded LU with
#: partial pivoting on the random diagonally dominant systems below: both are backward
#: stable there (Golub & Van Loan 2013, sec. 4.3), with condition numbers < 10 (off
#: diagonal <= 0.45 of the diagonal), so the solutions agree to a few units of round-off
#: (2.2e-16) times the condition number; 1e-13 leaves a factor ~50 above that.
BANDED_RTOL = 1e-13


# --- the numpy implementation the kernels replaced (reference only) --------------------


def _numpy_tridiagonal_solve(diag, off, *rhs):
    """The former ``gearsim.stiffness.mesh._tridiagonal_solve`` (numpy, axis 1)."""
    m = diag.shape[1]
    cp = np.empty(off.shape)
    rp = [np.empty(diag.shape) for _ in rhs]
    den = diag[:, 0]
    for j, r in enumerate(rhs):
        rp[j][:, 0] = r[:, 0] / den
    for i in range(1, m):
        cp[:, i - 1] = off[:, i - 1] / den
        den = diag[:, i] - off[:, i - 1] * cp[:, i - 1]
        for j, r in enumerate(rhs):
            rp[j][:, i] = (r[:, i] - off[:, i - 1] * rp[j][:, i - 1]) / den
    for i in range(m - 2, -1, -1):
        for x in rp:
            x[:, i] -= cp[:, i] * x[:, i + 1]
    return tuple(rp)


def _numpy_extended_law(width, corner, separation, rate, ch, cross, contact, force
                        ) -> Callable:
    """The former ``gearsim.stiffness.mesh.extended_law`` (numpy active set)."""
    exists = width > 0
    path = exists & ~corner
    cand = exists & corner
    s_pos = np.where(cand, separation, 0.0)
    rho = np.where(cand, rate, 1.0)

    def solve(cdiag, act, cross):
        if cross is None:
            with np.errstate(divide="ignore", invalid="ignore"):
                a = np.where(act, rho / cdiag, 0.0)
            b = a * s_pos
        else:
            off = np.where(act[:, :-1] & act[:, 1:], cross, 0.0)
            a, b = _numpy_tridiagonal_solve(np.where(act, cdiag, 1.0), off,
                                            np.where(act, rho, 0.0),
                                            np.where(act, rho * s_pos, 0.0))
        delta = (force + np.sum(width * rho * b, axis=(1, 2))) / np.sum(width * rho * a,
                                                                         axis=(1, 2))
        return delta, np.where(act, delta[:, None, None] * a - b, 0.0)

    def law(teeth, cross_now=None):
        cx = cross if cross_now is None else cross_now
        chs = np.full(width.shape, ch)
        act = path.copy()
        q = np.zeros(width.shape)
        for it in range(LINE_ITERATIONS + 1):
            if it:
                chs = np.where(exists & (q > 0), contact(np.where(q > 0, q, 1.0)), chs)
            cdiag = chs + teeth
            for _ in range(CORNER_PASSES):
                delta, q = solve(cdiag, act, cx)
                approach = rho * (delta[:, None, None] - s_pos)
                if cx is not None:
                    approach[:, 1:] -= np.where(cand[:, 1:], cx * q[:, :-1], 0.0)
                    approach[:, :-1] -= np.where(cand[:, :-1], cx * q[:, 1:], 0.0)
                new = path | (cand & np.where(act, q > 0, approach > 0))
                if np.array_equal(new, act):
                    break
                act = new
        ks = np.where(act, width * rho * q / delta[:, None, None], 0.0)
        return ks, chs

    return law


# --- the tridiagonal solve ---------------------------------------------------------------


def _random_system(rng, n: int, m: int, k: int):
    """Diagonally dominant symmetric tridiagonal systems (n, m, k) and two right sides."""
    diag = rng.uniform(1.0, 3.0, (n, m, k)) * 1e-11  # m^2/N, a slice's pair compliance
    off = rng.uniform(-0.45, 0.45, (n, m - 1, k)) * np.minimum(diag[:, :-1], diag[:, 1:])
    r0 = rng.uniform(0.0, 1.0, (n, m, k))
    r1 = rng.standard_normal((n, m, k)) * 1e-5
    return diag, off, r0, r1


@pytest.mark.parametrize("m", [1, 2, 5, 9])
def test_tridiagonal_solve_against_banded_lu(m):
    """The compiled Thomas solve against LAPACK's banded LU, column by column."""
    rng = np.random.default_rng(25 + m)
    n, k = 7, 6
    diag, off, r0, r1 = _random_system(rng, n, m, k)
    x0, x1 = _tridiagonal_solve(diag, off, r0, r1)
    worst = 0.0
    for p in range(n):
        for s in range(k):
            ab = np.zeros((3, m))
            ab[0, 1:] = off[p, :, s]
            ab[1] = diag[p, :, s]
            ab[2, :-1] = off[p, :, s]
            ref = solve_banded((1, 1), ab, np.stack([r0[p, :, s], r1[p, :, s]], axis=1))
            for got, want in ((x0[p, :, s], ref[:, 0]), (x1[p, :, s], ref[:, 1])):
                worst = max(worst, np.max(np.abs(got - want)) / np.max(np.abs(want)))
    assert worst < BANDED_RTOL


@pytest.mark.parametrize("shape", [(40, 5, 40), (3, 4, 1), (6, 7, 2, 3)])
def test_tridiagonal_solve_is_the_numpy_solve_to_the_bit(shape):
    """Same operations in the same order: the numpy solve's results, bit for bit
    (also for trailing axes beyond the third, as the mesh of contacts passes)."""
    rng = np.random.default_rng(7)
    n, m, rest = shape[0], shape[1], shape[2:]
    k = int(np.prod(rest))
    diag, off, r0, r1 = (a.reshape(a.shape[:2] + rest) for a in _random_system(rng, n, m, k))
    got = _tridiagonal_solve(diag, off, r0, r1)
    want = _numpy_tridiagonal_solve(diag, off, r0, r1)
    for g, w in zip(got, want, strict=True):
        assert g.shape == w.shape
        assert np.array_equal(g, w)


def test_pairwise_sum_is_numpy_sum():
    """The compiled sum of a position's contacts is np.sum's over (age, slice), bit for
    bit, at the sizes of the tables (n_age x ns = 4 ... 300) and beyond (2000)."""
    rng = np.random.default_rng(3)
    for shape in [(40, 5, 40), (40, 4, 1), (40, 7, 1), (3, 9, 17), (2, 3, 100), (2, 50, 40)]:
        x = rng.standard_normal(shape) * 10.0 ** rng.uniform(-8, 8, shape)
        want = np.sum(x, axis=(1, 2))
        flat = x.reshape(shape[0], -1)
        got = [0.0 + _kernels.pairwise_sum(f, 0, f.shape[0]) for f in flat]
        assert np.array_equal(got, want)


# --- whole tables against the numpy law ---------------------------------------------------


def _calibrated(name: str, slices: int, npc: int):
    train = gs.example(name).train
    st = dataclasses.replace(train.stiffness, slices=slices, positions_per_cycle=npc,
                             **MODELS["seed"])
    st = dataclasses.replace(st, source="calibrated", contact="line", coupling="fe")
    return train, st


def _revolution(train, st):
    return mesh_stiffness(train.pairs[0], cracks=train.mesh_cracks(0), settings=st,
                          compliance=tooth_compliance(st.source),
                          force=train.static_mesh_force(0), coupling=body_coupling(st))


def _assert_same_tables(a, b):
    assert np.array_equal(a.k, b.k)
    assert np.array_equal(a.pair_k, b.pair_k)
    for c in a.components:
        assert np.array_equal(a.components[c], b.components[c]), c


@pytest.mark.parametrize(("name", "slices", "coupling"),
                         [("idler-table1", 40, "fe"), ("spur-19-48", 40, "fe"),
                          ("idler-table1", 10, "none")])
def test_revolution_is_the_numpy_law_to_the_bit(name, slices, coupling, monkeypatch):
    """A whole calibrated revolution (Table-1 mesh I with its crack: 40 slices x 40
    positions, the bench's table; the 19/48 pair) equals the numpy law's table bit for
    bit, on one numba thread and on the threaded kernel; without coupling too."""
    train, st = _calibrated(name, slices, 40)
    if coupling == "none":
        st = dataclasses.replace(st, source="pe", coupling="none")
    assert st.corner_contact
    new = _revolution(train, st)
    with monkeypatch.context() as mp:
        mp.setattr(mesh_mod, "extended_law", _numpy_extended_law)
        ref = _revolution(train, st)
    _assert_same_tables(new, ref)
    assert ref.k.size == train.pairs[0].driver.teeth * 40
    # the threaded kernel, whatever the number of threads of this process
    with monkeypatch.context() as mp:
        mp.setattr(mesh_mod.numba, "get_num_threads", lambda: 2)
        mp.setattr(mesh_mod, "THREADED_MIN_CONTACTS", 1)
        threaded = _revolution(train, st)
    _assert_same_tables(threaded, ref)


def test_revolution_on_two_threads_is_the_one_thread_revolution():
    """A whole calibrated revolution (Table-1 mesh I, 40 slices x 40 positions: the law's
    threaded kernel above THREADED_MIN_CONTACTS) computed in a process with two numba
    threads and with one: the same table bit for bit, and the threaded kernel ran. A
    separate process, as the suite's workers run with one numba thread."""
    import os
    import subprocess
    import sys

    prog = ("import dataclasses, numba, numpy as np\n"
            "from gearsim.model import example\n"
            "from gearsim.stiffness import _kernels\n"
            "from gearsim.stiffness.mesh import mesh_stiffness\n"
            "from gearsim.stiffness.settings import MODELS\n"
            "from gearsim.system.train import body_coupling, tooth_compliance\n"
            "tr = example('idler-table1').train\n"
            "st = dataclasses.replace(tr.stiffness, slices=40, positions_per_cycle=40,\n"
            "                         **MODELS['accurate'])\n"
            "out = []\n"
            "for n in (1, 2):\n"
            "    numba.set_num_threads(n)\n"
            "    ms = mesh_stiffness(tr.pairs[0], cracks=tr.mesh_cracks(0), settings=st,\n"
            "                        compliance=tooth_compliance(st.source),\n"
            "                        force=tr.static_mesh_force(0), coupling=body_coupling(st))\n"
            "    out.append(np.concatenate([ms.k, ms.pair_k.ravel(),\n"
            "                               *ms.components.values()]))\n"
            "print(numba.get_num_threads(), np.array_equal(*out),\n"
            "      len(_kernels.extended_law_solve_threads.signatures) > 0)\n")
    env = {**os.environ, "NUMBA_NUM_THREADS": "2"}
    res = subprocess.run([sys.executable, "-c", prog], capture_output=True, text=True,
                         env=env, timeout=300)
    assert res.returncode == 0, res.stderr
    assert res.stdout.split() == ["2", "True", "True"]
