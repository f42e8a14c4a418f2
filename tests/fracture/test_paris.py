"""Paris-law life against the closed-form life of a constant-geometry-factor crack."""

from __future__ import annotations

import math

import numpy as np
import pytest

from gearsim.errors import InputError
from gearsim.fracture.paris import STEEL_CLASSES, ParisLaw, paris_life, steel_class_law

#: Issue 27: the integration must reproduce the closed form to 1e-6 (relative).
LIFE_RTOL = 1e-6

Y = 1.12
DSIGMA = 200e6  # stress range [Pa], R = 0
A0 = 1e-3


def closed_form_cycles(c: float, m: float, y: float, ds: float, a0: float, a1: float) -> float:
    """N = int_a0^a1 da / (C (Y ds sqrt(pi a))^m), integrated by hand."""
    k = c * (y * ds * math.sqrt(math.pi)) ** m
    if m == 2.0:
        return math.log(a1 / a0) / k
    e = 1.0 - 0.5 * m
    return (a1**e - a0**e) / (e * k)


def dk_const(a: float) -> float:
    return Y * DSIGMA * math.sqrt(math.pi * a)


@pytest.mark.parametrize("m", [2.0, 2.25, 3.0, 4.0])
def test_life_to_fracture_matches_closed_form(m: float) -> None:
    law = ParisLaw(c=1e-11 * 1e6 ** (-m), m=m, threshold=5e6, toughness=80e6)
    res = paris_life(law, dk_const, A0, 0.2)
    a_c = (law.toughness / (Y * DSIGMA)) ** 2 / math.pi
    assert res.status == "fracture"
    assert res.a_end == pytest.approx(a_c, rel=1e-12)
    want = closed_form_cycles(law.c, m, Y, DSIGMA, A0, a_c)
    assert res.cycles_end == pytest.approx(want, rel=LIFE_RTOL)
    # every output point, not only the end
    for a, n in zip(res.a[1:], res.cycles[1:], strict=True):
        assert n == pytest.approx(closed_form_cycles(law.c, m, Y, DSIGMA, A0, a), rel=LIFE_RTOL)
    assert np.all(np.diff(res.cycles) > 0.0)


def test_life_with_steel_class_constants() -> None:
    law = steel_class_law("martensitic", threshold=5e6, toughness=80e6)
    assert law.c == pytest.approx(1.36e-10 * 1e6 ** (-2.25))
    res = paris_life(law, dk_const, A0, 0.2)
    a_c = (80e6 / (Y * DSIGMA)) ** 2 / math.pi
    want = closed_form_cycles(law.c, 2.25, Y, DSIGMA, A0, a_c)
    assert res.cycles_end == pytest.approx(want, rel=LIFE_RTOL)


def test_length_limit_before_fracture() -> None:
    law = ParisLaw.from_mpa(1e-11, 3.0, 5.0, 80.0)
    res = paris_life(law, dk_const, A0, 5e-3)
    assert res.status == "length limit" and res.a_end == 5e-3
    assert res.cycles_end == pytest.approx(
        closed_form_cycles(law.c, 3.0, Y, DSIGMA, A0, 5e-3), rel=LIFE_RTOL)


def test_no_growth_below_threshold_is_an_answer() -> None:
    law = ParisLaw.from_mpa(1e-11, 3.0, 5.0, 80.0)
    res = paris_life(law, lambda a: 4.0e6, A0, 0.01)
    assert res.status == "no growth" and res.cycles_end == math.inf and res.a_end == A0


def test_arrest_where_the_range_falls_below_threshold() -> None:
    """dK falling linearly from 10 to 4 MPa sqrt(m): arrest at dK = 5, cycles to it
    closed form: int da / (C (10 - 6 (a - a0)/L)^3 MPa^3)."""
    law = ParisLaw.from_mpa(1e-11, 3.0, 5.0, 80.0)
    length = 0.01

    def dk(a: float) -> float:
        return (10.0 - 6.0 * (a - A0) / length) * 1e6

    res = paris_life(law, dk, A0, A0 + length)
    a_stop = A0 + length * 5.0 / 6.0
    assert res.status == "arrest" and res.cycles_end == math.inf
    assert res.a_end == pytest.approx(a_stop, rel=1e-12)
    # N = L/(6 C) * int_{5}^{10} x^-3 dx  (x in Pa sqrt(m))
    want = length / (6.0e6 * law.c) * 0.5 * ((5e6) ** -2 - (10e6) ** -2)
    assert res.cycles[-1] == pytest.approx(want, rel=LIFE_RTOL)


def test_immediate_fracture() -> None:
    law = ParisLaw.from_mpa(1e-11, 3.0, 5.0, 20.0)
    res = paris_life(law, lambda a: 30e6, A0, 0.01)
    assert res.status == "fracture" and res.cycles_end == 0.0


def test_rate_below_and_above_threshold() -> None:
    law = ParisLaw.from_mpa(1e-11, 3.0, 5.0, 80.0)
    assert law.rate(4.9e6) == 0.0
    assert law.rate(10e6) == pytest.approx(1e-11 * 10.0**3)


@pytest.mark.parametrize(("kwargs", "name"), [
    (dict(c=1e-11, m=3.0, threshold=5e6, toughness=80e6), "custom.c"),  # C in MPa units
    (dict(c=1e-29, m=0.5, threshold=5e6, toughness=80e6), "custom.m"),
    (dict(c=-1.0, m=3.0, threshold=5e6, toughness=80e6), "custom.c"),
    (dict(c=1e-29, m=3.0, threshold=5.0, toughness=80e6), "custom.threshold"),
    (dict(c=1e-29, m=3.0, threshold=5e6, toughness=math.inf), "custom.toughness"),
    (dict(c=1e-29, m=3.0, threshold=20e6, toughness=10e6), "custom.toughness"),
])
def test_bad_constants_refused_in_one_line(kwargs: dict, name: str) -> None:
    with pytest.raises(InputError) as err:
        ParisLaw(**kwargs)
    msg = str(err.value)
    assert msg.startswith(name) and "\n" not in msg


def test_bad_life_requests_refused() -> None:
    law = ParisLaw.from_mpa(1e-11, 3.0, 5.0, 80.0)
    with pytest.raises(InputError, match="a_limit"):
        paris_life(law, dk_const, A0, A0)
    with pytest.raises(InputError, match="a0"):
        paris_life(law, dk_const, 0.0, 1.0)
    with pytest.raises(InputError, match="delta_k"):
        paris_life(law, lambda a: math.nan, A0, 1.0)
    with pytest.raises(InputError, match="steel_class"):
        steel_class_law("bronze", threshold=5e6, toughness=80e6)


def test_steel_class_table_has_sources() -> None:
    for c, m, src in STEEL_CLASSES.values():
        assert c > 0 and 2.0 <= m <= 4.0 and "Barsom" in src
