"""The sweep report's folds are grouped by simulation: the noise realisations of one
simulated record, and the healthy record shared by every nominal crack depth, never fall
on both sides of a split. Checked on a synthetic store whose label cannot be learnt
across simulations (every simulation's rows share their features exactly, the features
are drawn independently of the label): folding the cases, as the report did, scores
near 1 (a held-out row has its twin in the training folds), grouped folds score at
chance; both computed by hand with scikit-learn."""

from __future__ import annotations

import json

import numpy as np
import pytest
import xarray as xr
from sklearn.linear_model import LogisticRegression
from sklearn.metrics import accuracy_score, roc_auc_score
from sklearn.model_selection import StratifiedGroupKFold, StratifiedKFold, cross_val_predict
from sklearn.pipeline import make_pipeline
from sklearn.preprocessing import StandardScaler

from gearsim import cli
from gearsim.studies.diagnostic import diagnostic_report

TORQUES = np.linspace(1000.0, 4000.0, 12)
DEPTHS = (1e-3, 2e-3)
REPLICATES = 3
N_FEATURES = 48  # more than the 36 simulations: any labelling of them is separable


@pytest.fixture(scope="module", autouse=True)
def _one_blas_thread():
    from threadpoolctl import threadpool_limits

    with threadpool_limits(limits=1, user_api="blas"):
        yield


def _store(path, torques=TORQUES):
    """Healthy and working-flank cases at every torque x nominal depth x replicate, noise
    0; the features of a simulation (healthy: its torque; cracked: torque and depth)
    drawn once; returns the path, the labels, the features and the hand-made
    simulation names of the rows."""
    rng = np.random.default_rng(7)
    rows = [(f, t, d, r) for f in ("none", "working") for t in torques for d in DEPTHS
            for r in range(REPLICATES)]
    names = [f"healthy {t:g}" if f == "none" else f"crack {t:g} {d:g}" for f, t, d, _ in rows]
    draw = {n: rng.normal(size=N_FEATURES) for n in dict.fromkeys(names)}
    x = np.array([draw[n] for n in names])
    flank = np.array([r[0] for r in rows])
    ds = xr.Dataset(
        {"status": ("case", ["ok"] * len(rows)), "error": ("case", [""] * len(rows)),
         **{f"sb_x{j:02d}": ("case", x[:, j]) for j in range(N_FEATURES)}},
        coords={"case": np.arange(len(rows)), "flank": ("case", flank),
                "torque": ("case", [r[1] for r in rows]),
                "crack_depth": ("case", [r[2] for r in rows]),
                "replicate": ("case", [r[3] for r in rows]),
                "noise": ("case", np.zeros(len(rows)))},
        attrs={"title": "synthetic", "study": "[parameters]", "n_cases": len(rows)})
    ds.to_netcdf(path, engine="h5netcdf")
    return path, flank, x, np.array(names)


def _by_hand(x, y, cv, groups=None):
    model = make_pipeline(StandardScaler(), LogisticRegression(max_iter=5000))
    p = cross_val_predict(model, x, y, cv=cv, groups=groups, method="predict_proba")
    return accuracy_score(y, np.array(["none", "working"])[p.argmax(1)]), \
        roc_auc_score(y == "working", p[:, 1])


def test_simulations_of_a_store_are_the_records_simulated(tmp_path):
    from gearsim.studies.diagnostic import simulation_groups  # new: not before the fix

    path, _, _, names = _store(tmp_path / "s.nc")
    sims = simulation_groups(xr.load_dataset(path, engine="h5netcdf"))
    # the same partition as the hand-made names: 12 healthy records (shared by both
    # nominal depths and the replicates), 24 cracked ones
    assert (np.equal.outer(sims, sims) == np.equal.outer(names, names)).all()
    assert np.unique(sims).size == 12 + 24


def test_grouped_folds_score_a_label_not_learnable_across_simulations_at_chance(tmp_path):
    path, y, x, names = _store(tmp_path / "s.nc")
    # by hand: folding the cases finds each held-out row's twin (measured 1.00 / 1.00),
    # grouping them by simulation does not (measured 0.56 / 0.53; chance 0.5 / 0.5)
    acc, auc = _by_hand(x, y, StratifiedKFold(5, shuffle=True, random_state=0))
    assert acc > 0.95 and auc > 0.95
    hand_acc, hand_auc = _by_hand(x, y, StratifiedGroupKFold(5, shuffle=True, random_state=0),
                                  names)
    assert abs(hand_acc - 0.5) < 0.15 and abs(hand_auc - 0.5) < 0.15
    _, js, _ = diagnostic_report(path, tmp_path / "rep")
    doc = json.loads(js.read_text())
    row = next(r for r in doc["rows"] if r["group"] == "all" and r["crack_depth_mm"] is None)
    # before: 1.00 / 1.00 (the by-case folds); now at chance like the grouped folds by
    # hand (measured 0.48 / 0.61; the folds themselves differ: sklearn orders the groups
    # by their labels, here the hand-made names, there simulation numbers)
    assert abs(row["accuracy"] - 0.5) < 0.15 and abs(row["auc"] - 0.5) < 0.15, row
    assert doc["grouped_by"] == "simulation" and "grouped by simulation" in doc["method"]
    assert doc["simulations"] == {"none": 12, "working": 24}
    assert row["folds"] == 5 and row["n"] == 144 and row["simulations"] == doc["simulations"]
    for r in (r for r in doc["rows"] if r["group"] == "all" and r["crack_depth_mm"]):
        assert r["simulations"] == {"none": 12, "working": 12} and r["folds"] == 5
        assert abs(r["accuracy"] - 0.5) < 0.2, r


def test_a_class_of_one_simulation_is_refused_not_folded_by_case(tmp_path, capsys):
    # one healthy torque: 6 healthy rows (two nominal depths x three replicates) of one
    # record; before, the report folded them and scored 1.00
    path, *_ = _store(tmp_path / "one.nc", torques=TORQUES[:1])
    code = cli.run(["sweep-report", str(path), "--out", str(tmp_path / "rep")])
    err = capsys.readouterr().err
    assert code == 2 and err.strip().splitlines() == [
        f"gearsim: error: store = {path}: too small to cross-validate: the folds are grouped "
        "by simulation and every noise level has a class of < 2 simulations (at noise 0: "
        "none 1, working 2; noise realisations, and a healthy case's nominal depths or "
        "severities, share one simulation); add torques or speeds"]
    assert not (tmp_path / "rep").exists()


def test_cli_states_the_grouping_and_folds(tmp_path, capsys):
    path, *_ = _store(tmp_path / "s.nc", torques=TORQUES[:3])
    code = cli.run(["sweep-report", str(path), "--out", str(tmp_path / "rep")])
    out = capsys.readouterr().out
    # 3 healthy records: 3 folds
    assert code == 0 and out.splitlines()[0] == (
        "gearsim: folds grouped by simulation (none 3, working 6 simulations); 3 folds")
    csv = (tmp_path / "rep" / "separability.csv").read_text().splitlines()
    assert csv[0] == "group,noise,snr_db,crack_depth_mm,n,n_features,folds,accuracy,auc"
