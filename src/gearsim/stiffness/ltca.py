"""Quasi-static loaded tooth contact analysis (LTCA) on a mesh of contacts.

At each mesh position c the deflection delta along the transverse line of action that
carries the transverse force F solves

    sum_j k_j(c) max(0, delta - s_j(c)) = F                                    (1)

(:mod:`gearsim.stiffness.contacts`). The left side is continuous, piecewise linear and
non-decreasing in delta, so (1) is solved exactly: sort the separations, accumulate
K_m = sum_{j<=m} k_j and S_m = sum_{j<=m} k_j s_j, find the first segment whose end
carries at least F, and delta = (F + S_m) / K_m. Results per position:

* loaded transmission error delta [m] (line of action; the driven gear lags by
  delta / r_b2 [rad]); the unloaded transmission error is the smallest separation of a
  contact that exists, min s_j;
* contact forces f_j = k_j max(0, delta - s_j) [N], load sharing between tooth pairs,
  load per unit face width along the contact lines (the contact pattern);
* positions where no contact can close (every k_j = 0, e.g. a broken spur tooth without
  corner contacts) are flagged, not given a number.

Slices are independent springs (the slicing model's assumption: no coupling along the
face through the tooth, which spreads the load of a crowned or misaligned tooth less than
a plate model would; Haddad 1991 / Velex & Maatar 1996 use the same independent-spring
foundation).

References
----------
.. [Velex1996] P. Velex, M. Maatar, J. Sound Vib. 191 (1996) 629-660.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from gearsim.errors import require
from gearsim.stiffness.contacts import ContactGrid

__all__ = ["LoadedContact", "loaded_contact", "solve_deflection"]


def solve_deflection(k: np.ndarray, s: np.ndarray, force: float) -> np.ndarray:
    """Deflection delta solving sum_j k_j max(0, delta - s_j) = F for each row.

    Parameters
    ----------
    k : ndarray, shape (n, m)
        Contact stiffnesses [N/m] (0: no contact).
    s : ndarray, shape (n, m)
        Separations [m].
    force : float
        Force F > 0 [N].

    Returns
    -------
    ndarray, shape (n,)
        delta [m]; NaN where every k_j of the row is 0 (no contact possible).

    Examples
    --------
    Two springs of 1e8 N/m at separations 0 and 10 um under 3000 N: the first alone
    reaches 10 um at 1000 N, then both: delta = 10 um + 2000 / 2e8 = 20 um.

    >>> round(float(solve_deflection(np.array([[1e8, 1e8]]), np.array([[0.0, 1e-5]]),
    ...                              3000.0)[0]) * 1e6, 9)
    20.0
    """
    k = np.asarray(k, dtype=float)
    s = np.where(k > 0, np.asarray(s, dtype=float), np.inf)
    order = np.argsort(s, axis=1)
    ss = np.take_along_axis(s, order, axis=1)
    kk = np.take_along_axis(np.where(k > 0, k, 0.0), order, axis=1)
    kc = np.cumsum(kk, axis=1)
    ksc = np.cumsum(kk * np.where(kk > 0, ss, 0.0), axis=1)
    nxt = np.concatenate([ss[:, 1:], np.full((ss.shape[0], 1), np.inf)], axis=1)
    with np.errstate(invalid="ignore"):
        g = np.where(kc > 0, kc * nxt - ksc, 0.0)  # force at the end of each segment
    g = np.where(np.isnan(g), np.inf, g)
    reach = g >= force
    m = np.argmax(reach, axis=1)
    ok = reach[np.arange(ss.shape[0]), m] & (kc[np.arange(ss.shape[0]), m] > 0)
    rows = np.arange(ss.shape[0])
    with np.errstate(divide="ignore", invalid="ignore"):
        delta = (force + ksc[rows, m]) / kc[rows, m]
    return np.where(ok, delta, np.nan)


@dataclass
class LoadedContact:
    """Result of :func:`loaded_contact`.

    Parameters
    ----------
    grid : ContactGrid
        The contacts analysed.
    force : float
        Transverse force along the line of action [N].
    delta : ndarray, shape (n_pos,)
        Loaded transmission error along the line of action [m] (NaN where no contact).
    unloaded : ndarray, shape (n_pos,)
        Unloaded (kinematic) transmission error, min s_j of existing contacts [m].
    load : ndarray
        Force of each contact [N], shape of ``grid.k``.
    """

    grid: ContactGrid
    force: float
    delta: np.ndarray
    unloaded: np.ndarray
    load: np.ndarray

    @property
    def contact(self) -> np.ndarray:
        """True where a contact carries the load [-]."""
        return np.isfinite(self.delta)

    @property
    def pair_share(self) -> np.ndarray:
        """Load share of each tooth pair, shape (n_pos, n_pair) [-]."""
        return self.load.sum(axis=(2, 3)) / self.force

    @property
    def peak_to_peak(self) -> float:
        """Peak-to-peak loaded transmission error over the positions with contact [m]."""
        d = self.delta[self.contact]
        return float(np.ptp(d)) if d.size else math.nan

    @property
    def stiffness(self) -> np.ndarray:
        """Secant mesh stiffness F / (delta - unloaded) [N/m]."""
        with np.errstate(divide="ignore", invalid="ignore"):
            return self.force / (self.delta - self.unloaded)

    @property
    def line_load(self) -> np.ndarray:
        """Load per unit face width of each slice, shape (n_pos, n_pair, n_slice) [N/m]."""
        return self.load.sum(axis=3) / self.grid.slice_width

    def pattern(self, bins: int = 40) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Contact pattern: largest line load over the flank (line of action x face).

        Parameters
        ----------
        bins : int
            Bins along the line of action.

        Returns
        -------
        l_edges : ndarray, shape (bins + 1,)
            Bin edges along the line of action [m].
        zfrac : ndarray, shape (n_slice,)
            Slice centres / face width [-].
        peak : ndarray, shape (bins, n_slice)
            Largest load per unit width seen in each bin [N/m].
        """
        ll = self.line_load
        l = self.grid.l
        on = ll > 0
        lo, hi = (float(l[on].min()), float(l[on].max())) if on.any() else (0.0, 1.0)
        edges = np.linspace(lo, hi, bins + 1)
        idx = np.clip(np.searchsorted(edges, l, side="right") - 1, 0, bins - 1)
        peak = np.zeros((bins, ll.shape[2]))
        for j in range(ll.shape[2]):
            np.maximum.at(peak[:, j], idx[..., j][on[..., j]], ll[..., j][on[..., j]])
        return edges, self.grid.zfrac, peak

    def plot(self, *, cycles: float | None = None, fig=None):
        """The figure of :func:`gearsim.viz.contacts.plot_loaded_contact`.

        Parameters
        ----------
        cycles : float, optional
            Mesh cycles shown; default all.
        fig : matplotlib.figure.Figure, optional
            Figure to draw into.

        Returns
        -------
        matplotlib.figure.Figure
        """
        from gearsim.viz.contacts import plot_loaded_contact

        return plot_loaded_contact(self, cycles=cycles, fig=fig)

    def summary(self) -> dict:
        """Key numbers (SI): peak-to-peak loaded error, stiffness, largest line load.

        Returns
        -------
        dict
        """
        ok = self.contact
        k = self.stiffness[ok]
        return {"mesh": self.grid.name, "force_N": self.force,
                "positions": int(self.delta.size), "positions_without_contact": int((~ok).sum()),
                "loaded_te_ptp_m": self.peak_to_peak,
                "loaded_te_mean_m": float(np.mean(self.delta[ok])) if ok.any() else None,
                "stiffness_mean_N_per_m": float(np.mean(k)) if k.size else None,
                "max_line_load_N_per_m": float(np.max(self.line_load)),
                "period_cycles": self.grid.period}

    def to_dataset(self):
        """The result as an :class:`xarray.Dataset` (units in attributes).

        Returns
        -------
        xarray.Dataset
        """
        import xarray as xr

        return xr.Dataset(
            {"loaded_te": ("position", self.delta, {"units": "m",
                                                    "long_name": "loaded transmission error"}),
             "unloaded_te": ("position", self.unloaded, {"units": "m"}),
             "stiffness": ("position", self.stiffness, {"units": "N/m"}),
             "pair_share": (("position", "pair"), self.pair_share, {"units": "1"}),
             "tooth1": (("position", "pair"), self.grid.tooth1),
             "tooth2": (("position", "pair"), self.grid.tooth2),
             "line_load": (("position", "pair", "slice"), self.line_load, {"units": "N/m"})},
            coords={"cycles": ("position", self.grid.cycles, {"units": "1"}),
                    "zfrac": ("slice", self.grid.zfrac, {"units": "1"})},
            attrs={"mesh": self.grid.name, "force": self.force, **self.grid.attrs})


