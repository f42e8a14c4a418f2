"""The seed-Figure-3 check: FE gear pair against the PE curves on a transverse section."""

from __future__ import annotations

import numpy as np
import pytest

from gearsim.studies.fe_pair_check import CURVES, fe_pair_check

#: Inside the contact zones the FE tooth with line contact and coupling is the FE pair
#: within 1.2-1.8 % on 19/48 (tests/test_pe_vs_fe_pair.py); on the Table-1 section the
#: same superposition, 3 %.
ZONE_TOL = 0.03


@pytest.fixture(scope="module")
def check(table1):
    return fe_pair_check(table1, 0)


#: FE tooth + line contact + coupling against the FE pair, max / min / mean of the
#: curves, healthy and cracked (19/48, 1 mm crack): measured within 1.9 %; the issue's
#: target is 5 %.
TARGET = 5.0


@pytest.mark.parametrize("crack", ["working", "non-working"])
def test_cracked_section_meets_the_target_with_the_fe_tooth(spur, crack):
    chk = fe_pair_check(spur, 0, crack=crack)
    for value in chk.differences("fe_tooth").values():
        assert abs(value) < TARGET
    # the crack shows in the FE pair where the cracked tooth is engaged (cycles 0, 1)
    healthy = fe_pair_check(spur, 0)
    drop = 1 - chk.k_fe / healthy.k_fe
    assert drop[(chk.cycles >= 0) & (chk.cycles < 2)].max() > (0.02 if crack == "working"
                                                                else 1e-4)
    assert np.all(np.abs(drop[chk.cycles < 0]) < 0.01)


def test_section_has_the_transverse_contact_structure(check, table1):
    """The PE section drops from double to single contact at u = eps_alpha - 1 (closed
    form of the transverse section; a face-width slice would smear it over
    b tan(beta_b)), within one FE position."""
    eps = table1.pairs[0].transverse_contact_ratio
    u = np.mod(check.cycles, 1.0)
    k = check.curves["pe"]
    step = np.argmax(-np.diff(k[: 20]))  # largest drop in the first cycle
    assert abs(u[step + 1] - (eps - 1)) <= 1 / 20 + 1e-12
    assert k[step] / k[step + 1] > 1.4  # two pairs against one


def test_fe_tooth_curve_equals_the_fe_pair_inside_the_zones(check, table1):
    eps = table1.pairs[0].transverse_contact_ratio
    u = np.mod(check.cycles, 1.0)
    inside = ((u > 0.1) & (u < eps - 1 - 0.1)) | ((u > eps - 1 + 0.1) & (u < 0.9))
    assert inside.sum() >= 8
    rel = check.curves["fe_tooth"][inside] / check.k_fe[inside] - 1
    assert np.all(np.abs(rel) < ZONE_TOL), rel


def test_differences_and_summary(check):
    d = check.differences("pe")
    assert set(d) == {"max", "min", "mean"}
    assert d["mean"] > 10  # the seed's PE options are the stiffer (docs/stiffness.md 4b)
    summary = check.to_dict()
    assert set(summary["differences_percent"]) == set(CURVES)
    assert len(summary["k_fe_pair_N_per_m"]) == check.cycles.size
