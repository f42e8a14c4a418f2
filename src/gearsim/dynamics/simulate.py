"""Run the train dynamics: checks, fixed-step RK4 kernel, decimation, labelled result.

Time grid and anti-aliasing
---------------------------
The output samples are at ``t_k = T_tr + k / fs`` (T_tr: the transient, dropped). The
kernel records instantaneous samples at the internal rate ``r fs`` (``r`` =
``oversample``, default 2) and the integration step is an integer divisor of the
internal sample interval, ``dt = 1 / (r fs m)`` with the smallest integer m that makes
``dt <= step``. The internal samples of the mesh forces and of the state are low-pass
filtered with a linear-phase FIR filter (Kaiser window, beta 8, 24 r + 1 taps, cut-off
0.45 fs) and taken every r-th sample (centred, so without delay). Everything reported
but the STE and the tacho is linear in (q, q', f), so filtering and combining commute:
:func:`linear_records` combines some channels before the filter (bearing forces, mesh
deflections) and the rest after it, so that fewer signals are filtered. Content above
r fs / 2 (e.g. images of the stiffness table at 40 f_m, about 1e-6 of the static force)
could still fold into the output; it is negligible for the default settings.
``oversample = 1`` gives unfiltered instantaneous samples.

Checks before running
---------------------
First, from the settings and the train alone (:func:`check_cost`, before the model is
built, so a refusal takes milliseconds):

* no shaft twisted past :data:`Q_LIMIT` by its static torque, T / k_t (:func:`check_twist`:
  the run would stop at its first step, whatever the step);
* the duration must cover one revolution of the slowest gear;
* no aliasing: ``fs > 2 n f_m`` with n the highest mesh harmonic the record is for
  (``harmonics``: 1 for the API, the highest ``[analysis] orders`` for ``gearsim
  simulate`` and the studies, default 4);
* the cost: at most :data:`MAX_STEPS` RK4 steps, ``(transient + duration) / dt``, and an
  estimated peak memory of at most :data:`MEMORY_FRACTION` of the machine's physical
  memory. Both bounds are lifted by ``force=True`` (``gearsim simulate --force``) or the
  environment variable ``GEARSIM_FORCE=1``.

Then, with the model: the step must be below the RK4 stability limit ``2.78 /
omega_max`` (highest natural frequency with the largest tabulated stiffness), and the
cost is checked again with the default transient (12 decay times of the slowest mode)
once it is known. During the run the kernel stops when a coordinate leaves [-1, 1] m
(or rad) or is not finite, and :class:`SimulationError` is raised; no NaN output is
produced.
"""

from __future__ import annotations

import functools
import json
import math
import os
import re
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from gearsim._version import __version__
from gearsim.dynamics import _kernels
from gearsim.dynamics.layout import idlers
from gearsim.dynamics.lta import _segment_torque, build_lta
from gearsim.dynamics.modal import decay_time, modes, stable_step
from gearsim.dynamics.model import DynamicModel
from gearsim.dynamics.seed3dof import build_seed
from gearsim.dynamics.settings import DynamicsSettings
from gearsim.dynamics.tables import MeshTable, mesh_tables
from gearsim.errors import (  # noqa: F401  (FORCE_ENV, cost_bounds_lifted: re-exported)
    FORCE_ENV,
    InputError,
    SimulationError,
    cost_bounds_lifted,
    warn_model_range,
)
from gearsim.system.toml import train_to_toml
from gearsim.system.train import GearTrain

__all__ = ["FORCE_ENV", "MAX_STEPS", "MEMORY_FRACTION", "LinearRecords", "Raw", "RunCost",
           "anti_alias_taps",
           "build_model",
           "check_cost", "check_twist", "check_twists", "cost_bounds_lifted", "integration_step",
           "linear_records",
           "nominal_acceleration_load",
           "physical_memory", "record", "reference_mesh_forces", "reference_rhs", "run_kernel",
           "settings_of", "simulate", "simulate_record", "summary", "tacho_variable"]

#: |q| limit [m or rad] beyond which a run counts as diverged.
Q_LIMIT = 1.0
#: FIR half length per unit oversampling factor, and Kaiser beta (see module docstring).
FIR_HALF_PER_R = 12
#: Largest spectral line of a mesh force's internal record in the top quarter below the
#: internal Nyquist r fs / 2, as a share of its largest line in the output band (0, 0.45
#: fs], above which the run warns that content above r fs / 2 has likely folded into the
#: record (the kernel samples, it does not average). Share against the folding measured
#: (largest spectral difference from the same run at r = 12-24, share of the largest
#: line): the examples 0.0014-0.13 against 0.04-2.5 %; a 23/57 pair at 20 and 10 kHz
#: 0.094 / 1 % and 0.30 / 12 %; a 30/24/78 stage at 20 kHz 0.92 / 9.9 %; a 24/36/96
#: stage driving a 90/23 pair at 2 kHz 2.0, its two largest lines aliases. 0.25 warns
#: from about 5-10 % on; it is a screen, not a bound (docs/dynamics.md 5).
ALIAS_SHARE = 0.25
#: Internal samples the check of :data:`ALIAS_SHARE` reads (the last ones): 2^15, 0.33 s
#: at 100 kHz, lines 3 Hz apart; about 1 ms a mesh.
FOLD_BLOCK = 2 ** 15
#: Lines below this share of a force's mean are round-off, not content (a stage of
#: constant mesh stiffnesses: 1e-16 of its mean force; the mesh harmonics of nrel-grc's
#: stage, the smallest of the examples': 8e-5).
FOLD_FLOOR = 1e-9
FIR_BETA = 8.0
FIR_CUTOFF = 0.45  # of fs

#: Largest number of RK4 steps of one run without ``force``. The compiled kernel takes
#: about 1e5 to 2e5 steps per second on the three-gear Table-1 train (one core), so 1e9
#: steps are hours of computing: past it, a run is almost surely a typing error (``--fs
#: 1e9``, ``--step 1e-12``, ``--duration 1e6``).
MAX_STEPS = 1e9
#: Largest share of the machine's physical memory the estimated peak of a run's arrays
#: may take without ``force`` (the rest is for the system, the analysis, the writer).
MEMORY_FRACTION = 0.5
_OVERRIDE = f"or override with --force ({FORCE_ENV}=1)"


def settings_of(train: GearTrain, settings: DynamicsSettings | None = None) -> DynamicsSettings:
    """The explicit settings, else the defaults.

    Parameters
    ----------
    train : GearTrain
        The train (kept for the call signature of the model builders).
    settings : DynamicsSettings, optional
        Settings given by the caller (a :class:`gearsim.model.Gearbox` carries the
        config's ``[dynamics]`` section).

    Returns
    -------
    DynamicsSettings
    """
    return settings if settings is not None else DynamicsSettings()


def build_model(train: GearTrain, settings: DynamicsSettings | None = None, *,
                tables: tuple[MeshTable, ...] | None = None) -> DynamicModel:
    """Equations of motion of ``train`` for ``settings.model`` ("lta", "torsional", "seed").

    Parameters
    ----------
    train : GearTrain
        Gear chain with operating point and cracks.
    settings : DynamicsSettings, optional
        Dynamics options; default :class:`DynamicsSettings` ``()``.
    tables : tuple of MeshTable, optional
        Precomputed stiffness tables; default :func:`mesh_tables` of ``train``.

    Returns
    -------
    DynamicModel
        :func:`gearsim.dynamics.seed3dof.build_seed` for ``"seed"``, else
        :func:`gearsim.dynamics.lta.build_lta` (both fidelity levels of a gearbox).

    Raises
    ------
    InputError
        A per-item option of the wrong length, or an idler angle that makes gears
        overlap.
    """
    settings = settings_of(train, settings)
    tables = tables or mesh_tables(train, contacts=settings.contact_mesh)
    if settings.model == "seed":
        return build_seed(train, settings, tables=tables)
    return build_lta(train, settings, tables=tables)


def integration_step(settings: DynamicsSettings) -> tuple[float, int]:
    """(dt, m): the step used and the number of steps per internal sample.

    ``dt = 1 / (r fs m)`` with the smallest integer m >= 1 that makes ``dt <= step``
    (r = ``oversample``), so every internal sample falls on a step.

    Parameters
    ----------
    settings : DynamicsSettings
        Uses ``step`` [s], ``fs`` [Hz] and ``oversample``.

    Returns
    -------
    dt : float
        Integration step [s].
    m : int
        Steps per internal sample.

    Examples
    --------
    50 kHz output, oversampling 2 (internal samples every 10 us), largest step 3 us:
    m = ceil(10 / 3) = 4 steps of 2.5 us.

    >>> from gearsim.dynamics.settings import DynamicsSettings
    >>> from gearsim.dynamics.simulate import integration_step
    >>> dt, m = integration_step(DynamicsSettings(step=3e-6, fs=50e3, oversample=2))
    >>> round(dt * 1e6, 9), m
    (2.5, 4)
    """
    t_int = 1.0 / (settings.oversample * settings.fs)
    m = max(1, math.ceil(t_int / settings.step * (1 - 1e-12)))
    return t_int / m, m


