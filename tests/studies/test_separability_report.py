"""The separability report of a labelled table: the healthy class is the reference, the
operating point is not an indicator, and the channels of one file share a fold. Checked
against scikit-learn's own roc_auc_score and a grouped cross-validation done by hand."""

import json
import sys

import numpy as np
import pytest
from sklearn.linear_model import LogisticRegression
from sklearn.metrics import accuracy_score, roc_auc_score
from sklearn.model_selection import StratifiedGroupKFold, StratifiedKFold, cross_val_predict
from sklearn.pipeline import make_pipeline
from sklearn.preprocessing import StandardScaler

from gearsim import cli
from gearsim.errors import InputError
from gearsim.studies import diagnostic
from gearsim.studies.batch import run_batch
from gearsim.studies.diagnostic import CLASSES, FAULT_CLASSES, separability_report


def _table(labels, seed=0):
    """A feature rising with the fault, one falling, and noise (20 rows)."""
    rng = np.random.default_rng(seed)
    y = np.array(labels * 10)
    fault = (y == labels[1]).astype(float) if labels[0] in ("healthy", "h", "normal") \
        else (y == labels[0]).astype(float)
    return y, fault, {"rises": fault + rng.normal(0, 0.6, y.size),
                      "falls": -fault + rng.normal(0, 0.8, y.size),  # not all > 0: not logged
                      "noise": rng.normal(0, 1, y.size)}


@pytest.mark.parametrize("labels, faulty", [(["healthy", "faulty"], "faulty"),
                                            (["h", "b"], "b"), (["normal", "worn"], "worn")])
def test_the_healthy_label_is_the_reference_and_auc_reads_for_the_fault(labels, faulty):
    # before: the second label in sorted order was the positive class, "healthy" for the
    # README's own '^(healthy|faulty)_' and "h" for h/b: every direction backwards
    y, fault, cols = _table(labels)
    rep = separability_report(cols, y, folds=2)
    assert rep["positive"] == faulty and rep["reference"] != faulty
    assert rep["reference_reason"] == "names a healthy state"
    rows = {r["indicator"]: r for r in rep["indicators"]}
    for name, direction in (("rises", "higher"), ("falls", "lower")):
        a = roc_auc_score(fault, cols[name])  # sklearn: P(faulty row > healthy row)
        assert rows[name]["class"] == faulty and rows[name]["direction"] == direction
        assert rows[name]["auc"] == pytest.approx(max(a, 1 - a), abs=1e-12)


def test_no_healthy_label_first_in_order_said_and_named_by_the_user():
    y, _, cols = _table(["worn", "chipped"])
    rep = separability_report(cols, y, folds=2)
    assert (rep["reference"], rep["positive"]) == ("chipped", "worn")
    assert rep["reference_reason"].startswith("first in sorted order: no label names")
    rep = separability_report(cols, y, folds=2, healthy="worn")
    assert (rep["reference"], rep["positive"]) == ("worn", "chipped")
    assert rep["reference_reason"] == "given (--healthy)"
    with pytest.raises(InputError, match=r"^--healthy = ok: is not a label of the rows "
                                         r"\(chipped, worn\)$"):
        separability_report(cols, y, healthy="ok")
    # two labels naming a healthy state: neither is guessed
    assert diagnostic.reference_class(["h", "n"])[1].startswith("first in sorted order: several")


def test_the_sweep_classes_keep_healthy_as_reference():
    for order in (CLASSES, FAULT_CLASSES):
        assert diagnostic.reference_class(sorted(order)) == ("none", "names a healthy state")
    assert diagnostic.reference_class(sorted(["working", "non-working"]))[0] == "non-working"


def test_operating_point_columns_are_left_out_of_the_table_and_the_classifier():
    # the speed separates the two sets perfectly (recorded at different speeds), the
    # condition indicator only partly: before, shaft_frequency_hz and the mesh
    # frequencies led the table with AUC 1 and fed the classifier
    y, fault, cols = _table(["healthy", "faulty"])
    speed = 29.0 + fault + np.linspace(0, 0.01, y.size)
    kin = {"shaft_frequency_hz": speed, "mesh_frequency_hz": 32 * speed,
           "stage2_mesh_frequency_hz": 32 / 80 * 48 * speed,
           "demodulation_carrier_frequency": 32 * speed, "n_averages": 10 + fault}
    rep = separability_report({**cols, **kin}, y, folds=2)
    assert {r["indicator"] for r in rep["indicators"]} == set(cols)
    assert {r["indicator"] for r in rep["left_out"]} == set(kin)
    assert rep["classifier"]["features"] == sorted(cols)
    # the classifier's numbers are those of sklearn on the three indicators alone
    x = np.column_stack([cols[k] for k in sorted(cols)])
    model = make_pipeline(StandardScaler(), LogisticRegression(max_iter=5000))
    p = cross_val_predict(model, x, y, cv=StratifiedKFold(2, shuffle=True, random_state=0),
                          method="predict_proba")  # classes sorted: faulty, healthy
    assert rep["classifier"]["auc"] == pytest.approx(roc_auc_score(y == "faulty", p[:, 0]))


