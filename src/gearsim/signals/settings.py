"""Options of :func:`gearsim.signals.analysis` (the ``[analysis]`` config section).

Every option is checked once, here, when the settings are built; :func:`analyze` and the
configuration reader share the defaults and the limits.

Example section::

    [analysis]
    orders = [1, 2, 3, 4]      # mesh harmonics n examined
    n_sidebands = 6            # sidebands per side (SER of Hanna et al. 2011)
    window = "hann"            # or "flattop", "boxcar"
    remove_mean = true
    impact_factor = 1.5
    band_fraction = 0.9
    stft_frames_per_rev = 4
    shaft_harmonics = 2
    sideband_orders = 1
    emd_method = "correlation" # optional; absent: no EMD
    emd_threshold = 0.3        # number, or "ayenu-prah"
    emd_max_imf = -1
    pulses_per_rev = 1
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields
from typing import Any

from gearsim.errors import InputError
from gearsim.signals._checks import WINDOWS, check_int

__all__ = [
    "BAND_FRACTION",
    "IMPACT_FACTOR",
    "KEYS",
    "LIST_KEYS",
    "STFT_FRAMES_PER_REV",
    "AnalysisSettings",
    "parse_analysis",
]

#: An impact must exceed the median per-mesh-period peak by this factor. The seed's
#: cracked-gear impacts reach about 2x the healthy level (209.8 %, 203.1 %) while normal
#: meshing peaks scatter by a few per cent, so 1.5 sits between the two with margin.
IMPACT_FACTOR = 1.5

#: Fraction of the power around n f_m that defines the band width (90 %: the main lobe
#: and the first sidebands of a healthy mesh tone, but not its far leakage).
BAND_FRACTION = 0.9

#: STFT frames per revolution of the reference shaft: four frames resolve the once-per-
#: revolution pulsation of the band energy (seed Figure 8) with frequency resolution
#: 4 f_r, still far finer than the mesh-harmonic spacing f_m = Z f_r for Z >= 12.
STFT_FRAMES_PER_REV = 4

#: Methods of IMF selection (:func:`gearsim.signals.emd.select_imfs`).
EMD_METHODS = ("correlation", "kurtosis")

#: Threshold rule of Ayenu-Prah & Attoh-Okine (2010), the word accepted for emd_threshold.
AYENU_PRAH = "ayenu-prah"

#: Config value kind of every option (as in :func:`gearsim.sections.convert`).
#: ``emd_threshold`` is a number or the word ``"ayenu-prah"``; ``emd_method`` may be
#: left out (no EMD).
KEYS: dict[str, str] = {
    "orders": "int", "n_sidebands": "int", "window": "str", "remove_mean": "bool",
    "impact_factor": "dimensionless", "band_fraction": "dimensionless",
    "stft_frames_per_rev": "int", "shaft_harmonics": "int", "sideband_orders": "int",
    "emd_method": "str", "emd_threshold": "dimensionless", "emd_max_imf": "int",
    "pulses_per_rev": "int",
}
#: Options given as a list in the config (each item of the kind in :data:`KEYS`).
LIST_KEYS = ("orders",)


@dataclass(frozen=True)
class AnalysisSettings:
    """Options of :func:`gearsim.signals.analysis`, validated on construction.

    Parameters
    ----------
    orders : tuple of int, default (1, 2, 3, 4)
        Mesh harmonics ``n`` examined (seed: 1..4), integers >= 1.
    n_sidebands : int, default 6
        Sidebands per side ``K`` (Hanna et al. 2011 use 6 for SER), >= 1.
    window : str, default "hann"
        Window of the amplitude spectrum: ``"hann"``, ``"flattop"`` or ``"boxcar"``.
    remove_mean : bool, default True
        RMS and peak of the signal minus its mean (the dynamic part) if True.
    impact_factor : float, default 1.5
        Multiple of the median per-mesh-period peak that an impact must exceed [-]
        (:data:`IMPACT_FACTOR`), > 0.
    band_fraction : float, default 0.9
        Fraction of the band power that defines the band width [-]
        (:data:`BAND_FRACTION`), in (0, 1).
    stft_frames_per_rev : int, default 4
        STFT frames per revolution of the reference shaft (:data:`STFT_FRAMES_PER_REV`);
        the hop is half a frame.
    shaft_harmonics : int, default 2
        Shaft orders 1..H removed for the TSA residual and difference signals, >= 0
        (Zakrajsek et al. 1993: 2 in practice).
    sideband_orders : int, default 1
        Mesh sidebands +-1..S removed for the TSA difference signal, >= 0.
    emd_method : str or None, default None
        ``None`` (no EMD), ``"correlation"`` or ``"kurtosis"``: decompose by EMD first and
        analyse the sum of the selected IMFs (seed sec. 4).
    emd_threshold : float or str, default "ayenu-prah"
        IMF selection threshold [-], a finite number or ``"ayenu-prah"``.
    emd_max_imf : int, default -1
        Maximum number of IMFs, -1 for no limit.
    pulses_per_rev : int, default 1
        Tacho pulses per revolution of the reference shaft, >= 1.

    Raises
    ------
    InputError
        If an option is of the wrong kind or out of range; the message names it
        ``analysis.<option>``.
    """

    orders: tuple[int, ...] = (1, 2, 3, 4)
    n_sidebands: int = 6
    window: str = "hann"
    remove_mean: bool = True
    impact_factor: float = IMPACT_FACTOR
    band_fraction: float = BAND_FRACTION
    stft_frames_per_rev: int = STFT_FRAMES_PER_REV
    shaft_harmonics: int = 2
    sideband_orders: int = 1
    emd_method: str | None = None
    emd_threshold: float | str = AYENU_PRAH
    emd_max_imf: int = -1
    pulses_per_rev: int = 1

    def __post_init__(self) -> None:
        p = "analysis"
        try:
            orders = [self.orders] if isinstance(self.orders, int) else list(self.orders)
        except TypeError:
            raise InputError(f"{p}.orders", self.orders, "must be a list of integers >= 1") \
                from None
        if not orders:
            raise InputError(f"{p}.orders", orders, "must list at least one mesh harmonic")
        object.__setattr__(self, "orders", tuple(
            check_int(f"{p}.orders[{j}]", n, minimum=1) for j, n in enumerate(orders)))
        for name, low in (("n_sidebands", 1), ("stft_frames_per_rev", 1),
                          ("shaft_harmonics", 0), ("sideband_orders", 0),
                          ("pulses_per_rev", 1)):
            object.__setattr__(self, name, check_int(f"{p}.{name}", getattr(self, name),
                                                     minimum=low))
        object.__setattr__(self, "emd_max_imf", check_int(
            f"{p}.emd_max_imf", self.emd_max_imf, minimum=1, allow=(-1,)))
        if self.window not in WINDOWS:
            raise InputError(f"{p}.window", self.window, f"must be one of {sorted(WINDOWS)}")
        if not isinstance(self.remove_mean, bool):
            raise InputError(f"{p}.remove_mean", self.remove_mean, "must be true or false")
        object.__setattr__(self, "impact_factor", _number(
            f"{p}.impact_factor", self.impact_factor, lambda v: v > 0, "must be > 0"))
        object.__setattr__(self, "band_fraction", _number(
            f"{p}.band_fraction", self.band_fraction, lambda v: 0 < v < 1, "must lie in (0, 1)"))
        if self.emd_method is not None and self.emd_method not in EMD_METHODS:
            raise InputError(f"{p}.emd_method", self.emd_method,
                             'must be "correlation" or "kurtosis" (or left out: no EMD)')
        if self.emd_threshold != AYENU_PRAH:
            object.__setattr__(self, "emd_threshold", _number(
                f"{p}.emd_threshold", self.emd_threshold, lambda v: True,
                f'must be a finite number or "{AYENU_PRAH}"'))

    def to_dict(self) -> dict[str, Any]:
        """Plain dict of the options (lists for tuples), for results files.

        Returns
        -------
        dict of str to Any
            Option name to value, every field.
        """
        return {f.name: list(v) if isinstance(v := getattr(self, f.name), tuple) else v
                for f in fields(self)}


def _number(name: str, value: Any, ok, limit: str) -> float:
    """``value`` as a finite float satisfying ``ok``, else :class:`InputError`."""
    if isinstance(value, bool):
        raise InputError(name, value, f"must be a number; {limit}")
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InputError(name, value, f"must be a number; {limit}") from None
    if not (math.isfinite(v) and ok(v)):
        raise InputError(name, value, limit)
    return v


def parse_analysis(table: Any, section: str = "analysis") -> AnalysisSettings:
    """Parse the ``[analysis]`` table into :class:`AnalysisSettings`.

    Parameters
    ----------
    table : dict
        The TOML table (keys of :data:`KEYS`; ``orders`` one integer or a list).
    section : str, optional
        Its name, for messages.

    Returns
    -------
    AnalysisSettings
        The validated options; defaults for the keys not given.

    Raises
    ------
    InputError
        Unknown key, bad value or a value out of range.
    """
    from gearsim.sections import convert  # pint (units): loaded only for a config table

    if isinstance(table, dict) and table.get("emd_threshold") == AYENU_PRAH:
        rest = {k: v for k, v in table.items() if k != "emd_threshold"}
        return AnalysisSettings(**convert(rest, KEYS, section, list_keys=LIST_KEYS),
                                emd_threshold=AYENU_PRAH)
    return AnalysisSettings(**convert(table, KEYS, section, list_keys=LIST_KEYS))