@dataclass
class Raw:
    """Instantaneous kernel records (internal rate), returned by :func:`run_kernel`.

    Parameters
    ----------
    t : ndarray, shape (n_rec,)
        Record times [s].
    q, v : ndarray, shape (n_rec, n_dof)
        Coordinates [m, rad] and velocities [m/s, rad/s] at the record times.
    f : ndarray, shape (n_rec, n_mesh)
        Mesh forces f_i (kernel units, before ``to_transverse``) [N].
    q_end, v_end : ndarray, shape (n_dof,)
        State after the last step.
    channels : ndarray, shape (n_q + n_v + n_f, n_rec), optional
        The same records one channel per row, as the kernel writes them (the recorded
        columns of q, then of q', then of f): ``q``, ``v`` and ``f`` are transposed views
        of its row blocks (the anti-aliasing filter reads the rows, without a copy).
    """

    t: np.ndarray
    q: np.ndarray
    v: np.ndarray
    f: np.ndarray
    q_end: np.ndarray
    v_end: np.ndarray
    channels: np.ndarray | None = None


def _kernel_args(model: DynamicModel):
    """Packed kernel arguments (layout in :mod:`gearsim.dynamics._kernels`)."""
    tabs = model.tables
    lens = np.array([t.k.size for t in tabs], dtype=np.int64)
    offs = np.concatenate([[0], np.cumsum(lens)[:-1]]).astype(np.int64)
    g = np.zeros(model.n_dof) if model.inertial is None else model.inertial
    dof = np.ascontiguousarray(np.stack([1.0 / model.mass, model.kb, model.cb, model.fext, g]),
                               dtype=float)
    mp = np.ascontiguousarray(np.stack(
        [model.kappa, model.kscale, model.cm, model.clearance, model.phase, model.e0,
         np.array([t.positions_per_cycle for t in tabs], dtype=float),
         np.array([t.period for t in tabs], dtype=float), model.mesh_frequencies], axis=1),
        dtype=float)
    tabz, on, ptr, poff, cx = _contact_args(tabs)
    mi = np.ascontiguousarray(np.stack([offs, lens, on, poff], axis=1), dtype=np.int64)
    nh = model.h_amp.shape[1]
    a = np.zeros((3, model.n_mesh, nh))
    if model.a_amp is not None:  # centre-distance harmonics beside the STE harmonics
        na = model.a_amp.shape[1]
        if na > nh:
            raise ValueError("more centre-distance than STE harmonics")
        a[0, :, :na], a[1, :, :na], a[2, :, :na] = model.a_amp, model.a_omega, model.a_phase
    harm = np.ascontiguousarray(np.concatenate(
        [np.stack([model.h_amp, model.h_omega, model.h_phase]), a]), dtype=float)
    tabd = np.concatenate([t.dk_da if t.dk_da is not None else np.zeros(t.k.size)
                           for t in tabs])
    prof = np.array([[0.0, 0.0, 1.0, 0.0]]) if model.profile is None else model.profile
    lam = np.array([[0.0, 1.0]]) if model.load is None else model.load
    return (dof, *_sparse_rows(model.V), mp, mi,
            np.concatenate([t.k for t in tabs]), tabz, np.ascontiguousarray(tabd),
            np.ascontiguousarray(prof, dtype=float), harm, ptr, cx,
            np.ascontiguousarray(lam, dtype=float))


