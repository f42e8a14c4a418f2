"""Results to draw: small real ones where they are cheap, a synthetic study otherwise.

The reproduction of the seed's study takes a minute, so :func:`reproduction` builds a
stand-in with the attributes the figures read: real :class:`Analysis` objects of
synthetic gear signals and made-up stiffness curves and sensitivity rows.
"""

from __future__ import annotations

import dataclasses
from types import SimpleNamespace

import numpy as np
import pytest

FS = 20_000.0
F_R = 1900.0 / 60.0
TEETH = 39


def load_example(name: str):
    """A built-in example: ``(train, dynamics settings)`` (``gearsim.load`` or older)."""
    try:
        from gearsim import load
    except ImportError:  # pragma: no cover - older layout
        from gearsim.io.config import load
    model = load(name)
    train = getattr(model, "train", model)
    settings = getattr(model, "dynamics", None) or train.extra.get("dynamics")
    return train, settings


def _signal(*, impacts: bool, sideband: float, seed: int) -> np.ndarray:
    from gearsim.signals.synthetic import ImpactSpec, gear_signal

    return gear_signal(fs=FS, duration=1.0, shaft_frequency=F_R, teeth=TEETH,
                       mesh_amplitudes={1: 1000.0, 2: 500.0, 3: 200.0, 4: 100.0},
                       sidebands={(1, -1): sideband, (1, 1): sideband},
                       impacts=ImpactSpec(4000.0, 3e-4, 4000.0, 0.01) if impacts else None,
                       noise=5.0, offset=10_000.0, seed=seed)


def _analyze(x: np.ndarray):
    from gearsim.signals.analysis import analyze

    return analyze(x, FS, teeth=(TEETH, 59), shaft_frequency=F_R)


@pytest.fixture(scope="session")
def analysis():
    """Analysis of a synthetic signal with impacts once per revolution."""
    return _analyze(_signal(impacts=True, sideband=50.0, seed=2))


@pytest.fixture(scope="session")
def comparison():
    """Sideband comparison of two synthetic signals."""
    from gearsim.signals.compare import compare_sidebands

    s = _signal(impacts=False, sideband=50.0, seed=3)
    m = _signal(impacts=False, sideband=60.0, seed=4)
    return compare_sidebands(s, FS, m, FS, mesh_frequency=F_R * TEETH, shaft_frequency=F_R,
                             orders=(1, 2), n_sidebands=2)


@pytest.fixture(scope="session")
def spur():
    """The built-in 19/48 spur pair."""
    return load_example("spur-19-48")[0]


@pytest.fixture(scope="session")
def idler():
    """The built-in Table-1 idler train with its example crack."""
    return load_example("idler-table1")[0]


@pytest.fixture(scope="session")
def stage_train():
    """The Lin & Parker example stage on computed (coarse) mesh tables."""
    import dataclasses

    from gearsim.model.config import example
    from gearsim.stiffness.settings import StiffnessSettings

    tr = example("lin-parker-1999").stage
    return dataclasses.replace(tr, sun_mesh_stiffness=None, ring_mesh_stiffness=None,
                               settings=StiffnessSettings(positions_per_cycle=8, slices=2))


@pytest.fixture(scope="session")
def spur_stiffness(spur):
    """TVMS of every mesh of the spur pair."""
    from gearsim.system import train_stiffness

    return train_stiffness(spur)


@pytest.fixture(scope="session")
def gears_and_stage(spur_stiffness, stage_train):
    """The parts of a gearbox of gears driving a stage: the spur pair's TVMS, the stage."""
    return [spur_stiffness, stage_train]


@pytest.fixture(scope="session")
def loaded_contact_result(spur):
    """Loaded contact analysis of the spur pair with a broken pinion tooth."""
    from gearsim.stiffness.faults import BrokenTooth
    from gearsim.stiffness.ltca import loaded_contact

    tr = spur.with_faults((BrokenTooth(gear=spur.gears[0].name, tooth=0),))
    return loaded_contact(tr.mesh_contacts(0), tr.static_mesh_force(0))


@pytest.fixture(scope="session")
def fe_result(spur):
    """A coarse FE check of the spur pinion."""
    from gearsim.fem.check import fe_check

    return fe_check(spur, None, crack="working", closure="open", level=1, points=4)


@pytest.fixture(scope="session")
def dynamics_run():
    """A short dynamics run of the idler train."""
    from gearsim.dynamics import DynamicsSettings, simulate

    train, settings = load_example("idler-table1")
    settings = settings or DynamicsSettings()
    return simulate(train, dataclasses.replace(settings, duration=0.11, fs=10_000.0))


@pytest.fixture(scope="session")
def separability_rows():
    """Rows shaped like those of ``separability_table``."""
    rows = []
    for noise in (0.0, 0.1):
        for group in ("time", "spectrum", "all"):
            rows.append({"group": group, "noise": noise, "crack_depth_mm": None,
                         "accuracy": 0.9 - noise, "auc": 0.95 - noise})
        for depth in (1.0, 3.0):
            rows.append({"group": "all", "noise": noise, "crack_depth_mm": depth,
                         "accuracy": 0.6 + 0.1 * depth - noise, "auc": 0.9})
    # confusion matrices (true rows, predicted columns) of the pooled rows
    for r in rows:
        if r["crack_depth_mm"] is None:
            good = 6 if r["noise"] == 0.0 else 4
            bad = (6 - good) // 2
            r["confusion"] = [[good if i == j else bad for j in range(3)] for i in range(3)]
    return rows


