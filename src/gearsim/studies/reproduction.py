"""Options and result objects of the seed reproduction (:mod:`gearsim.studies.reproduce`)."""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from gearsim._version import __version__
from gearsim.dynamics.settings import MODELS
from gearsim.errors import require
from gearsim.signals.analysis import Analysis
from gearsim.studies.claims import SEED
from gearsim.system import GearTrain
from gearsim.viz.reproduce import plot_all

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure

__all__ = ["DEFAULT_DEPTHS", "CaseRun", "ReproduceOptions", "Reproduction"]

#: Crack depths of the sensitivity study [m] (the tooth model refuses depths past
#: 9.278 mm at 45 deg on the Table-1 input gear).
DEFAULT_DEPTHS = (1e-3, 2e-3, 4e-3, 6e-3, 8e-3, 9e-3)


@dataclass(frozen=True)
class ReproduceOptions:
    """Options of :func:`run_reproduction` (SI units).

    Parameters
    ----------
    config
        Gear train: a TOML path or built-in example name (default the seed's Table 1).
    depth
        Reference crack depth [m] of the figures and the claims table.
    depths
        Crack depths of the sensitivity study [m].
    revolutions
        Recorded duration in revolutions of the input gear (a whole number, so that the
        mesh harmonics and the sidebands fall on spectral bins).
    fe
        Also run the FE-stiffness route and the FE check of the tooth (Figure 3).
    fe_points
        Contact positions of the FE check.
    model
        Dynamic model, ``"lta"`` or ``"seed"`` (see :mod:`gearsim.dynamics`).
    fault_severities
        Severities of the fault-magnitude section (every class of
        :data:`gearsim.model.variants.FAULT_CLASSES` at each; empty: no such section).
    """

    config: str = "idler-table1"
    depth: float = 6e-3
    depths: tuple[float, ...] = DEFAULT_DEPTHS
    revolutions: int = 32
    fe: bool = True
    fe_points: int = 11
    model: str = "lta"
    fault_severities: tuple[float, ...] = (0.25, 0.5, 1.0)

    def __post_init__(self) -> None:
        require(math.isfinite(self.depth) and self.depth > 0, "depth", self.depth,
                "must be > 0 m")
        require(len(self.depths) >= 1, "depths", self.depths, "must hold at least one depth")
        for d in self.depths:
            require(math.isfinite(d) and d > 0, "depths", d, "every depth must be > 0 m")
        require(isinstance(self.revolutions, int) and self.revolutions >= 4, "revolutions",
                self.revolutions, "must be a whole number >= 4 (impacts need repeats)")
        require(self.fe_points >= 3, "fe_points", self.fe_points, "must be >= 3")
        require(self.model in MODELS, "model", self.model,
                "must be one of " + ", ".join(f'"{m}"' for m in MODELS))
        for v in self.fault_severities:
            require(math.isfinite(v) and 0 < v <= 1, "fault_severities", v,
                    "every severity must be in (0, 1]")


@dataclass
class CaseRun:
    """One simulated and analysed case.

    Parameters
    ----------
    route : str
        ``"PE"`` or ``"FE"`` (tooth-compliance model).
    label : str
        Case label (``"healthy"``, ``"working"``, ...).
    train : GearTrain
        The simulated train variant.
    force : ndarray
        Dynamic load of mesh I [N].
    force2 : ndarray
        Dynamic load of mesh II [N].
    fs : float
        Sampling rate [Hz].
    analysis : Analysis
        :func:`gearsim.signals.analysis` of ``force``.
    """

    route: str
    label: str
    train: GearTrain
    force: np.ndarray
    force2: np.ndarray
    fs: float
    analysis: Analysis


@dataclass
class Reproduction:
    """Everything the report shows: the result of :func:`compute_reproduction`.

    Parameters
    ----------
    options : ReproduceOptions
        The options of the run.
    train : GearTrain
        The base train (from ``options.config``).
    t1 : float
        Input shaft period [s].
    f_m : float
        Mesh frequency [Hz].
    contact_ratio : float
        Total contact ratio of mesh I [-].
    runs : dict
        ``"route/label" -> CaseRun``.
    metrics : dict
        ``"route/label" -> CaseMetrics`` of each cracked case against healthy.
    stiffness : dict
        Route -> label -> ``{"theta_deg", "k"}`` mesh-I TVMS curves.
    fe_checks : dict
        Crack -> FE check of the input tooth (empty without FE).
    sensitivity : list of dict
        Rows of the crack-depth study.
    claims : list of dict
        The claims table.
    findings : dict
        Route -> qualitative findings.
    timings : dict
        Seconds per step.
    fe_pair : dict
        Crack (``"none"``, ``"working"``, ``"non-working"``) ->
        :class:`gearsim.studies.fe_pair_check.FEPairCheck`: the FE gear pair's section
        TVMS of mesh I against the PE curves (seed Figure 3; empty without FE).
    fault_magnitudes : list of dict
        Rows of the fault-magnitude section: every fault class at each severity against
        the healthy train on the same (contact) mesh model, with the seed's impact and
        RMS levels reached or not.
    seed : dict
        The seed's stated numbers (:data:`gearsim.studies.claims.SEED`), for the figures.
    """

    options: ReproduceOptions
    train: GearTrain
    t1: float
    f_m: float
    contact_ratio: float
    runs: dict[str, CaseRun]
    metrics: dict[str, Any]
    stiffness: dict[str, Any]
    fe_checks: dict[str, Any]
    sensitivity: list[dict[str, Any]]
    claims: list[dict[str, Any]]
    findings: dict[str, list[dict[str, Any]]]
    timings: dict[str, float]
    fault_magnitudes: list[dict[str, Any]] = field(default_factory=list)
    fe_pair: dict[str, Any] = field(default_factory=dict)
    seed: dict[str, float] = field(default_factory=lambda: dict(SEED))

    def plot(self) -> dict[str, Figure]:
        """The report's figures (:func:`gearsim.viz.reproduce.plot_all`).

        Returns
        -------
        dict
            Figure name -> Figure (captions in :data:`gearsim.viz.reproduce.CAPTIONS`).
        """
        return plot_all(self)

    def to_dict(self) -> dict[str, Any]:
        """The content of ``claims.json`` (JSON-ready; NaN written as null by the writer).

        Returns
        -------
        dict
        """
        c = self.train.cracks[0] if self.train.cracks else None
        return {
            "gearsim_version": __version__,
            "system": self.train.name,
            "seed": "Shi, Li & Zhou, Actuators 14 (2025) 292, doi:10.3390/act14060292",
            "crack": {"gear": c.gear if c else self.train.gears[0].name,
                      "tooth": c.tooth if c else 0,
                      "depth_m": self.options.depth,
                      "angle_deg": math.degrees(c.angle) if c else 45.0,
                      "profile": c.profile if c else "uniform"},
            "T1_s": self.t1, "mesh_frequency_hz": self.f_m,
            "total_contact_ratio": self.contact_ratio,
            "options": dataclasses.asdict(self.options),
            "claims": self.claims,
            "findings": self.findings,
            "cases": {k: m.to_dict() for k, m in self.metrics.items()},
            "fe_check": {k: v.differences() for k, v in self.fe_checks.items()},
            "fe_pair_check": {k: v.to_dict() for k, v in self.fe_pair.items()},
            "sensitivity": self.sensitivity,
            "fault_magnitudes": self.fault_magnitudes,
            "timings_s": self.timings,
        }