def _sparse_rows(V: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``V`` as (columns, values) of each row's nonzero entries, ascending, padded with
    column 0 and value 0 (the kernel's ELL layout, :mod:`gearsim.dynamics._kernels`)."""
    V = np.asarray(V, dtype=float)
    nz = V != 0.0
    width = max(1, int(nz.sum(axis=1).max(initial=0)))
    col = np.zeros((V.shape[0], width), dtype=np.int64)
    val = np.zeros((V.shape[0], width))
    for i in range(V.shape[0]):
        (c,) = np.nonzero(nz[i])
        col[i, :c.size] = c
        val[i, :c.size] = V[i, c]
    return col, val


def _contact_args(tabs):
    """Kernel arrays of the meshes of contacts: k_zero tables, flags and row offsets per
    mesh, CSR row pointers, listed (stiffness, separation) pairs."""
    tabz = np.concatenate([t.k_zero if t.has_contacts else t.k for t in tabs])
    on = np.array([1 if t.has_contacts else 0 for t in tabs], dtype=np.int64)
    ptrs, kxs, sxs, poff = [], [], [], []
    n_ptr = 0
    n_x = 0
    for t in tabs:
        poff.append(n_ptr)
        if t.has_contacts:
            ptrs.append(t.ptr + n_x)
            kxs.append(t.kx)
            sxs.append(t.sx)
            n_ptr += t.ptr.size
            n_x += t.kx.size
    ptr = np.concatenate(ptrs).astype(np.int64) if ptrs else np.zeros(1, dtype=np.int64)
    kx = np.concatenate(kxs) if kxs else np.zeros(1)
    sx = np.concatenate(sxs) if sxs else np.zeros(1)
    cx = np.ascontiguousarray(np.stack([kx, sx]), dtype=float)
    return (np.ascontiguousarray(tabz, dtype=float), on, ptr,
            np.array(poff, dtype=np.int64), cx)


def run_kernel(model: DynamicModel, *, dt: float, n_steps: int, rec_start: int = 0,
               rec_every: int = 1, n_rec: int | None = None, q0: np.ndarray | None = None,
               v0: np.ndarray | None = None, t0: float = 0.0,
               channels: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None) -> Raw:
    """Integrate ``model`` with the compiled RK4 kernel and return the raw records.

    Parameters
    ----------
    model
        Equations of motion.
    dt
        Step [s].
    n_steps
        Number of steps from ``t0``.
    rec_start, rec_every, n_rec
        Record at steps ``rec_start + r rec_every``, r < n_rec (default: all to the end).
    q0, v0
        Initial state (default: static equilibrium of the mean system, at rest).
    t0
        Initial time [s].
    channels
        Columns of q, q' and the mesh forces to record (int arrays; default: all). The
        state is integrated whole; only the records are narrower.

    Raises
    ------
    SimulationError
        If the solution diverges.
    """
    if n_rec is None:
        n_rec = (n_steps - rec_start) // rec_every + 1
    q0 = model.q_static.copy() if q0 is None else np.asarray(q0, dtype=float).copy()
    v0 = np.zeros(model.n_dof) if v0 is None else np.asarray(v0, dtype=float).copy()
    contacts = any(t.has_contacts for t in model.tables)
    profiled = model.profile is not None or model.load is not None
    integrate = {(False, False): _kernels.integrate_rk4,
                 (True, False): _kernels.integrate_rk4_contacts,
                 (False, True): _kernels.integrate_rk4_profile,
                 (True, True): _kernels.integrate_rk4_contacts_profile}[contacts, profiled]
    # records allocated by numpy (huge pages for large arrays: fewer page faults than the
    # kernel's own allocation, _kernels.integrate_rk4), one channel per row: the row
    # blocks of q, q' and f of one array (C-contiguous), which the filter reads as is
    n_rec = int(n_rec)
    if channels is None:
        channels = (np.arange(model.n_dof), np.arange(model.n_dof), np.arange(model.n_mesh))
    cols = tuple(np.ascontiguousarray(c, dtype=np.int64) for c in channels)
    nq, nv = cols[0].size, cols[1].size
    x = np.zeros((nq + nv + cols[2].size, n_rec))
    rec = (x[:nq], x[nq:nq + nv], x[nq + nv:])
    status, step, _, _, _, q, v = integrate(
        q0, v0, float(t0), float(dt), int(n_steps), int(rec_start), int(rec_every), *rec,
        *cols, Q_LIMIT, *_kernel_args(model))
    if status != 0:
        raise SimulationError(
            f"the {model.kind} simulation diverged at t = {t0 + step * dt:.6g} s (step "
            f"{step} of {n_steps}, dt = {dt:.4g} s): a coordinate left [-{Q_LIMIT}, "
            f"{Q_LIMIT}] or became NaN; reduce dynamics.step or check the inputs")
    t = t0 + (rec_start + rec_every * np.arange(n_rec)) * dt
    return Raw(t=t, q=rec[0].T, v=rec[1].T, f=rec[2].T, q_end=q, v_end=v, channels=x)


def anti_alias_taps(r: int, fs: float) -> np.ndarray:
    """Taps of the anti-aliasing low-pass that decimates the internal rate r fs to fs.

    The Kaiser-window design of a linear-phase FIR (Oppenheim & Schafer, *Discrete-Time
    Signal Processing*, 3rd ed., 2010, sec. 7.6): the ideal low-pass impulse response
    h_d[n] = w_c sinc(w_c (n - M/2)), w_c = the cut-off ``FIR_CUTOFF fs`` over the
    Nyquist rate r fs / 2, times the Kaiser window of ``FIR_BETA``,
    w[n] = I_0(beta sqrt(1 - ((n - M/2) / (M/2))^2)) / I_0(beta)
    (:func:`scipy.special.i0`), M + 1 = 2 ``FIR_HALF_PER_R`` r + 1 taps, scaled to unit
    gain at 0 Hz. These are the taps of ``scipy.signal.firwin(M + 1, FIR_CUTOFF fs,
    window=("kaiser", FIR_BETA), fs=r fs)``, the same operations in the same order (equal
    to the bit, tested), without importing ``scipy.signal`` (0.4-0.7 s of start-up;
    ``scipy.special`` comes with xarray's first variable anyway).

    Parameters
    ----------
    r : int
        Oversampling factor (internal rate over output rate), >= 2.
    fs : float
        Output sampling rate [Hz].

    Returns
    -------
    ndarray, shape (2 FIR_HALF_PER_R r + 1,)
        The taps [-], summing to 1 (a new array; the design is made once per ``(r,
        fs)``).
    """
    return _taps(int(r), float(fs)).copy()


@functools.lru_cache(maxsize=32)
def _taps(r: int, fs: float) -> np.ndarray:
    """:func:`anti_alias_taps`, computed once per (r, fs) (read-only)."""
    from scipy.special import i0

    taps = 2 * FIR_HALF_PER_R * r + 1
    cutoff = FIR_CUTOFF * fs / (0.5 * (r * fs))  # of the internal Nyquist rate
    half = 0.5 * (taps - 1)
    n = np.arange(0, taps, dtype=float) - half
    h = cutoff * np.sinc(cutoff * n)
    h *= i0(FIR_BETA * np.sqrt(1 - ((np.arange(0, taps, dtype=float) - half) / half) ** 2.0)
            ) / i0(np.float64(FIR_BETA))
    h = h / np.sum(h)
    h.flags.writeable = False
    return h


@dataclass(frozen=True)
class RunCost:
    """What a run will take, estimated by :func:`check_cost` before it starts.

    Parameters
    ----------
    steps : float
        RK4 steps, transient included.
    samples : float
        Output samples (``round(duration fs)``).
    internal_samples : float
        Samples recorded by the kernel (``oversample`` times more, plus the filter
        margins).
    memory : float
        Estimated peak of the run's arrays [bytes].
    dt : float
        Integration step [s].
    transient : float
        Transient used for the estimate [s] (0 while the default is not yet known).
    """

    steps: float
    samples: float
    internal_samples: float
    memory: float
    dt: float
    transient: float


def physical_memory() -> int | None:
    """Physical memory of the machine [bytes], or ``None`` if it cannot be read.

    Returns
    -------
    int or None
        ``MemTotal`` of ``/proc/meminfo``, else ``os.sysconf`` pages x page size.
    """
    try:
        with open("/proc/meminfo", encoding="ascii") as f:
            for line in f:
                if line.startswith("MemTotal:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    try:
        return int(os.sysconf("SC_PHYS_PAGES")) * int(os.sysconf("SC_PAGE_SIZE"))
    except (AttributeError, ValueError, OSError):
        return None


def _gigabytes(n: float) -> str:
    return f"{n / 1e9:.3g} GB"


def check_cost(train: GearTrain, settings: DynamicsSettings | None = None, *,
               harmonics: int = 1, transient: float | Callable[[], float] | None = None,
               force: bool | None = None) -> RunCost:
    """Refuse, before any work, a run that is too short, aliased or too costly.

    Only arithmetic on the settings and the train (no model is built), so the API, the
    CLI, the studies and the sweeps can check every case up front.

    Parameters
    ----------
    train : GearTrain
        The train (shaft and mesh frequencies, number of gears and meshes).
    settings : DynamicsSettings, optional
        Dynamics options; default :class:`DynamicsSettings` ``()``.
    harmonics : int
        Highest mesh harmonic n the record must hold: ``fs > 2 n f_m`` (1: the mesh
        frequency itself; the analysis of ``gearsim`` uses up to 4 by default).
    transient : float or callable, optional
        Transient [s] to count; default ``settings.transient``, or 0 when that is the
        default (known only with the model: :func:`simulate` checks again). A callable
        returns the default transient: called only when the run is refused for its
        steps, so that the refusal states the transient the run would use.
    force : bool, optional
        Lift the step and memory bounds; default: the environment variable
        ``GEARSIM_FORCE`` (set to 1). The duration and aliasing checks always apply.

    Returns
    -------
    RunCost
        The estimate.

    Raises
    ------
    InputError
        ``dynamics.duration`` shorter than one revolution of the slowest gear;
        ``dynamics.fs`` not above ``2 n f_m``; ``dynamics.idler_angle`` given for a train
        without idlers; more than :data:`MAX_STEPS` steps or an
        estimated memory above :data:`MEMORY_FRACTION` of the physical memory (the
        parameter named is the one that contributes most: ``dynamics.fs``,
        ``dynamics.step``, ``dynamics.duration`` or ``dynamics.transient``).

    Examples
    --------
    >>> from gearsim.model import load
    >>> from gearsim.dynamics.settings import DynamicsSettings
    >>> from gearsim.dynamics.simulate import check_cost
    >>> train = load("spur-19-48").train
    >>> round(check_cost(train, DynamicsSettings(duration=1.0, transient=0.0)).steps, -3)
    100000.0
    >>> check_cost(train, DynamicsSettings(duration=1e4, fs=1e6))  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    gearsim.errors.InputError: dynamics.duration = 10000.0: the run needs 2e+10 ...
    """
    s = settings_of(train, settings)
    s.per_item("idler_angle", len(idlers(train)), "idler")  # refused without idlers
    slow = min(range(len(train.gears)), key=train.shaft_frequency)
    t_rev = 1.0 / train.shaft_frequency(slow)
    if s.duration < t_rev * (1 - 1e-9):
        raise InputError("dynamics.duration", s.duration,
                         f"must be >= {t_rev:.6g} s (one revolution of the slowest gear, "
                         f"{train.gears[slow].name})")
    f_m = max(train.mesh_frequencies) * max(1.0, *(np.array(s.speed_values or (0.0,))
                                                   / train.operating.speed))
    n = max(1, int(harmonics))
    if not s.fs > 2.0 * n * f_m:
        which = "the mesh frequency f_m" if n == 1 else \
            f"the highest analysed mesh harmonic {n} f_m"
        fewer = "" if n == 1 else " or analyse fewer orders"
        raise InputError("dynamics.fs", s.fs,
                         f"must be > {2 * n * f_m:.6g} Hz, twice {which} = {n * f_m:.6g} Hz, "
                         f"else the record is aliased: raise fs, lower the speed{fewer}")
    default = transient if callable(transient) and s.transient is None else None
    if transient is None or callable(transient):
        transient = s.transient if s.transient is not None else 0.0
    if not math.isfinite(transient):
        raise InputError("dynamics.transient", transient,
                         "must be finite; the default (12 decay times of the slowest mode) "
                         "is infinite for an undamped system: give the transient")
    if s.speed_times is not None:  # the revolutions a speed profile turns over the record:
        # its nominal time tau (operating-speed seconds, exact) over t_rev
        prof, _ = s.profiles(train.operating.speed)
        one = np.array([[0.0, 1.0]])
        rev = (_kernels.nominal(transient + s.duration, prof, one)[0]
               - _kernels.nominal(transient, prof, one)[0]) / t_rev
        if rev < 1.0 - 1e-9:
            raise InputError("dynamics.speed_values", [f"{v * 30 / math.pi:g} rpm"
                                                       for v in s.speed_values],
                             f"turn the slowest gear, {train.gears[slow].name}, "
                             f"{rev:.3g} revolutions over the record ({transient:g} to "
                             f"{transient + s.duration:g} s): must turn it at least once")
    dt, _ = integration_step(s)
    r = s.oversample
    half = FIR_HALF_PER_R * r if r > 1 else 0
    t_int = 1.0 / (r * s.fs)
    n_out = float(round(s.duration * s.fs))
    n_rec = (n_out - 1) * r + 1 + 2 * half

    def count(transient: float) -> float:
        return (max(transient / t_int, half) + n_rec - 1 - half) * (t_int / dt)

    steps = count(transient)
    g, n_mesh = len(train.gears), len(train.pairs)
    n_dof = 4 * g
    width = 2 * n_dof + n_mesh  # q, v, f records
    out_vars = n_dof + 4 * n_mesh + 7 * g  # acceleration, dte, ste, forces, bearing data
    memory = 8.0 * (2 * n_rec * width + n_out * (2 * width + 2 * out_vars))
    cost = RunCost(steps=steps, samples=n_out, internal_samples=n_rec, memory=memory, dt=dt,
                   transient=transient)
    if cost_bounds_lifted(force):
        return cost
    if steps > MAX_STEPS:
        if default is not None:  # the transient the run would use (needs the model)
            transient = float(default())
            steps = count(transient) if math.isfinite(transient) else steps
        rate_ratio = (1.0 / dt) * 1e-5          # against the default 10 us step
        time_ratio = transient + s.duration     # against the default 1 s
        if rate_ratio >= time_ratio:
            name = "fs" if t_int < s.step * (1 - 1e-12) else "step"
        else:
            name = "transient" if transient > s.duration else "duration"
        raise InputError(f"dynamics.{name}", getattr(s, name) if name != "transient"
                         else transient,
                         f"the run needs {steps:.3g} integration steps (transient "
                         f"{max(math.ceil(transient / t_int - 1e-9), half) * t_int:.4g} s "
                         f"+ duration {s.duration:.4g} s at dt = {dt:.4g} "
                         f"s, the largest step {s.step:.4g} s divided to fall on the "
                         f"{1 / t_int:.6g} Hz internal samples), above the limit of "
                         f"{MAX_STEPS:.0e} (hours of computing): "
                         "shorten the duration or transient, raise the step or lower fs "
                         f"(--duration, --transient, --step, --fs), {_OVERRIDE}")
    ram = physical_memory()
    if ram is not None and memory > MEMORY_FRACTION * ram:
        name = "duration" if s.duration >= s.fs / 50e3 else "fs"
        raise InputError(f"dynamics.{name}", getattr(s, name),
                         f"the run needs about {_gigabytes(memory)} of memory for "
                         f"{n_out:.3g} output samples ({n_rec:.3g} internal), above half "
                         f"of this machine's {_gigabytes(ram)}: shorten the duration or "
                         f"lower fs (--duration, --fs), {_OVERRIDE}")
    return cost


def check_twist(torque: float, kt: object, parameter: str, shaft: str) -> None:
    """Refuse a shaft that its static torque twists past :data:`Q_LIMIT`.

    A run starts from the static equilibrium, in which a shaft of torsional stiffness
    k_t carrying the torque T is twisted by T / k_t [rad]; past ``Q_LIMIT`` the kernel
    stops at its first step as diverged, whatever the step.

    Parameters
    ----------
    torque : float
        Static torque T of the shaft [N m].
    kt : float or None
        Its torsional stiffness k_t [N m/rad]; ``None`` (rigid) or not a number > 0 (left
        to the bounds check): nothing to check.
    parameter : str
        The name of k_t for the message.
    shaft : str
        The shaft's name.

    Raises
    ------
    InputError
        T / k_t > ``Q_LIMIT``.
    """
    t = abs(torque)
    if isinstance(kt, (int, float)) and kt > 0 and t > Q_LIMIT * kt:
        raise InputError(parameter, f"{kt:.6g} N*m/rad", f"twists shaft {shaft} by {t / kt:.4g} "
                         f"rad under its static torque of {t:.6g} N*m, beyond the {Q_LIMIT:g} rad "
                         f"at which a run stops as diverged: give at least {t / Q_LIMIT:.6g} "
                         "N*m/rad")


def check_twists(train: GearTrain) -> None:
    """:func:`check_twist` of each shaft segment of ``train`` between two of its gears.

    Parameters
    ----------
    train : GearTrain
        The train in operation.

    Raises
    ------
    InputError
        A segment twisted past ``Q_LIMIT`` (``shafts.<name>.torsional_stiffness``).
    """
    for sh in train.flow.shafts:
        for a in sh.gears[:-1]:
            check_twist(_segment_torque(train, a), sh.torsional_stiffness,
                        f"shafts.{sh.name}.torsional_stiffness", sh.name)


def check_inputs(train: GearTrain, settings: DynamicsSettings, model: DynamicModel) -> float:
    """Refuse an unstable step; return the step used [s] (after :func:`check_cost`)."""
    dt, _ = integration_step(settings)
    limit = stable_step(model)
    if dt > limit:
        raise InputError("dynamics.step", settings.step,
                         f"is too large for RK4 stability (step used {dt:.4g} s); the largest "
                         f"safe step is {limit:.4g} s = 2.78 / omega_max (highest natural "
                         f"frequency {2.78 / limit / (2 * math.pi):.6g} Hz)")
    return dt


def simulate(train: GearTrain, settings: DynamicsSettings | None = None, *,
             tables: tuple[MeshTable, ...] | None = None, model: DynamicModel | None = None,
             check_step: bool = True, harmonics: int = 1, force: bool | None = None):
    """Simulate the gear train and return an :class:`xarray.Dataset`.

    Parameters
    ----------
    train
        Gear chain with operating point and cracks.
    settings
        Dynamics options; default: :class:`DynamicsSettings` ``()`` (the train does not
        carry the config's ``[dynamics]`` section: pass ``Gearbox.dynamics`` for it).
    tables, model
        Precomputed stiffness tables or model (parameter studies reuse them).
    check_step
        Refuse an unstable step before running (default). ``False`` only for tests of
        the divergence detection.
    harmonics
        Highest mesh harmonic the record must hold without aliasing, ``fs > 2 n f_m``
        (see :func:`check_cost`).
    force
        Lift the bounds on steps and memory (default: ``GEARSIM_FORCE`` in the
        environment); see :func:`check_cost`.

    Returns
    -------
    xarray.Dataset
        ``mesh_force_i`` (transverse line-of-action force, N), ``dte_i`` (m), ``ste_i``
        (m), ``bearing_force`` (N, gear x axis), ``acceleration`` (m/s^2, gear x axis),
        for the LTA model also ``angular_acceleration`` (rad/s^2); coordinate ``time``
        (s); attributes ``fs``, ``model``, ``config`` (TOML), ``dynamics`` (the run's
        options, JSON, SI), ``gearsim_version``, ...

    Raises
    ------
    InputError
        Duration shorter than one revolution of the slowest gear, aliasing, too many
        steps or too much memory (:func:`check_cost`, before any work), unstable step.
    SimulationError
        The run diverged.
    """
    settings, model, dt, m, transient = _prepare(train, settings, tables, model, check_step,
                                                 harmonics, force)
    lin = linear_records(model, train)
    t, z, transient = _run_linear(model, settings, lin, dt=dt, m=m, transient=transient)
    return _dataset(train, settings, model, lin, t, z, dt=dt, transient=transient)


def _prepare(train: GearTrain, settings: DynamicsSettings | None,
             tables: tuple[MeshTable, ...] | None, model: DynamicModel | None,
             check_step: bool, harmonics: int, force: bool | None
             ) -> tuple[DynamicsSettings, DynamicModel, float, int, float]:
    """Checks, model, step and transient of a run (:func:`simulate`, :func:`simulate_record`)."""
    settings = settings_of(train, settings)
    check_twists(train)

    def default_transient() -> float:  # the model, for a refusal to state the transient
        nonlocal model
        model = model or build_model(train, settings, tables=tables)
        return max(12.0 * decay_time(model), 1.0 / model.mesh_frequency)

    check_cost(train, settings, harmonics=harmonics, force=force, transient=default_transient)
    model = model or build_model(train, settings, tables=tables)
    if check_step:
        dt = check_inputs(train, settings, model)
    else:
        dt, _ = integration_step(settings)
    _, m = integration_step(settings)
    transient = settings.transient
    if transient is None:
        transient = default_transient()
        check_cost(train, settings, harmonics=harmonics, transient=transient, force=force)
    return settings, model, dt, m, transient


#: The records :func:`simulate_record` derives from the few channels they need:
#: ``mesh_force_i``, ``dte_i``, ``bearing_force[shaft,axis]``, ``acceleration[shaft,axis]``,
#: ``angular_acceleration[rotation]``.
_RECORD = re.compile(r"(mesh_force|dte)_(\d+)|(bearing_force|acceleration)\[([^,\]]+),([^,\]]+)\]"
                     r"|angular_acceleration\[([^,\]]+)\]")


def simulate_record(train: GearTrain, spec: str, settings: DynamicsSettings | None = None,
                    *, harmonics: int = 1, force: bool | None = None) -> np.ndarray | None:
    """One record of :func:`simulate`, computed from the channels it needs only.

    A parameter study analyses one record of each run (a bearing's acceleration, say).
    The run is the same (same checks, model, kernel and transient); only the channels
    the record is made of are decimated (:func:`record`: the FIR filter acts on each
    channel alone) and the record is formed from them after the filter: ``mesh_force_i
    = f_i c_i``; ``dte_i = (q V^T)_i + e_i``; ``bearing_force = k_b q_d + c_b q'_d``;
    ``acceleration = (F_d - k_b q_d - c_b q'_d - (f V)_d) / m_d``
    (``angular_acceleration`` likewise, at a rotation coordinate) (docs/dynamics.md
    section 6). No dataset is built.

    This is the order in which studies formed their records before :func:`simulate`
    came to form its records around the decimation (:func:`linear_records`): a study's
    records, and so its features, are those of before to the bit (docs/studies.md,
    "Results identical to before"). The two orders agree to 4.2e-14 of a record's
    largest value (``tests/dynamics/test_dyn_record.py``); features that follow a
    record's last bits (the spread of sidebands 1e-4 below the record's peak) would not.

    Parameters
    ----------
    train : GearTrain
        Gear chain with operating point and cracks.
    spec : str
        ``mesh_force_i``, ``dte_i`` (i from 1), ``bearing_force[shaft,axis]``,
        ``acceleration[shaft,axis]`` or ``angular_acceleration[rotation]``, blanks
        removed (:meth:`gearsim.model.Gearbox.signal_key`).
    settings : DynamicsSettings, optional
        As :func:`simulate`.
    harmonics : int, optional
        As :func:`simulate`.
    force : bool, optional
        As :func:`simulate`.

    Returns
    -------
    ndarray or None
        The record, equal to ``simulate(...)[variable].sel(...)`` to round-off (the same
        channels through the same filter, combined after it instead of before);
        ``None``, before any work, for a name this function does not derive or a label
        the train does not have (use :func:`simulate` and select the record there,
        which says what is wrong).

    Raises
    ------
    InputError, SimulationError
        As :func:`simulate`.
    """
    mt = _RECORD.fullmatch(spec)
    if mt is None:
        return None
    shafts = [sh.name for sh in train.flow.shafts]
    if mt.group(1):
        i = int(mt.group(2)) - 1
        if not 0 <= i < len(train.pairs):
            return None
    elif mt.group(6) is None and mt.group(4) not in shafts:
        return None
    settings, model, dt, m, transient = _prepare(train, settings, None, None, True,
                                                 harmonics, force)
    every = np.arange(model.n_dof)
    none = every[:0]
    whole = settings.oversample == 1  # record() returns every column (nothing to filter)
    if mt.group(1) == "mesh_force":
        _, _, _, f, _ = record(model, settings, dt=dt, m=m, transient=transient,
                               channels=(none, none, np.array([i])))
        return f[:, i if whole else 0] * model.to_transverse[i]
    if mt.group(1) == "dte":
        _, q, _, _, _ = record(model, settings, dt=dt, m=m, transient=transient,
                               channels=(every, none, none))
        return (q @ model.V.T + model.dte_offset)[:, i]
    if mt.group(6) is not None:  # a rotation coordinate (not of the seed's model)
        label = f"{mt.group(6)}.theta"
        if model.kind == "seed" or label not in model.dof_labels:
            return None
        d = model.dof_labels.index(label)
    elif mt.group(5) not in model.axes:
        return None
    else:
        d = int(model.bearing_dofs[shafts.index(mt.group(4)), model.axes.index(mt.group(5))])
    one = np.array([d])
    meshes = np.arange(model.V.shape[0])
    t, q, v, f, _ = record(model, settings, dt=dt, m=m, transient=transient,
                           channels=(one, one, none if mt.group(3) == "bearing_force"
                                     else meshes))
    qd, vd = (q[:, d], v[:, d]) if whole else (q[:, 0], v[:, 0])
    if mt.group(3) == "bearing_force":
        return model.kb[d] * qd + model.cb[d] * vd
    if model.profile is None and model.load is None:
        return (model.fext[d] - model.kb[d] * qd - model.cb[d] * vd - (f @ model.V)[:, d]
                ) / model.mass[d]
    _, _, taudd, lam = model.nominal(t)  # a profile: eq. 6a, as linear_records
    return (lam * model.fext[d] + nominal_acceleration_load(model)[d] * taudd
            - model.kb[d] * qd - model.cb[d] * vd - (f @ model.V)[:, d]) / model.mass[d]


def record(model: DynamicModel, settings: DynamicsSettings, *, dt: float, m: int,
           transient: float, channels: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None
           ) -> tuple[np.ndarray, ...]:
    """Run the kernel past the transient and record q, v, f at fs (FIR-decimated).

    The kernel keeps every ``m``-th step (the internal rate ``oversample fs``), from
    ``FIR_HALF_PER_R oversample`` samples before the end of the transient on, and the
    records are decimated to ``fs`` by a Kaiser FIR low-pass (:func:`anti_alias_taps`,
    ``_kernels.fir_decimate``); the first
    output sample is centred on the end of the transient.

    Parameters
    ----------
    model : DynamicModel
        The equations of motion.
    settings : DynamicsSettings
        ``fs``, ``oversample`` and ``duration``.
    dt : float
        Step [s], ``1 / (oversample fs m)``.
    m : int
        Steps per internal sample.
    transient : float
        Time to skip [s] (rounded up to whole internal samples, at least the filter's
        half length).
    channels : tuple of three int arrays, optional
        Columns of q, q' and f to decimate and return (default: all). The filter acts
        on each channel alone, so a column is the same whichever others are kept.
        Without oversampling nothing is filtered and the records are returned whole.

    Returns
    -------
    t, q, v, f : ndarray
        Times [s] and the records, shapes (n,), (n, n_dof) twice, (n, n_mesh) (with
        oversampling and ``channels``, the columns it names).
    transient : float
        The transient used [s].
    """
    g = _Grid.of(settings, m, transient)
    r = settings.oversample
    # with oversampling, the kernel records only the channels to decimate
    raw = run_kernel(model, dt=dt, n_steps=g.n_steps, rec_start=g.rec_start, rec_every=m,
                     n_rec=g.n_rec, channels=channels if r > 1 else None)
    n, nv = raw.q.shape[1], raw.v.shape[1]
    _warn_folding(raw.f, settings)
    if r > 1:
        y = _kernels.fir_decimate(anti_alias_taps(r, settings.fs), raw.channels, r, g.first,
                                  g.n_out).T
        q, v, f = y[:, :n], y[:, n:n + nv], y[:, n + nv:]
    else:
        # unfiltered: the records themselves, one row per sample (C order)
        q, v, f = (np.ascontiguousarray(a) for a in (raw.q, raw.v, raw.f))
    return g.t, q, v, f, g.transient


@functools.lru_cache(maxsize=4)
def _hann(n: int) -> np.ndarray:
    """``numpy.hanning(n)``, made once per length (0.3 ms for 2^15 points)."""
    w = np.hanning(n)
    w.flags.writeable = False
    return w


def _warn_folding(f: np.ndarray, settings: DynamicsSettings) -> None:
    """Warn (:class:`ModelRangeWarning`) when a mesh force's internal record (rate r fs)
    holds a line in its top quarter below r fs / 2 larger than :data:`ALIAS_SHARE` of
    its largest line in the output band: content above r fs / 2 then has likely folded
    into the record before the filter (Hann-windowed amplitude spectra, mean removed, of
    the last :data:`FOLD_BLOCK` internal samples: the run's fastest part of a run-up, at
    a cost bounded whatever the duration)."""
    fs, r = settings.fs, settings.oversample
    if r == 1 or f.shape[1] == 0 or f.shape[0] <= 8:  # nothing filtered, or nothing to read
        return
    x = np.array(f[-FOLD_BLOCK:], order="F")
    mean = x.mean(axis=0)
    x -= mean
    n = x.shape[0]
    a = np.abs(np.fft.rfft(x * _hann(n)[:, None], axis=0))
    freq = np.fft.rfftfreq(n, 1.0 / (r * fs))  # increasing: the bands as slices
    band = a[1:np.searchsorted(freq, 0.45 * fs, side="right")].max(axis=0)
    top = a[np.searchsorted(freq, 0.375 * r * fs):].max(axis=0)
    top[top * 2.0 / x.shape[0] <= FOLD_FLOOR * np.abs(mean)] = 0.0  # round-off, not content
    share = np.max(top / np.where(band > 0, band, np.inf))
    if share > ALIAS_SHARE:
        warn_model_range(f"anti-aliasing of the record: a mesh force holds {share:.3g} times "
                         f"its largest line near the internal Nyquist frequency {r * fs / 2:g} "
                         f"Hz (dynamics.oversample = {r} x fs = {fs:g} Hz): content above it "
                         "has likely folded into the record; raise dynamics.oversample until "
                         "the spectrum stops changing (docs/dynamics.md 5)")


@dataclass(frozen=True)
class _Grid:
    """The samples of a run: kernel steps, internal records, output times.

    The kernel keeps every ``m``-th step (the internal rate ``oversample fs``) from
    ``half = FIR_HALF_PER_R oversample`` internal samples before the end of the
    transient on (none without oversampling); the records, one channel per row, are
    filtered along their contiguous rows: full-convolution index j = kk r holds the
    output centred on j - half, so the first output sample, centred on the end of the
    transient (internal index half), is kk = ``first`` = 2 half / r (j - i >= 0 for
    every tap, and the last j = (n_out - 1) r + 2 half = n_rec - 1).
    """

    transient: float
    n_out: int
    n_rec: int
    rec_start: int
    n_steps: int
    first: int
    t: np.ndarray

    @staticmethod
    def of(settings: DynamicsSettings, m: int, transient: float) -> _Grid:
        r = settings.oversample
        fs = settings.fs
        t_int = 1.0 / (r * fs)
        half = FIR_HALF_PER_R * r if r > 1 else 0
        tr_samples = max(math.ceil(transient / t_int - 1e-9), half)
        transient = tr_samples * t_int
        n_out = int(round(settings.duration * fs))
        n_rec = (n_out - 1) * r + 1 + 2 * half
        rec_start = (tr_samples - half) * m
        return _Grid(transient=transient, n_out=n_out, n_rec=n_rec, rec_start=rec_start,
                     n_steps=rec_start + (n_rec - 1) * m, first=2 * half // r,
                     t=transient + np.arange(n_out) / fs)


@dataclass(frozen=True)
class LinearRecords:
    """Records of a run as linear maps of the kernel's channels (q, q', f).

    Built by :func:`linear_records`; run by ``_kernels.decimate_linear``: the kernel
    records ``channels``; ``pre`` forms the signals to filter from them at the internal
    rate; the filtered, decimated signals (and the rows at the output times named in
    ``extra``) are combined by ``post`` into one record per name.

    Parameters
    ----------
    names : tuple of str
        Each record's name, in the form of :meth:`gearsim.model.Gearbox.signal_key`
        (``mesh_force_1``, ``bearing_force[input,x]``, ``shaft_angle[input]``, ...).
    channels : tuple of three int arrays
        Columns of q, of q' and of f the kernel records, in this order, one row each.
    pre : tuple of three arrays
        (ptr, col, w): signal m = sum_k w[k] (recorded row col[k]), k = ptr[m] ..
        ptr[m + 1] - 1.
    extra : tuple of str
        Rows at the output times after the filtered signals, from
        :meth:`DynamicModel.nominal`: ``"tau"`` (the nominal time), and under a profile
        ``"lam"`` (the load factor) and ``"taudd"`` (tau'') for the accelerations.
    post : tuple of five arrays
        (ptr, col, w, b, d): record j = (b[j] + sum_k w[k] y[col[k]]) / d[j], y the
        filtered signals then the ``extra`` rows.
    """

    names: tuple[str, ...]
    channels: tuple[np.ndarray, np.ndarray, np.ndarray]
    pre: tuple[np.ndarray, np.ndarray, np.ndarray]
    extra: tuple[str, ...]
    post: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]


def _compressed(rows: list[list[tuple[int, float]]]) -> tuple[np.ndarray, ...]:
    """(ptr, col, w) of rows of (column, weight) terms."""
    ptr = np.zeros(len(rows) + 1, dtype=np.int64)
    ptr[1:] = np.cumsum([len(r) for r in rows])
    col = np.array([c for r in rows for c, _ in r], dtype=np.int64)
    w = np.array([wk for r in rows for _, wk in r], dtype=float)
    return ptr, col, w


def nominal_acceleration_load(model: DynamicModel) -> np.ndarray:
    """c_j = g_j + m_j w_j: the load per unit tau'' of the absolute acceleration record.

    Under a speed profile each coordinate is a deviation q_j from the nominal motion
    w_j tau(t) (:func:`gearsim.dynamics.model.nominal_inertia`), so m_j q_j'' =
    lambda(t) F_j + g_j tau'' - k_b q_j - c_b q_j' - sum_i V_ij f_i. The recorded
    acceleration is that of the coordinate itself, w_j tau'' + q_j'' (the second
    derivative of ``shaft_angle`` for a shaft's rotation; w_j = 0 for a translation):

        a_j = (lambda(t) F_j + (g_j + m_j w_j) tau''(t) - k_b q_j - c_b q_j'
               - sum_i V_ij f_i) / m_j                                           (6a)

    (docs/dynamics.md section 6). With g = -M w but at the input, c_j = 0 on every
    coordinate but the input's, which carries the drive's torque sum_k m_k w_k^2 / w_in.

    Parameters
    ----------
    model : DynamicModel
        The equations of motion (``inertial`` g and ``info["nominal_velocity"]`` w when
        it has a speed profile).

    Returns
    -------
    ndarray, shape (n_dof,)
        c [N s or N m s per unit tau'']; zeros without a speed profile.
    """
    c = np.zeros(model.n_dof)
    if model.inertial is not None:
        c += model.inertial
        w = model.info.get("nominal_velocity")
        if w is not None:
            c += model.mass * np.asarray(w, dtype=float)
    return c


def linear_records(model: DynamicModel, train: GearTrain) -> LinearRecords:
    """The records of :func:`simulate` as linear maps of the kernel's channels.

    Every record of the result but the STE and the tacho is linear in q, q' and the
    mesh forces f (and, for the shaft angles, the nominal time tau), and the
    anti-aliasing decimation is linear, so a combination may be formed before or after
    the filter: the same record to round-off. Before, at the internal rate, each
    combination that is filtered as one signal saves the filter's products of its
    channels; after, at the output rate, a record is combined from few filtered signals.
    The signals filtered are

    * ``f_i``, each mesh (and shaft-spring) row;
    * ``(V q)_i``, the deflection of each mesh of the train (for ``dte_i``);
    * ``k_b q_j + c_b q'_j``, the bearing force of each bearing coordinate j (and of
      any other coordinate with a bearing stiffness or damping);
    * ``q_j`` of each shaft's own rotation (for its angle);

    and the records, from them: ``mesh_force_i = 0 + c_i f_i``; ``dte_i = e_i + (V
    q)_i``; ``shaft_torque[s] = 0 + f_s``; ``bearing_force[shaft,axis] = 0 + (k_b q +
    c_b q')_d``; ``acceleration[shaft,axis]`` and ``angular_acceleration[rotation]``
    ``= (F_j - (k_b q + c_b q')_j - sum_i V_ij f_i) / m_j``; ``shaft_angle[shaft] = 0 +
    Omega tau + q_j`` (docs/dynamics.md section 6). The kernel records only the
    channels these use (for the Table-1 train, 23 of 26: no rotation speeds; 16 signals
    are filtered).

    Parameters
    ----------
    model : DynamicModel
        The equations of motion.
    train : GearTrain
        Its train (pairs, shafts and their speeds).

    Returns
    -------
    LinearRecords
        Records named ``mesh_force_i``, ``dte_i``, ``shaft_torque[spring]``,
        ``bearing_force[shaft,axis]``, ``acceleration[shaft,axis]``,
        ``angular_acceleration[rotation]``, ``shaft_angle[shaft]``, in this order (the
        bearing records shaft by shaft, axes in ``model.axes`` order).
    """
    shafts = [sh.name for sh in train.flow.shafts]
    V = model.V.tolist()  # Python numbers: the map has tens of terms, no array work
    kb, cb = model.kb.tolist(), model.cb.tolist()
    labels = model.dof_labels
    sig: dict[tuple, int] = {}  # a signal's terms ((kind, column), weight) -> its index

    def signal(*terms: tuple[tuple[str, int], float]) -> int:
        # terms of weight 0 dropped (a bearing force without damping: x + 0 y = x)
        return sig.setdefault(tuple(t for t in terms if t[1] != 0.0), len(sig))

    def bearing(j: int) -> int:
        return signal((("q", j), kb[j]), (("v", j), cb[j]))

    bd = model.bearing_dofs.tolist()
    axes = model.axes
    each = [(shafts[g], axes[a], j) for g, row in enumerate(bd) for a, j in enumerate(row)]
    rot = [j for j, lab in enumerate(labels) if lab.endswith(".theta") and model.kind != "seed"]
    with_bearing = {j for _, _, j in each} | {j for j in range(model.n_dof) if kb[j] or cb[j]}

    profiled = model.profile is not None or model.load is not None
    nominal_load = nominal_acceleration_load(model)

    def acceleration(j: int) -> tuple[float, list, float]:
        terms = [(bearing(j), -1.0)] if j in with_bearing else []
        terms += [(signal((("f", i), 1.0)), -row[j]) for i, row in enumerate(V) if row[j]]
        if not profiled:
            return float(model.fext[j]), terms, float(model.mass[j])
        # a speed or load profile: lambda(t) F_j and the nominal motion's (g_j + m_j w_j)
        # tau''(t), rows at the output times (the absolute acceleration, eq. 6a)
        return 0.0, [("lam", float(model.fext[j])), ("taudd", float(nominal_load[j])),
                     *terms], float(model.mass[j])

    rows: list[tuple[str, tuple[float, list, float]]] = []  # name, (b, terms, d)
    n_pair = len(train.pairs)
    rows += [(f"mesh_force_{i + 1}", (0.0, [(signal((("f", i), 1.0)),
                                             float(model.to_transverse[i]))], 1.0))
             for i in range(n_pair)]
    rows += [(f"dte_{i + 1}", (float(model.dte_offset[i]), [
        (signal(*((("q", j), w) for j, w in enumerate(V[i]) if w)), 1.0)], 1.0))
             for i in range(n_pair)]
    rows += [(f"shaft_torque[{s}]", (0.0, [(signal((("f", int(i)), 1.0)), 1.0)], 1.0))
             for s, i in zip(model.info.get("shaft_springs", ()),
                             model.info.get("shaft_rows", ()), strict=True)]
    rows += [(f"bearing_force[{sh},{a}]", (0.0, [(bearing(j), 1.0)], 1.0))
             for sh, a, j in each]
    rows += [(f"acceleration[{sh},{a}]", acceleration(j)) for sh, a, j in each]
    rows += [(f"angular_acceleration[{labels[j][:-6]}]", acceleration(j)) for j in rot]
    for sh in train.flow.shafts:
        terms = [("tau", train.speed(train.gear_index(sh.gears[0])))]
        own = [lab for lab in (f"{sh.name}.theta", f"{sh.gears[0]}.theta")
               if lab in labels and model.kind != "seed"]
        if own:
            terms.append((signal((("q", labels.index(own[0])), 1.0)), 1.0))
        rows.append((f"shaft_angle[{sh.name}]", (0.0, terms, 1.0)))
    pre_rows = list(sig)  # in the order of their indices
    cols = {k: sorted({j for r in pre_rows for (kk, j), _ in r if kk == k}) for k in "qvf"}
    at = {("q", j): i for i, j in enumerate(cols["q"])}
    at |= {("v", j): len(cols["q"]) + i for i, j in enumerate(cols["v"])}
    at |= {("f", j): len(cols["q"]) + len(cols["v"]) + i for i, j in enumerate(cols["f"])}
    extra = ("tau", "lam", "taudd") if profiled else ("tau",)
    post = _compressed([[(len(sig) + extra.index(c) if isinstance(c, str) else c, w)
                         for c, w in terms if w != 0.0] for _, (_, terms, _) in rows])
    return LinearRecords(
        names=tuple(name for name, _ in rows),
        channels=tuple(np.array(cols[k], dtype=np.int64) for k in "qvf"),
        pre=_compressed([[(at[c], w) for c, w in r] for r in pre_rows]), extra=extra,
        post=(*post, np.array([b for _, (b, _, _) in rows], dtype=float),
              np.array([d for _, (_, _, d) in rows], dtype=float)))


def _run_linear(model: DynamicModel, settings: DynamicsSettings, lin: LinearRecords, *,
                dt: float, m: int, transient: float) -> tuple[np.ndarray, np.ndarray, float]:
    """Run the kernel past the transient and form the records ``lin`` at fs.

    The grid of :func:`record`; the kernel records ``lin.channels`` and
    ``_kernels.decimate_linear`` forms, filters (the Kaiser FIR of
    :func:`anti_alias_taps`; without oversampling the single tap 1) and combines them.
    Returns the output times [s], the records (one per row, ``lin.names``) and the
    transient used [s].
    """
    g = _Grid.of(settings, m, transient)
    r = settings.oversample
    raw = run_kernel(model, dt=dt, n_steps=g.n_steps, rec_start=g.rec_start, rec_every=m,
                     n_rec=g.n_rec, channels=lin.channels)
    _warn_folding(raw.f, settings)
    taps = anti_alias_taps(r, settings.fs) if r > 1 else np.ones(1)
    if lin.extra:
        tau, _, taudd, lam = model.nominal(g.t)
        rows = {"tau": tau, "lam": lam, "taudd": taudd}
        extra = np.stack([rows[e] for e in lin.extra])
    else:
        extra = np.empty((0, g.n_out))
    z = np.empty((lin.post[3].size, g.n_out))
    _kernels.decimate_linear(taps, raw.channels, r, g.first, g.n_out, *lin.pre, extra,
                             *lin.post, z)
    return g.t, z, g.transient


#: The simulated tacho: a pulse of TACHO_VOLTS while a shaft's angle is within
#: TACHO_WIDTH rad after each whole revolution (a TTL-level once-per-revolution pulse).
TACHO_VOLTS = 5.0
TACHO_WIDTH = 0.2 * math.pi


def tacho_variable(angles: np.ndarray) -> tuple:
    """The simulated tacho of shafts at ``angles`` [rad], as an xarray variable.

    Parameters
    ----------
    angles : ndarray, shape (n_time, n_shaft)
        Each shaft's angle in its own sense of rotation [rad].

    Returns
    -------
    tuple
        ``(("time", "shaft"), pulses [V], attrs)``: :data:`TACHO_VOLTS` while the angle is
        within :data:`TACHO_WIDTH` after a whole revolution, else 0 (one pulse per rev).

    Notes
    -----
    The pulse is on where ``numpy.mod(angle, 2 pi) < TACHO_WIDTH``. That remainder costs
    10 ns an angle; the angle less its whole turns by floor, ``a - floor(a / 2pi) 2pi``, a
    tenth of it, and is within (|a| + 3 (2 pi)) 2^-53 of the remainder (one rounding of
    the quotient, product, difference; the remainder of a negative angle is rounded
    once) unless the floor is one turn off, which happens only where the remainder is
    within |a| 2^-53 of 0 or 2 pi. So an angle whose cheap remainder lies more than
    tol = (|a| + 2 (2 pi)) 2^-50 inside [0, width) or [width, 2 pi) has the pulse that
    decides; the others (near an edge, non-finite, beyond 2^50 turns: none or a few per
    record) take the remainder itself, ``numpy.mod``'s (compiled:
    ``_kernels.tacho_pulses``, one pass, 0.1 ms for a simulated second of three shafts
    instead of 0.6 ms in numpy). The pulses are those of ``numpy.mod``, bit for bit
    (tested on edge values).
    """
    a = np.asarray(angles, dtype=float)
    if not (a.flags.c_contiguous or a.flags.f_contiguous):
        a = np.ascontiguousarray(a)
    pulses = np.empty_like(a)  # the layout of a: both in memory order, one pass
    _kernels.tacho_pulses(a.ravel(order="K"), TACHO_WIDTH, TACHO_VOLTS,
                          pulses.ravel(order="K"))
    return (("time", "shaft"), pulses,
            {"units": "V", "long_name": "once-per-revolution tacho pulse of each shaft",
             "pulses_per_rev": 1})


def _dataset(train, settings, model: DynamicModel, lin: LinearRecords, t, z, *, dt,
             transient):
    import xarray as xr

    # the records of linear_records, one per row of z: the variables are views of its
    # rows (the bearing and acceleration rows shaft by shaft, axes in order)
    at = {name: j for j, name in enumerate(lin.names)}

    def rows(names: list[str], shape: tuple[int, ...] | None = None) -> np.ndarray:
        shape = (len(names),) if shape is None else shape
        if not names:
            return np.zeros((t.size, *shape))
        j0 = at[names[0]]
        assert [at[n] for n in names] == list(range(j0, j0 + len(names)))
        return z[j0:j0 + len(names)].T.reshape(t.size, *shape)

    ste = model.ste(t)
    data = {}
    for i in range(len(train.pairs)):
        name = i + 1
        pair = train.pairs[i]
        data[f"mesh_force_{name}"] = (
            "time", z[at[f"mesh_force_{name}"]],
            {"units": "N", "long_name": f"dynamic mesh force, mesh {pair.name} "
             f"({pair.driver.name} -> {pair.driven.name}), along the transverse line of "
             "action (normal force = this / cos(beta_b))",
             "static_force": float(model.static_force[i])})
        data[f"dte_{name}"] = ("time", z[at[f"dte_{name}"]], {
            "units": "m", "long_name": f"dynamic transmission error, mesh {pair.name}, "
            "relative displacement along the transverse line of action"})
        data[f"ste_{name}"] = ("time", ste[:, i], {
            "units": "m", "long_name": f"static transmission error input, mesh {pair.name}"})
    springs = model.info.get("shaft_rows", ())
    if springs:
        data["shaft_torque"] = (("time", "spring"), rows(
            [f"shaft_torque[{s}]" for s in model.info["shaft_springs"]]), {
            "units": "N m", "long_name": "torque in each shaft spring between two gears"})
    shafts = [sh.name for sh in train.flow.shafts]
    bd = model.bearing_dofs
    each = [f"[{sh},{a}]" for sh in shafts[:bd.shape[0]] for a in model.axes]
    data["bearing_force"] = (("time", "shaft", "axis"),
                             rows([f"bearing_force{k}" for k in each], bd.shape),
                             {"units": "N", "long_name": "force of each shaft on its bearings"})
    data["acceleration"] = (("time", "shaft", "axis"),
                            rows([f"acceleration{k}" for k in each], bd.shape),
                            {"units": "m/s^2", "long_name": "acceleration of the shaft centre"})
    rot = [j for j, lab in enumerate(model.dof_labels)
           if lab.endswith(".theta") and model.kind != "seed"]
    if rot:
        data["angular_acceleration"] = (("time", "rotation"), rows(
            [f"angular_acceleration[{model.dof_labels[j][:-6]}]" for j in rot]), {
            "units": "rad/s^2", "long_name": "angular acceleration (own sense of rotation)"})
    angles = rows([f"shaft_angle[{sh}]" for sh in shafts])
    data["shaft_angle"] = (("time", "shaft"), angles, {
        "units": "rad", "long_name": "angle of each shaft in its own sense of rotation"})
    data["tacho"] = tacho_variable(angles)
    md = modes(model)
    attrs = {
        "title": f"gearsim train dynamics: {train.name}",
        "model": model.kind,
        "fs": float(settings.fs),
        "step": float(dt),
        "transient": float(transient),
        "mesh_frequency": float(model.mesh_frequency),
        "mesh_frequencies": [float(x) for x in train.mesh_frequencies],
        "shaft_frequency": [float(train.shaft_frequency(j)) for j in range(len(train.gears))],
        # what the analysis of a record needs (f_m = f_r1 Z_1, shaft j at f_m / Z_j): every
        # gear of a chain; of a graph, the input mesh's two gears (its first stage)
        "analysis_teeth": [int(g.teeth) for g in (train.gears if train.is_chain else
                                                  (train.pairs[0].driver,
                                                   train.pairs[0].driven))],
        # a compound train: every stage's (driving, driven) teeth, "32/80,48/64", so
        # that a results file is analysed with its stages without its configuration
        **({"analysis_stages": ",".join(f"{d}/{n}" for d, n in stages)}
           if (stages := train.compound_stages()) is not None else {}),
        # the meshes' [N]; the shaft springs' torques [N m] are static_shaft_torque
        "static_force": [float(x) for x in model.static_force[:len(train.pairs)]],
        **({"static_shaft_torque": [float(model.static_force[r]) for r in springs]}
           if springs else {}),
        "natural_frequencies": [float(x) for x in md.frequencies],
        "cracks": "; ".join(f"{c.gear} tooth {c.tooth} {c.flank} depth {c.depth:g} m angle "
                            f"{math.degrees(c.angle):g} deg" for c in train.cracks) or "none",
        "config": train_to_toml(train, settings.to_dict()),
        "gearsim_version": __version__, "dynamics": json.dumps(settings.to_dict()),
        "anti_aliasing": (f"FIR Kaiser({FIR_BETA}) {2 * FIR_HALF_PER_R * settings.oversample + 1}"
                          f" taps, cut-off {FIR_CUTOFF} fs, from {settings.oversample} fs"
                          if settings.oversample > 1 else "none (instantaneous samples)"),
    }
    coords = {"time": ("time", t, {"units": "s"}),
              "axis": ("axis", list(model.axes)),
              "rotation": ("rotation", [model.dof_labels[j][:-6] for j in rot]),
              "shaft": ("shaft", [sh.name for sh in train.flow.shafts])}
    if springs:
        coords["spring"] = ("spring", list(model.info["shaft_springs"]))
    return xr.Dataset(data, coords=coords, attrs=attrs)


def summary(ds) -> dict:
    """Per-mesh mean, RMS, peak of the dynamic mesh force and the static force [N].

    Parameters
    ----------
    ds : xarray.Dataset
        Result of :func:`simulate` (or a results file read back).

    Returns
    -------
    dict
        ``model``, ``fs`` [Hz], ``step`` [s], ``duration`` (samples / fs) [s], ``cracks``
        and ``meshes``: per mesh ``mesh`` (1-based), ``mean``, ``rms`` (the RMS about the
        mean, the standard deviation: the fluctuation, as for every kind of gearbox,
        :func:`gearsim.dynamics.stage.stage_summary`), ``peak`` (max abs),
        ``static_force`` [N] (at the operating load), ``load_factor`` (the load profile's
        lambda(t) averaged over the record, 1 without one: the mean force it loads) and
        ``mean_error`` = (mean - lambda static) / (lambda static) [-] (left out when
        lambda static is 0: a load profile of zeros).
    """
    meshes = []
    i = 1
    run = json.loads(ds.attrs.get("dynamics", "{}"))
    lam = (1.0 if run.get("load_times") is None else float(np.mean(np.interp(
        ds["time"].values, run["load_times"], run["load_values"]))))
    while f"mesh_force_{i}" in ds:
        x = np.asarray(ds[f"mesh_force_{i}"].values)
        fs_ = float(ds[f"mesh_force_{i}"].attrs["static_force"])
        mean = float(np.mean(x))
        meshes.append({
            "mesh": i, "mean": mean, "rms": float(np.std(x)),  # about the mean
            "peak": float(np.max(np.abs(x))),
            "static_force": fs_, "load_factor": lam,
            # no load over the record (a profile of zeros): no relative error
            **({"mean_error": (mean - lam * fs_) / (lam * fs_)} if lam * fs_ != 0 else {}),
        })
        i += 1
    return {"model": ds.attrs["model"], "fs": ds.attrs["fs"], "step": ds.attrs["step"],
            "duration": float(ds.sizes["time"] / ds.attrs["fs"]),
            "cracks": ds.attrs["cracks"], "meshes": meshes}


def reference_mesh_forces(model: DynamicModel, t: float, q: np.ndarray,
                          v: np.ndarray) -> np.ndarray:
    """Mesh forces f_i [N] of the equations in plain numpy (see :func:`reference_rhs`).

    The force law of :mod:`gearsim.dynamics.model` (backlash function, contact force
    clipped at zero on either flank, linear when the clearance is ``inf``).

    Parameters
    ----------
    model : DynamicModel
        Equations of motion.
    t : float
        Time [s].
    q, v : ndarray, shape (n_dof,)
        Coordinates [m, rad] and velocities [m/s, rad/s].

    Returns
    -------
    ndarray, shape (n_mesh,)
        f_i including the factor kappa_i [N].
    """
    tau, taud, _, _ = model.nominal(t)
    arg = model.h_omega * tau + model.h_phase
    e = model.e0 + np.sum(model.h_amp * np.sin(arg), axis=1)
    ed = np.sum(model.h_amp * model.h_omega * np.cos(arg), axis=1) * taud
    if any(tab.has_contacts or tab.dk_da is not None for tab in model.tables):
        return _reference_contact_forces(model, tau, q, v, e, ed)
    fr = model.mesh_frequencies
    k = np.array([model.kscale[i] * float(tab(fr[i] * tau + model.phase[i]))
                  for i, tab in enumerate(model.tables)])
    x = model.V @ q - e
    xd = model.V @ v - ed
    b2 = model.clearance
    linear = k * x + model.cm * xd
    work = np.maximum(linear, 0.0)
    back = np.minimum(k * (x + b2) + model.cm * xd, 0.0)
    f = np.where(x > 0, work, np.where(x <= -b2, back, 0.0))
    return model.kappa * np.where(np.isinf(b2), linear, f)


def _reference_contact_forces(model: DynamicModel, t: float, q: np.ndarray, v: np.ndarray,
                              e: np.ndarray, ed: np.ndarray) -> np.ndarray:
    """Mesh forces with meshes of contacts (``t``: the nominal time), written from the
    force law of docs/contacts.md: F = sum_j k_j max(0, x - s_j) over every contact of the two
    samples around c (zero-separation contacts included), interpolated linearly."""
    x_all = model.V @ q - e
    xd_all = model.V @ v - ed
    out = np.zeros(len(model.tables))
    da = (np.zeros(len(model.tables)) if model.a_amp is None else np.sum(
        model.a_amp * np.sin(model.a_omega * t + model.a_phase), axis=1))
    for i, tab in enumerate(model.tables):
        ks = model.kscale[i]
        x, xd, b2, cm = x_all[i], xd_all[i], model.clearance[i], model.cm[i]
        c = model.mesh_frequencies[i] * t + model.phase[i]
        pos = np.mod(c, tab.period) * tab.positions_per_cycle
        i0 = int(np.floor(pos)) % tab.k.size
        w = pos - np.floor(pos)
        i1 = (i0 + 1) % tab.k.size
        dk = 0.0 if tab.dk_da is None else da[i] * (tab.dk_da[i0] * (1 - w)
                                                   + tab.dk_da[i1] * w)
        ka = ks * (tab.k[i0] * (1 - w) + tab.k[i1] * w + dk)
        if not tab.has_contacts:
            lin = ka * x + cm * xd
            f = lin if np.isinf(b2) else (max(lin, 0.0) if x > 0 else (
                min(ka * (x + b2) + cm * xd, 0.0) if x <= -b2 else 0.0))
            out[i] = model.kappa[i] * f
            continue
        force = closed = 0.0
        for row, wt in ((i0, 1 - w), (i1, w)):
            dkr = 0.0 if tab.dk_da is None else da[i] * tab.dk_da[row]
            kk = np.concatenate([[tab.k_zero[row] + dkr],
                                 tab.kx[tab.ptr[row]:tab.ptr[row + 1]]])
            ss = np.concatenate([[0.0], tab.sx[tab.ptr[row]:tab.ptr[row + 1]]])
            gap = x - ss
            bil = np.isinf(b2) & (ss == 0.0)  # linear mesh: zero-separation part bilateral
            force += wt * ks * np.sum(np.where(bil | (gap > 0), kk * gap, 0.0))
            closed += wt * ks * np.sum(np.where(bil | (gap > 0), kk, 0.0))
        damp = cm * xd * closed / ka if ka > 0 else 0.0
        if np.isinf(b2):
            f = force + damp
        elif closed > 0:
            f = max(force + damp, 0.0)
        elif x <= -b2:
            f = min(ka * (x + b2) + cm * xd, 0.0)
        else:
            f = 0.0
        out[i] = model.kappa[i] * f
    return out


def reference_rhs(model: DynamicModel):
    """The same equations as the kernel in plain numpy, ``fun(t, y)`` for solve_ivp.

    ``y = [q, q']``. Independent of the numba code (vectorised numpy, the table's own
    interpolation :meth:`MeshTable.__call__`), for cross-checks and benchmarks.

    Parameters
    ----------
    model : DynamicModel
        Equations of motion.

    Returns
    -------
    callable
        ``fun(t, y) -> [q', q'']`` with ``q'' = M^-1 (lambda F_ext + g tau'' - K_b q -
        C_b q' - V^T f)`` (speed and load profiles: :meth:`DynamicModel.nominal`).
    """
    n = model.n_dof
    minv = 1.0 / model.mass

    def fun(t: float, y: np.ndarray) -> np.ndarray:
        q, v = y[:n], y[n:]
        f = reference_mesh_forces(model, t, q, v)
        _, _, taudd, lam = model.nominal(t)
        g = 0.0 if model.inertial is None else model.inertial * taudd
        a = minv * (lam * model.fext + g - model.kb * q - model.cb * v - model.V.T @ f)
        return np.concatenate([v, a])

    return fun