def loaded_contact(grid: ContactGrid, force: float) -> LoadedContact:
    """Quasi-static loaded contact of every position of ``grid`` under ``force``.

    Parameters
    ----------
    grid : ContactGrid
        Contacts of the mesh (:func:`gearsim.stiffness.contacts.contact_grid`).
    force : float
        Transverse force along the line of action [N] (torque / base radius), > 0.

    Returns
    -------
    LoadedContact

    Raises
    ------
    InputError
        If the force is not a finite number > 0.
    """
    require(isinstance(force, (int, float)) and math.isfinite(force) and force > 0,
            "force", force, "must be a finite number > 0 N")
    n = grid.k.shape[0]
    k = grid.k.reshape(n, -1)
    s = grid.s.reshape(n, -1)
    delta = solve_deflection(k, s, float(force))
    with np.errstate(invalid="ignore"):
        load = np.where(k > 0, k * np.maximum(0.0, delta[:, None] - s), 0.0)
    load = np.nan_to_num(load, nan=0.0).reshape(grid.k.shape)
    unloaded = np.min(np.where(k > 0, s, np.inf), axis=1)
    unloaded = np.where(np.isfinite(unloaded), unloaded, np.nan)
    return LoadedContact(grid=grid, force=float(force), delta=delta, unloaded=unloaded,
                         load=load)
