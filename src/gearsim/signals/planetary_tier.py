r"""The planetary tier of a record's analysis: a fixed sensor on the ring of a stage.

Given the stage (tooth counts z_s, z_p, z_r, N planets) and the carrier speed with the ring
held, three groups of quantities are computed from one record:

1. **Sidebands at carrier orders** (McFadden & Smith 1985; Inalpolat & Kahraman 2009).
   Around the m-th mesh harmonic the amplitude spectrum (periodic Hann, mean removed) is
   read at ``m f_m + n f_c``, ``|n| <= span``; the orders the cyclic symmetry of N equally
   spaced planets lets through, ``m z_r + n = 0 (mod N)``
   (:func:`gearsim.signals.planetary.sideband_orders`), are flagged, and

   .. math:: \text{predicted share} = \sum_{n\ \text{allowed}} A_n^2 \Big/ \sum_n A_n^2

   is the fraction of the sideband power at the allowed orders (1 for an ideal healthy
   stage, smaller when a fault or unequal spacing breaks the symmetry). The lines must be
   resolved: the record spans at least ``MIN_BINS`` Hann bins per ``f_c``.
2. **Fault lines in the squared-envelope spectrum** of the band of mesh harmonics
   ``[f_m / 2, (H + 1/2) f_m]`` (:func:`gearsim.signals.envelope.envelope_spectrum`):
   at the sun fault frequency ``N (f_s - f_c)``, the planet fault frequency
   ``f_m / z_p`` (one flank) and twice it (both flanks), and ``N f_c`` (a ring-tooth
   fault, which coincides with the planet-pass frequency of a healthy stage). Each line is
   the largest amplitude within one bin of the frequency, and its level is given against
   the median of the envelope spectrum from ``f / 2`` to ``3 f / 2`` (dB). A line closer
   than ``2 LOBE`` bins to another of them or to a harmonic of the planet pass is not
   read (skipped, naming the record length that separates them): its bins would hold the
   other line (a healthy stage's planet pass read as a planet fault).
3. **Separated averages** of every planet and of the sun (McFadden 1991;
   :mod:`gearsim.signals.planet_tsa`), Hann windows of ``gcd(z_r, z_p)`` teeth (the
   fewest that reach every planet tooth), when the record holds the carrier revolutions
   that needs; for each the RMS of the average and its FM4 (Stewart 1977: the kurtosis
   of the difference signal, the average without its mesh harmonics k z and their first
   sidebands k z +- 1, in orders per member revolution; about 3 when healthy). A local
   tooth fault shows as the planet (or the sun) of largest FM4, provided the sensor hears
   mainly the planet passing it (McFadden's premise; a wide transfer-path window lets
   the other planets in).

The carrier angle is zero at the start of the record unless a phase is given (a gearsim
stage result stores its carrier angle, and the planets are numbered from it).

References
----------
.. [McFadden1985] P. D. McFadden, J. D. Smith, An explanation for the asymmetry of the
   modulation sidebands about the tooth meshing frequency in epicyclic gear vibration,
   Proc. IMechE C 199 (1985) 65-70.
.. [Inalpolat2009] M. Inalpolat, A. Kahraman, A theoretical and experimental
   investigation of modulation sidebands of planetary gear sets, J. Sound Vib. 323
   (2009) 677-696.
.. [Stewart1977] R. M. Stewart, Some useful data analysis techniques for gearbox
   diagnostics, Report MHM/R/10/77, Institute of Sound and Vibration Research,
   University of Southampton, 1977 (FM4).
.. [McFadden1991] P. D. McFadden, A technique for calculating the time domain averages of
   the vibration of the individual planet gears and the sun gear in an epicyclic
   gearbox, J. Sound Vib. 144 (1991) 163-172.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from gearsim.errors import InputError, require
from gearsim.signals.tiers import _hann_amplitude, _kurtosis

__all__ = ["MIN_BINS", "StageSpec", "planetary_tier"]

#: Hann bins per carrier-order spacing f_c needed to read the sidebands (the gear tier's
#: rule: 4 bins per sideband spacing).
MIN_BINS = 4
#: Carrier orders read on each side of a mesh harmonic.
SPAN = 8
#: Sideband power below this fraction of the record's power: the harmonic is absent.
EMPTY = 1e-12
#: Mesh harmonics read (fewer when m f_m + SPAN f_c passes the Nyquist frequency).
HARMONICS = 2
#: Main-lobe half width of the Hann window [bins]: two known envelope lines closer than
#: 2 LOBE bins share bins, and neither is read.
LOBE = 2


@dataclass(frozen=True)
class StageSpec:
    """What the planetary tier needs to know about the stage.

    Parameters
    ----------
    z_sun, z_planet, z_ring : int
        Tooth counts.
    planets : int
        Number of planets N (taken as equally spaced).
    carrier_frequency : float
        Carrier frequency f_c [Hz] (> 0), ring held.
    carrier_phase : float
        Carrier angle at the first sample [rad].
    sensor_angle : float
        Ring angle of the sensor [rad], same origin as the planet angles 2 pi n / N at
        carrier angle 0.
    provenance : str
        ``"file"`` (a gearsim stage result) or ``"given"``.
    """

    z_sun: int
    z_planet: int
    z_ring: int
    planets: int
    carrier_frequency: float
    carrier_phase: float = 0.0
    sensor_angle: float = 0.0
    provenance: str = "given"

    def __post_init__(self) -> None:
        for name in ("z_sun", "z_planet", "z_ring", "planets"):
            v = getattr(self, name)
            require(isinstance(v, (int, np.integer)) and not isinstance(v, bool) and v >= 1,
                    f"stage.{name}", v, "must be an integer >= 1")
        f = self.carrier_frequency
        require(isinstance(f, (int, float)) and math.isfinite(f) and f > 0,
                "carrier frequency", f, "must be a finite frequency > 0 Hz (ring held)")
        for name in ("carrier_phase", "sensor_angle"):
            require(math.isfinite(getattr(self, name)), name, getattr(self, name),
                    "must be finite")


def _sidebands(a: np.ndarray, fs: float, spec: StageSpec, fr: Any, skipped: list
               ) -> list[dict] | None:
    from gearsim.signals.planetary import sideband_orders

    df = fs / a.size
    fc, fm = spec.carrier_frequency, fr.mesh
    if fc < MIN_BINS * df:
        skipped.append({"tier": "planetary.sidebands", "reason": f"record {a.size / fs:.4g} s"
                        f" must be >= {MIN_BINS / fc:.4g} s ({MIN_BINS} Hann bins per carrier "
                        f"order f_c = {fc:.4g} Hz)"})
        return None
    amp = _hann_amplitude(a)
    out = []
    for m in range(1, HARMONICS + 1):
        if m * fm + SPAN * fc >= 0.5 * fs:
            skipped.append({"tier": f"planetary.sidebands.{m}", "reason": f"{m} f_m + {SPAN} "
                            f"f_c = {m * fm + SPAN * fc:.5g} Hz reaches the Nyquist frequency"})
            break
        present, dominant = sideband_orders(spec.z_ring, spec.planets, m, SPAN)
        orders = np.arange(-SPAN, SPAN + 1)
        a_n = np.array([amp[int(round((m * fm + n * fc) / df))] for n in orders])
        allowed = np.isin(orders, present)
        power = a_n**2
        if power.sum() <= EMPTY * float(np.sum(amp**2)):
            skipped.append({"tier": f"planetary.sidebands.{m}", "reason": f"no power around "
                            f"{m} f_m = {m * fm:.5g} Hz (below {EMPTY:g} of the record's)"})
            continue
        out.append({
            "harmonic": m, "frequency_hz": m * fm,
            "orders": [{"order": int(n), "amplitude": float(v), "allowed": bool(ok)}
                       for n, v, ok in zip(orders, a_n, allowed, strict=True)],
            "predicted_share": float(power[allowed].sum() / power.sum())
            if power.sum() > 0 else None,
            "dominant_order": int(orders[int(np.argmax(a_n))]),
            "predicted_dominant_order": int(dominant)})
    return out


def _fault_lines(a: np.ndarray, fs: float, fr: Any, skipped: list) -> dict | None:
    from gearsim.signals.envelope import envelope_spectrum

    lo = 0.5 * fr.mesh
    hi = min(0.5 * fs, (HARMONICS + 0.5) * fr.mesh)
    if not lo < hi:
        skipped.append({"tier": "planetary.envelope", "reason": "no mesh harmonic below the "
                        "Nyquist frequency"})
        return None
    es = envelope_spectrum(a, fs, band=(lo, hi))
    f, amp = es.frequency, es.amplitude
    df = f[1] - f[0]
    lines = {"sun_fault": fr.sun_fault, "planet_fault": fr.planet_fault,
             "planet_fault_both_flanks": 2.0 * fr.planet_fault,
             "ring_fault_planet_pass": fr.ring_fault}
    # the known lines: these and the harmonics of the planet pass N f_c (a healthy
    # stage's envelope); a line is read only where its +-1 bin stay out of their main lobes
    known = {**lines, **{f"{j} x planet pass": j * fr.ring_fault
                         for j in range(2, int(f[-1] / fr.ring_fault) + 1)}}
    out: dict[str, Any] = {"band_hz": [float(lo), float(hi)], "lines": {}}
    for name, fq in lines.items():
        if not 2 * df <= fq < 0.66 * f[-1]:
            skipped.append({"tier": f"planetary.envelope.{name}", "reason": f"{fq:.4g} Hz is "
                            f"not resolved by the record (bin {df:.3g} Hz) or above the band"})
            continue
        near_by = min(((abs(g - fq), n) for n, g in known.items() if abs(g - fq) > 1e-9 * fq),
                      default=(math.inf, ""))
        if near_by[0] < 2 * LOBE * df:  # would be read from the other line's main lobe
            skipped.append({"tier": f"planetary.envelope.{name}", "reason": f"{fq:.4g} Hz "
                            f"lies {near_by[0]:.4g} Hz from {near_by[1]} "
                            f"({known[near_by[1]]:.4g} Hz): the record "
                            f"{a.size / fs:.4g} s must be >= {2 * LOBE / near_by[0]:.4g} s to "
                            f"separate them ({2 * LOBE} Hann bins)"})
            continue
        k = int(round(fq / df))
        line = float(amp[max(k - 1, 0):k + 2].max())
        near = (f >= 0.5 * fq) & (f <= 1.5 * fq)
        floor = float(np.median(amp[near]))
        out["lines"][name] = {"frequency_hz": float(fq), "amplitude": line,
                              "to_floor_db": float(20 * math.log10(line / floor))
                              if floor > 0 and line > 0 else None}
    return out


def _fm4(y: np.ndarray, teeth: int) -> float | None:
    """Kurtosis of the difference signal of an average over one member revolution.

    FM4 (Stewart 1977): the regular meshing, the mesh harmonics k z and their first
    sidebands k z +- 1 (orders per revolution), is removed from the average and the
    kurtosis of what is left is taken; ~3 for a healthy member, larger for a local fault.
    """
    spec = np.fft.rfft(y - y.mean())
    orders = np.arange(spec.size)
    regular = np.zeros(spec.size, dtype=bool)
    for k in range(teeth, spec.size + 1, teeth):
        regular |= np.abs(orders - k) <= 1
    regular[0] = True
    d = np.fft.irfft(np.where(regular, 0.0, spec), n=y.size)
    k = _kurtosis(d)
    return None if np.isnan(k) else k  # none for a constant average


def _separated(a: np.ndarray, fs: float, spec: StageSpec, skipped: list) -> dict | None:
    from gearsim.signals.planet_tsa import planet_average, sun_average

    fc = spec.carrier_frequency
    k = math.gcd(spec.z_ring, spec.z_planet)
    k_max = min(spec.z_planet, spec.z_ring // spec.planets)
    if k > k_max:
        skipped.append({"tier": "planetary.separation", "reason": f"windows of gcd(z_r, z_p) "
                        f"= {k} teeth exceed min(z_p, z_r // N) = {k_max}"})
        return None
    # carrier pulses where the carrier angle is a whole number of turns
    t_end = a.size / fs
    first = ((-spec.carrier_phase) % (2 * math.pi)) / (2 * math.pi * fc)
    pulses = np.arange(first, t_end, 1.0 / fc)
    if pulses.size < 2:  # the averages need one whole carrier revolution between marks
        skipped.append({"tier": "planetary.separation", "reason": f"the planets and the sun "
                        f"are separated over whole carrier revolutions, from one passage of "
                        f"the carrier at angle 0 to the next ({1 / fc:.4g} s apart at "
                        f"{fc:.4g} Hz); the record of {t_end:.4g} s holds {pulses.size} "
                        f"passage{'' if pulses.size == 1 else 's'}: one of "
                        f"{first + 1 / fc:.4g} s or longer would hold two"})
        return None
    common = dict(carrier_pulses=pulses, z_sun=spec.z_sun, z_planet=spec.z_planet,
                  z_ring=spec.z_ring, planets=spec.planets, sensor_angle=spec.sensor_angle,
                  window="hann", window_teeth=max(k, 1), samples_per_tooth=16)
    out: dict[str, Any] = {"window": f"hann, {max(k, 1)} teeth", "planets": []}
    try:
        for n in range(spec.planets):
            avg = planet_average(a, fs, planet=n, **common)
            out["planets"].append({"planet": n + 1, "rms": float(np.std(avg.signal)),
                                   "fm4": _fm4(avg.signal, spec.z_planet),
                                   "passes": avg.passes})
        sun = sun_average(a, fs, **common)
    except InputError as exc:
        skipped.append({"tier": "planetary.separation", "reason": str(exc)})
        return None
    out["sun"] = {"rms": float(np.std(sun.signal)), "fm4": _fm4(sun.signal, spec.z_sun),
                  "passes": sun.passes}
    fm4 = np.array([np.nan if p["fm4"] is None else p["fm4"] for p in out["planets"]],
                   dtype=float)
    # none where no planet's FM4 is defined (a constant record: no residual to measure)
    out["highest_fm4_planet"] = (int(np.nanargmax(fm4)) + 1 if np.isfinite(fm4).any()
                                 else None)
    return out


def planetary_tier(x: np.ndarray, fs: float, spec: StageSpec, skipped: list | None = None
                   ) -> dict[str, Any]:
    """Sidebands, envelope fault lines and separated averages of a ring-sensor record.

    Parameters
    ----------
    x : array_like
        Signal of a sensor fixed on the ring (any units), finite.
    fs : float
        Sampling rate [Hz].
    spec : StageSpec
        Stage and carrier speed (ring held).
    skipped : list, optional
        Receives ``{"tier", "reason"}`` for every part not computed.

    Returns
    -------
    dict
        ``frequencies`` (:func:`gearsim.signals.planetary.planetary_frequencies` fields,
        Hz), ``sidebands`` (per harmonic: orders, amplitudes, allowed flags, predicted
        share, dominant and predicted dominant order), ``envelope`` (fault lines and their
        level over the local floor, dB), ``separation`` (per planet and the sun: RMS,
        FM4, passes; the planet of highest FM4); parts that could not be
        computed are None and listed in ``skipped``.

    Raises
    ------
    InputError
        If the signal or ``fs`` is invalid, or the mesh frequency is at or above the
        Nyquist frequency.

    References
    ----------
    McFadden & Smith (1985); Inalpolat & Kahraman (2009); McFadden (1991); module
    docstring.

    Examples
    --------
    Ring held, z 30/24/78, four planets, f_c = 5 Hz: f_m = 390 Hz, planet pass 20 Hz, sun
    fault 4 x 13 = 52 Hz. A synthetic record of the ring-mesh lines the symmetry allows
    (m z_r + n = 0 mod 4 around 390 Hz: n = 2, -2, 6, ...) has all its sideband power at
    the allowed orders:

    >>> import numpy as np
    >>> fs, t = 5000.0, np.arange(5000) / 5000.0
    >>> x = 0.5 * np.cos(2 * np.pi * 400 * t) + np.cos(2 * np.pi * 380 * t)
    >>> res = planetary_tier(x, fs, StageSpec(30, 24, 78, 4, carrier_frequency=5.0))
    >>> res["frequencies"]["mesh"], res["frequencies"]["sun_fault"]
    (390.0, 52.0)
    >>> sb = res["sidebands"][0]
    >>> round(sb["predicted_share"], 6), sb["dominant_order"], sb["predicted_dominant_order"]
    (1.0, -2, -2)
    """
    from gearsim.signals._checks import as_signal, check_fs
    from gearsim.signals.planetary import planetary_frequencies

    a = as_signal(x)
    fs = check_fs(fs)
    skipped = [] if skipped is None else skipped
    fr = planetary_frequencies(spec.z_sun, spec.z_planet, spec.z_ring, spec.planets,
                               carrier=spec.carrier_frequency, ring=0.0)
    if fr.mesh >= 0.5 * fs:
        raise InputError("stage", f"z_r {spec.z_ring} x f_c {spec.carrier_frequency:g} Hz",
                         f"mesh frequency {fr.mesh:g} Hz is at or above the Nyquist frequency "
                         f"{0.5 * fs:g} Hz: check the tooth counts, the speed and fs")
    freqs = {k: float(getattr(fr, k)) for k in (
        "sun", "carrier", "ring", "planet", "planet_relative", "mesh", "planet_pass",
        "sun_fault", "ring_fault", "planet_fault")}
    return {"rests_on": {"stage": spec.provenance}, "frequencies": freqs,
            "sidebands": _sidebands(a, fs, spec, fr, skipped),
            "envelope": _fault_lines(a, fs, fr, skipped),
            "separation": _separated(a, fs, spec, skipped)}