def _grouped_table():
    """10 files x 4 channels; the label is drawn per file and no feature carries it, but
    the channels of a file share the file's 10 offsets: rows of one file are near twins."""
    rng = np.random.default_rng(1)
    files = np.repeat([f"f{i}" for i in range(10)], 4)
    y = np.repeat(np.array(["b", "h"] * 5)[rng.permutation(10)], 4)
    x = np.repeat(rng.normal(0, 1, (10, 10)), 4, axis=0) + rng.normal(0, 0.05, (40, 10))
    return files, y, {f"x{j}": x[:, j] for j in range(10)}, x


def test_the_channels_of_a_file_stay_in_one_fold():
    # before: folds split rows, so a file's twin channels sat in training and test alike
    files, y, cols, x = _grouped_table()
    rep = separability_report(cols, y, groups=files, group_name="file")
    c = rep["classifier"]
    assert c["grouped_by"] == "file" and c["folds"] == 5
    model = make_pipeline(StandardScaler(), LogisticRegression(max_iter=5000))
    p = cross_val_predict(model, x, y, groups=files, method="predict_proba",
                          cv=StratifiedGroupKFold(5, shuffle=True, random_state=0))
    assert c["accuracy"] == pytest.approx(accuracy_score(y, np.array(["b", "h"])[p.argmax(1)]))
    assert c["auc"] == pytest.approx(roc_auc_score(y == "b", p[:, 0]))
    # no feature carries the label: grouped, about chance (0.4 here); split by row, a
    # file's twin rows in training gave every answer
    assert c["accuracy"] < 0.8
    q = cross_val_predict(model, x, y, method="predict_proba",
                          cv=StratifiedKFold(5, shuffle=True, random_state=0))
    assert accuracy_score(y, np.array(["b", "h"])[q.argmax(1)]) == 1.0
    # one row per group: the plain stratified folds, said so
    one = separability_report(cols, y, groups=[str(i) for i in range(40)])
    assert one["classifier"]["grouped_by"] is None
    assert one["classifier"]["accuracy"] == 1.0


def _signal(rng, impacted, n=4000, fs=5000.0):
    x = np.sin(2 * np.pi * 300 * np.arange(n) / fs) + 0.2 * rng.standard_normal(n)
    if impacted:
        x[::250] += 4.0
    return x


def _files(folder, n=6, channels=3):
    rng = np.random.default_rng(0)
    for i in range(n):
        kind = "faulty" if i % 2 else "healthy"
        cols = np.column_stack([_signal(rng, kind == "faulty") for _ in range(channels)])
        (folder / f"{kind}_{i}.csv").write_text(
            "# fs = 5000\n" + ",".join(f"a{j}" for j in range(channels)) + "\n" + "\n".join(
                ",".join(f"{v:.6g}" for v in row) for row in cols) + "\n")


def test_batch_report_grouped_by_file_healthy_reference(tmp_path):
    _files(tmp_path)
    ds = run_batch([str(tmp_path / "*.csv")], label_pattern=r"^(healthy|faulty)_",
                   teeth=[32], speed=30.0)
    rep = json.loads(ds.attrs["separability"])
    assert (rep["reference"], rep["positive"]) == ("healthy", "faulty")
    assert rep["classifier"]["grouped_by"] == "file" and rep["classifier"]["folds"] == 3
    assert "shaft_frequency_hz" in {r["indicator"] for r in rep["left_out"]}
    top = {r["indicator"]: r for r in rep["indicators"]}
    k = np.asarray(ds["kurtosis"].values)
    assert top["kurtosis"]["direction"] == "higher"
    assert top["kurtosis"]["auc"] == pytest.approx(
        roc_auc_score(ds["label"].values == "faulty", k))
    with pytest.raises(InputError, match=r"^healthy = normal: is not a label of the rows "
                                         r"\(faulty, healthy\)$"):
        run_batch([str(tmp_path / "*.csv")], label_pattern=r"^(healthy|faulty)_",
                  healthy="normal")


def _run(monkeypatch, capsys, *args):
    monkeypatch.setattr(sys, "argv", ["gearsim", *map(str, args)])
    code = 0
    try:
        cli.main()
    except SystemExit as exc:
        code = exc.code
    out = capsys.readouterr()
    return code, out.out, out.err


def test_cli_healthy_option(tmp_path, monkeypatch, capsys):
    _files(tmp_path, n=4, channels=2)
    glob = tmp_path / "*.csv"
    code, _, err = _run(monkeypatch, capsys, "analyze", glob, "--label-pattern",
                        r"^(healthy|faulty)_", "--healthy", "normal", "--out",
                        tmp_path / "t.csv")
    assert code == 2
    assert err.strip() == ("gearsim: error: --healthy = normal: is not a label of the rows "
                           "(faulty, healthy)")
    assert not (tmp_path / "t.csv.parts").exists()  # refused before any file was read
    code, _, err = _run(monkeypatch, capsys, "analyze", glob, "--healthy", "healthy")
    assert code == 2 and err.strip() == ("gearsim: error: --healthy = healthy: needs "
                                         "--labels or --label-pattern")
    code, out, err = _run(monkeypatch, capsys, "analyze", glob, "--label-pattern",
                          r"^(healthy|faulty)_", "--healthy", "faulty")
    assert code == 0, err
    assert "AUC of healthy against faulty (reference faulty: given (--healthy))" in out
    assert "2-fold CV grouped by file" in out
