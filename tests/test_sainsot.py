"""The fillet-foundation term against the published formula of Sainsot, Velex & Duverger.

P. Sainsot, P. Velex, O. Duverger, Contribution of gear body to tooth deflections - a
new bidimensional analytical formula, J. Mech. Des. 126 (2004) 748-752: Table 1 gives
each coefficient as X*(h_f, theta_f) = A/theta_f^2 + B h_f^2 + C h_f/theta_f
+ D/theta_f + E h_f + F, and the foundation deflection is

    delta_f = F cos^2(alpha_m) / (E b) [L* (u_f/S_f)^2 + M* (u_f/S_f) + P* (1 + Q* tan^2 alpha_m)].

The table is typed below from the paper (also in docs/references.md); the contact point,
alpha_m, u_f, S_f, theta_f and h_f are computed here from the involute and the rack in
closed form, not from gearsim's outline or kernel.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from gearsim.geometry.gear import Gear, Material
from gearsim.stiffness.tooth import SAINSOT, ToothModel, sainsot_coefficients

# (A, B, C, D, E, F) of L*, M*, P*, Q*, Sainsot et al. (2004), Table 1.
PAPER = {
    "L": (-5.574e-5, -1.9986e-3, -2.3015e-4, 4.7702e-3, 0.0271, 6.8045),
    "M": (60.111e-5, 28.100e-3, -83.431e-4, -9.9256e-3, 0.1624, 0.9086),
    "P": (-50.952e-5, 185.50e-3, 0.0538e-4, 53.300e-3, 0.2895, 0.9236),
    "Q": (-6.2042e-5, 9.0889e-3, -4.0964e-4, 7.8297e-3, -0.1472, 0.6904),
}
# The same six-term polynomial summed in another order: rounding only (terms up to ~7,
# results >= 0.4, so a few 1e-16 relative; 1e-13 leaves two orders of margin).
ROUNDING_RTOL = 1e-13
# Foundation term from an independent evaluation of the same closed-form geometry: the
# only difference is theta_f (rack closed form here, generated outline in gearsim, equal
# to ~1e-15) and rounding.
FOUNDATION_RTOL = 1e-10


def _paper_coefficient(key: str, h_f: float, theta_f: float) -> float:
    a, b, c, d, e, f = PAPER[key]
    return a / theta_f**2 + b * h_f**2 + c * h_f / theta_f + d / theta_f + e * h_f + f


def test_table_as_published():
    """gearsim's coefficient table is the paper's, entry by entry."""
    assert set(SAINSOT) == set(PAPER)
    for key, row in PAPER.items():
        assert tuple(SAINSOT[key]) == row, key


@pytest.mark.parametrize("h_f,theta_f", [
    (1.5, 0.08), (2.0, 0.1), (2.0, 0.1586), (3.3, 0.12), (5.0, 0.2), (6.8, 0.06)])
def test_coefficients_at_points(h_f, theta_f):
    """All four rows at points spanning solid blanks to thin rims and slim/fat teeth."""
    got = sainsot_coefficients(h_f, theta_f)
    want = [_paper_coefficient(k, h_f, theta_f) for k in "LMPQ"]
    np.testing.assert_allclose(got, want, rtol=ROUNDING_RTOL)


def test_coefficients_hand_value():
    """One point evaluated term by term on paper: h_f = 2, theta_f = 0.1 rad.

    L* = -5.574e-3 - 7.9944e-3 - 4.603e-3 + 4.7702e-2 + 5.42e-2 + 6.8045 = 6.8882306
    Q* = -6.2042e-3 + 3.63556e-2 - 8.1928e-3 + 7.8297e-2 - 0.2944 + 0.6904 = 0.4962556
    """
    got = sainsot_coefficients(2.0, 0.1)
    assert got[0] == pytest.approx(6.8882306, rel=1e-12)
    assert got[3] == pytest.approx(0.4962556, rel=1e-12)


def _inv(a: float) -> float:
    return math.tan(a) - a


@pytest.mark.parametrize("z,m,beta_deg,bore,frac", [
    (19, 3.2e-3, 0.0, None, 0.3), (19, 3.2e-3, 0.0, 10e-3, 0.8),
    (39, 6e-3, 13.0, None, 0.5), (125, 6e-3, 13.0, 0.2, 0.1)])
def test_foundation_compliance_at_contact_point(z, m, beta_deg, bore, frac):
    """The foundation column of the tooth model equals Sainsot's formula, L = 1 m.

    Geometry from closed forms (ISO 21771; rack generation): contact point on the
    involute at radius r_c, psi = pi/(2z) + inv(alpha_t) - inv(alpha_r) (x = 0),
    alpha_m = alpha_r - psi; the load line meets the centre line at
    y_Q = y_c - x_c tan(alpha_m); theta_f = u_C / (r cos beta) with
    u_C = pi m/4 + (h_fP - rho) tan(alpha_n) + rho / cos(alpha_n);
    u_f = y_Q - r_f cos(theta_f), S_f = 2 r_f theta_f, h_f = r_f / r_bore.
    """
    mat = Material()
    beta = math.radians(beta_deg)
    gear = Gear(teeth=z, normal_module=m, helix_angle=beta, face_width=0.05,
                bore_radius=bore, material=mat)
    an = math.radians(20.0)
    at = math.atan(math.tan(an) / math.cos(beta))
    r = z * m / (2 * math.cos(beta))
    rb = r * math.cos(at)
    ra = r + m
    rf = r - 1.25 * m
    r_bore = rf / 2 if bore is None else bore
    tm = ToothModel(gear)
    rc = tm.profile.form_radius + frac * (ra - tm.profile.form_radius)
    ar = math.acos(rb / rc)
    psi = math.pi / (2 * z) + _inv(at) - _inv(ar)
    xc, yc = rc * math.sin(psi), rc * math.cos(psi)
    am = ar - psi
    rho = 0.38 * m
    u_c = math.pi * m / 4 + (1.25 * m - rho) * math.tan(an) + rho / math.cos(an)
    theta_f = u_c / (r * math.cos(beta))
    u_f = yc - xc * math.tan(am) - rf * math.cos(theta_f)
    s_f = 2 * rf * theta_f
    h_f = rf / r_bore
    lc, mc, pc, qc = (_paper_coefficient(k, h_f, theta_f) for k in "LMPQ")
    ratio = u_f / s_f
    want = math.cos(am) ** 2 / mat.youngs_modulus * (
        lc * ratio**2 + mc * ratio + pc * (1 + qc * math.tan(am) ** 2))
    got = tm.compliance([rc])[0, 3]
    assert got == pytest.approx(want, rel=FOUNDATION_RTOL)
    # plausibility: the foundation is a positive compliance of order 1e-11 m/N per metre
    assert 1e-12 < want < 1e-10


def test_warns_outside_the_fitted_range():
    """A 19-tooth pinion (theta_f 0.159 rad) is outside Sainsot's fitted theta_f range
    [0.01, 0.12] rad: one ModelRangeWarning naming the gear and the quantity; a
    39-tooth gear (theta_f 0.08 rad, h_f = 2) is inside and silent; a bore that makes
    h_f = 8 names h_f."""
    import warnings

    from gearsim.errors import ModelRangeWarning

    small = Gear(teeth=19, normal_module=3.2e-3, face_width=0.016, name="pinion")
    with pytest.warns(ModelRangeWarning, match=r"gear pinion: theta_f = 0\.15\d+ rad"):
        _ = ToothModel(small).sainsot
    big = Gear(teeth=39, normal_module=6e-3, face_width=0.15, name="input")
    with warnings.catch_warnings():
        warnings.simplefilter("error", ModelRangeWarning)
        _ = ToothModel(big).sainsot
    thin = Gear(teeth=39, normal_module=6e-3, face_width=0.15, name="input",
                bore_radius=big.root_radius / 8)
    with pytest.warns(ModelRangeWarning, match=r"gear input: h_f = 8 "):
        _ = ToothModel(thin).sainsot


def test_cli_prints_the_range_warning_as_one_line(capsys, monkeypatch):
    """The CLI turns the warning into one line on standard error; the run goes on. As in
    a new ``gearsim`` process, the run starts without the in-memory stiffness tables an
    earlier in-process run of the same example left (a cached table is not recomputed,
    so it does not warn again)."""
    import gearsim.system.train as train_module
    from gearsim.cli import run
    from gearsim.system.memo import Memo

    monkeypatch.setattr(train_module, "_TABLES", Memo(train_module.TABLE_CACHE_SIZE))
    assert run(["stiffness", "spur-19-48"]) == 0
    err = capsys.readouterr().err.strip().splitlines()
    assert err == ["gearsim: warning: Sainsot foundation of gear pinion: theta_f = 0.1586 rad "
                   "outside the fitted range [0.01, 0.12] rad (the fit is extrapolated)"]
