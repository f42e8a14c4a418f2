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
#: curves, healthy and cracked (19/48, 1 mm crack): measured within 1.9 % at 20 positions
#: per cycle, within 1.8 % at CRACKED_POSITIONS; the issue's target is 5 %.
TARGET = 5.0
#: FE pair positions per mesh cycle of the cracked 19/48 checks (the study's default is
#: 20). A cracked table costs five FE pair models (healthy and the four pair labels of
#: the cracked tooth) times these positions: ~45 s of CPU at 20, ~25 s at 10 (cold
#: cache). At 10 both curves are still compared at the same 40 positions, which sample
#: both contact zones of every cycle (u < eps_alpha - 1 = 0.646: 7 positions in double
#: contact, 3 in single) and both transitions. Measured at 10, fe_tooth against the FE
#: pair, max/min/mean: +1.4/+1.0/-1.8 % working, +1.4/+0.5/-1.7 % non-working (at 20:
#: +1.4/+0.4/-1.9 % and +1.4/-0.0/-1.9 %); the crack's largest drop in cycles 0-1 is
#: 5.7 % working and 0.41 % non-working, as at 20 (it sits on the 10-point grid), and
#: at most 0.03 % in the cycle before.
CRACKED_POSITIONS = 10


@pytest.fixture(scope="module")
def healthy_spur(spur):
    """The healthy 19/48 section at CRACKED_POSITIONS, shared by the cracked checks."""
    return fe_pair_check(spur, 0, positions_per_cycle=CRACKED_POSITIONS)


@pytest.mark.parametrize("crack", ["working", "non-working"])
def test_cracked_section_meets_the_target_with_the_fe_tooth(spur, healthy_spur, crack):
    chk = fe_pair_check(spur, 0, crack=crack, positions_per_cycle=CRACKED_POSITIONS)
    assert chk.cycles.size == 4 * CRACKED_POSITIONS
    for value in chk.differences("fe_tooth").values():
        assert abs(value) < TARGET
    # the crack shows in the FE pair where the cracked tooth is engaged (cycles 0, 1)
    np.testing.assert_array_equal(healthy_spur.cycles, chk.cycles)
    drop = 1 - chk.k_fe / healthy_spur.k_fe
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


#: gearsim's default model (calibrated PE tooth, 2D line contact, FE coupling) against the
#: FE pair inside the zones of the Table-1 section: the issue's target (issue 25, 3 %).
DEFAULT_TARGET = 0.03


def test_default_model_curve_within_target_inside_the_zones(check, table1):
    """The default model on the Table-1 mesh I transverse section: within 3 % of the FE
    gear pair inside both contact zones (away from the transitions, where the loaded FE
    pair touches outside the nominal path), and far closer than the seed's method."""
    eps = table1.pairs[0].transverse_contact_ratio
    u = np.mod(check.cycles, 1.0)
    inside = ((u > 0.1) & (u < eps - 1 - 0.1)) | ((u > eps - 1 + 0.1) & (u < 0.9))
    rel = check.curves["accurate"][inside] / check.k_fe[inside] - 1
    assert np.all(np.abs(rel) < DEFAULT_TARGET), rel
    seed = check.curves["pe"][inside] / check.k_fe[inside] - 1
    assert np.min(np.abs(seed)) > 3 * np.max(np.abs(rel))


def test_differences_and_summary(check):
    d = check.differences("pe")
    assert set(d) == {"max", "min", "mean"}
    assert d["mean"] > 10  # the seed's PE options are the stiffer (docs/stiffness.md 4b)
    summary = check.to_dict()
    assert set(summary["differences_percent"]) == set(CURVES)
    assert len(summary["k_fe_pair_N_per_m"]) == check.cycles.size