@pytest.fixture(scope="session")
def reproduction():
    """Stand-in for ``gearsim.studies.reproduce.Reproduction`` (see the module docstring)."""
    f_m = F_R * TEETH
    t1 = 1.0 / F_R
    labels = ("healthy", "working", "non-working")
    runs, metrics = {}, {}
    for route in ("PE", "FE"):
        for i, label in enumerate(labels):
            x = _signal(impacts=label != "healthy", sideband=0.0 if label == "healthy" else 50.0,
                        seed=10 + i)
            runs[f"{route}/{label}"] = SimpleNamespace(force=x, fs=FS, analysis=_analyze(x))
            a = runs[f"{route}/{label}"].analysis
            metrics[f"{route}/{label}"] = SimpleNamespace(
                impact_times=np.asarray(a.impacts.times), impact_period=t1,
                residual=x - np.mean(x))
    theta = np.linspace(0.0, 360.0, 19 * 40, endpoint=False)
    base = 1e9 * (1.5 + 0.3 * (np.mod(theta * 19 / 360.0, 1.0) < 0.6))
    drop = np.exp(-0.5 * ((theta - 180.0) / 4.0) ** 2)
    curves = {"healthy": base, "working": base * (1 - 0.2 * drop),
              "non-working": base * (1 - 0.1 * drop), "working-open": base * (1 - 0.25 * drop)}
    stiffness = {route: {k: {"theta_deg": theta, "k": v} for k, v in curves.items()}
                 for route in ("PE", "FE")}
    roll = np.radians(np.linspace(10.0, 30.0, 4))

    def check(scale: float):
        return SimpleNamespace(roll_angle=roll, k_pe=scale * np.linspace(1.0, 2.0, 4) * 1e10,
                               k_fe=scale * np.linspace(1.1, 2.1, 4) * 1e10,
                               differences=lambda: {"max": 5.0, "min": 6.0, "mean": 5.5})

    sensitivity = [
        {"case": case, "depth_m": d * 1e-3, "tvms_max_local_drop_percent": 2.0 * d,
         "impact_percent": 100 + 20 * d, "rms_percent": 100 + 5 * d, "ser_1fm": 0.1 * d,
         "ser_2fm": None if d == 2 else 0.05 * d}
        for case in ("working", "non-working", "open") for d in (2, 4, 6)]
    seed = {"T1": 0.032, "impact_working": 2.098, "impact_non_working": 2.031,
            "far_field_working": 1.597, "rms_working": 1.324, "rms_non_working": 0.973}
    gear = SimpleNamespace(teeth=19, face_width=0.02, name="input")
    return SimpleNamespace(
        options=SimpleNamespace(depth=6e-3, revolutions=30), train=SimpleNamespace(gears=[gear]),
        t1=t1, f_m=f_m, contact_ratio=1.6, runs=runs, metrics=metrics, stiffness=stiffness,
        fe_checks={"none": check(1.0), "working": check(0.8)}, sensitivity=sensitivity,
        claims=[], findings={}, timings={}, seed=seed,
        fault_magnitudes=[{"fault": k, "severity": s, "impact_percent": 100 + 80 * s * i,
                           "rms_percent": 100 + 10 * s * i}
                          for i, k in enumerate(("working", "broken", "eccentricity"))
                          for s in (0.5, 1.0)],
        fe_pair={c: _fe_pair_check(c) for c in ("none", "working", "non-working")})


def _fe_pair_check(crack):
    """A FEPairCheck of made-up curves (the figure's data contract)."""
    from gearsim.studies.fe_pair_check import FEPairCheck

    u = np.arange(80) / 20 - 1
    k = 2.8e9 - 0.8e9 * (np.mod(u, 1.0) > 0.68) - 1e8 * (crack != "none") * (u > 0)
    return FEPairCheck(mesh="I", crack=crack, torque=4876.0, cycles=u, k_fe=k,
                       curves={"pe": 1.3 * k, "pe_line": 0.93 * k, "fe_tooth": 1.01 * k,
                               "accurate": 1.02 * k})


@pytest.fixture(scope="session")
def envelope_result():
    """Squared-envelope spectrum of impulses repeating at 37 Hz (the toolbox plots)."""
    from gearsim.signals.envelope import envelope_spectrum

    fs = 10_000.0
    t = np.arange(int(fs)) / fs
    x = np.random.default_rng(1).normal(0.0, 0.1, t.size)
    for k in range(37):
        i = int(k * fs / 37)
        n = np.arange(t.size - i)
        x[i:] += np.exp(-n / 50.0) * np.sin(2 * np.pi * 2000.0 * n / fs)
    return envelope_spectrum(x, fs, band=(1500.0, 2500.0))


@pytest.fixture(scope="session")
def kurtogram_result():
    """Fast kurtogram of the same kind of signal."""
    from gearsim.signals.kurtogram import fast_kurtogram

    fs = 10_000.0
    n = 2 ** 14
    x = np.random.default_rng(2).normal(0.0, 0.1, n)
    for i in range(0, n, 271):
        m = np.arange(n - i)
        x[i:] += np.exp(-m / 40.0) * np.sin(2 * np.pi * 2000.0 * m / fs)
    return fast_kurtogram(x, fs)
