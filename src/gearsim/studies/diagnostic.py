"""Diagnostic value of vibration features: separability of the fault classes of a
parameter-study store.

The classes are the store's ``fault`` coordinate when it has one (a study that varies
the fault class, :data:`gearsim.model.variants.FAULT_CLASSES`: healthy, root crack on the
working or non-working flank, spall, pitting, chipped tip, broken tooth, pitch error,
eccentricity), else its ``flank`` coordinate (healthy, working-flank and
non-working-flank crack). For each feature group (time-domain, sideband, STFT band
energy, TSA indicators, all together) and each subset of the store (per noise level with
every depth or severity pooled, and per noise level and crack depth or severity) a
multinomial logistic regression on standardised features is scored by stratified k-fold
cross-validation grouped by simulation (:func:`simulation_groups`: the cases of one
simulated record, its noise realisations and the healthy record shared by every nominal
depth or severity, stay in one fold, so no record is predicted by a model trained on a
noisy copy of itself): accuracy (chance 1 / number of classes), the macro-averaged
one-vs-rest ROC AUC (chance 0.5) of the out-of-fold probabilities, and the confusion
matrix of the out-of-fold predictions (rows: true class, columns: predicted class).

References
----------
Pedregosa, F. et al. (2011). Scikit-learn: machine learning in Python. *JMLR* 12,
2825-2830 (``LogisticRegression``, ``StandardScaler``, ``StratifiedKFold``,
``StratifiedGroupKFold``).
Hastie, T., Tibshirani, R. & Friedman, J. (2009). *The Elements of Statistical
Learning*, 2nd ed., Springer: sec. 4.4 (logistic regression), sec. 7.10 (cross-validation).
Fawcett, T. (2006). An introduction to ROC analysis. *Pattern Recognit. Lett.* 27,
861-874 (AUC, confusion matrix); Hand, D. J. & Till, R. J. (2001). *Mach. Learn.* 45,
171-186 (multi-class).
"""

from __future__ import annotations

import json
import math
import re
import warnings
from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np

from gearsim._version import __version__
from gearsim.errors import InputError, require
from gearsim.io.targets import atomic_folder, check_output_folder
from gearsim.model.variants import FAULT_CLASSES
from gearsim.studies.sweep import simulation_params
from gearsim.studies.sweep_case import FEATURE_GROUPS
from gearsim.viz import save
from gearsim.viz.sweep import plot_diagnostic

__all__ = ["CLASSES", "FAULT_CLASSES", "FOLDS", "REPORT_NAMES", "STORE_ATTRS", "STORE_VARIABLES",
           "HEALTHY_LABELS", "class_labels", "columns_matrix", "diagnostic_report",
           "feature_matrix", "indicator_auc", "not_indicators", "open_store",
           "reference_class", "require_simulations", "separability", "separability_report",
           "separability_table", "simulation_groups"]

#: The files of a separability report (its folder holds these only).
REPORT_NAMES = ("separability.csv", "separability.json", "separability.png")

#: Class labels of a store without faults: its ``flank`` coordinate.
CLASSES = ("none", "working", "non-working")
#: Folds of the stratified cross-validation (at most: fewer where a class has fewer
#: simulations, or rows, than this).
FOLDS = 5
#: How the diagnostic report's folds are grouped, and why (the JSON's ``grouped_by``,
#: ``method``).
SIMULATION_GROUPS = ("the cases of one simulated record stay in one fold: its noise "
                     "realisations, and a healthy record's every nominal depth or severity")
#: Labels that name a healthy state (whole label, any case): such a label is the reference
#: (negative) class of a separability report, the other class the positive one, so an
#: AUC's direction reads as "the faulty rows have the higher (lower) values". Kept
#: short: a label not in this list (``faulty``, ``low``, ``a``) is never guessed healthy.
HEALTHY_LABELS = ("healthy", "normal", "good", "ok", "baseline", "reference", "nominal",
                  "intact", "undamaged", "fault-free", "none", "h", "n")
#: Columns that describe the operating point or the record, not the machine's condition
#: (name pattern, why): they would separate sets recorded at different speeds, loads or
#: lengths, so they are neither scored nor given to the classifier.
NOT_INDICATORS = (
    (r"(?:^|_)(?:shaft|mesh|carrier)_frequency(?:_hz|_cps)?$|(?:^|_)planet_pass(?:_hz)?$",
     "kinematics: speed times tooth counts (the operating point)"),
    (r"(?:^|_)(?:speed|rpm|torque|load)(?:_|$)", "the operating point"),
    (r"(?:^|_)(?:n_samples|n_averages|n_revolutions|n_revs|duration|fs|sampling_rate)(?:_|$)",
     "the record (its length, rate or number of averages)"),
)
#: Variables and attributes every store of :func:`gearsim.studies.sweep_run.run_study` has.
STORE_VARIABLES = ("case", "status", "flank", "noise", "crack_depth")
STORE_ATTRS = ("study", "n_cases")


def class_labels(ds) -> tuple[str, tuple[str, ...]]:
    """Which coordinate of a store holds the classes, and their order.

    Parameters
    ----------
    ds : xarray.Dataset
        A sweep store (or a subset of its cases).

    Returns
    -------
    coordinate : str
        ``"fault"`` when the store has that coordinate (a study that varies the fault
        class), else ``"flank"``.
    classes : tuple of str
        Every class of that coordinate in report order: :data:`FAULT_CLASSES` or
        :data:`CLASSES`.

    Examples
    --------
    >>> import xarray as xr
    >>> class_labels(xr.Dataset(coords={"flank": ("case", ["none", "working"])}))
    ('flank', ('none', 'working', 'non-working'))
    """
    if "fault" in ds.variables:
        return "fault", FAULT_CLASSES
    return "flank", CLASSES


def feature_matrix(ds, group: str) -> tuple[np.ndarray, list[str]]:
    """Features of one group (``"all"`` or a value of :data:`FEATURE_GROUPS`) as a matrix.

    Columns with a NaN or without variance in ``ds`` are dropped; a column whose values
    are all > 0 is replaced by its logarithm (amplitudes, energies and moment ratios span
    decades; the log makes their spread closer to normal for the logistic model).

    Parameters
    ----------
    ds : xarray.Dataset
        A sweep store or a subset of its cases; features are the float variables along
        ``case`` whose name starts with a prefix of :data:`FEATURE_GROUPS` (after the
        ``stage{k}_`` of a compound train's further stages).
    group : str
        ``"all"`` or a feature group (``"time-domain"``, ``"sideband"``, ``"TSA"``,
        ``"band energy"``).

    Returns
    -------
    x : ndarray, shape (n_cases, n_kept)
        Feature matrix (empty second axis when no column is kept).
    names : list of str
        Names of the kept columns, sorted.
    """
    def group_of(name: str) -> str | None:  # a compound train's stage{k}_ names too
        base = re.sub(r"^stage\d+_", "", name)
        return next((g for p, g in FEATURE_GROUPS.items() if base.startswith(p)), None)

    names = [v for v in ds.data_vars if ds[v].dims == ("case",) and ds[v].dtype.kind == "f"
             and (g := group_of(str(v))) is not None and group in ("all", g)]
    x, kept = columns_matrix({v: ds[v].values for v in names})
    if not kept:
        return np.empty((ds.sizes["case"], 0)), []
    return x, kept


def columns_matrix(columns: Mapping[str, Sequence[float]]) -> tuple[np.ndarray, list[str]]:
    """Feature columns of any table as a matrix for :func:`separability`.

    Columns with a NaN (or None) or without variance are dropped; a column whose values
    are all > 0 is replaced by its logarithm (amplitudes, energies and moment ratios span
    decades; the log makes their spread closer to normal for the logistic model).

    Parameters
    ----------
    columns : mapping of str to sequence of float
        Column name to values (one per row, all of the same length).

    Returns
    -------
    x : ndarray, shape (n_rows, n_kept)
        Feature matrix (empty second axis when no column is kept).
    names : list of str
        Names of the kept columns, sorted.
    """
    n = len(next(iter(columns.values()))) if columns else 0
    cols, kept = [], []
    for v in sorted(columns):
        x = np.asarray([np.nan if c is None else c for c in columns[v]], dtype=float)
        if x.size == 0 or not np.all(np.isfinite(x)) or np.ptp(x) == 0:
            continue
        cols.append(np.log(x) if np.all(x > 0) else x)
        kept.append(v)
    if not cols:
        return np.empty((n, 0)), []
    return np.column_stack(cols), kept


def reference_class(classes: Sequence[str], healthy: str | None = None,
                    parameter: str = "--healthy") -> tuple[str, str]:
    """The reference (negative) class of a separability report and why.

    Parameters
    ----------
    classes : sequence of str
        The classes, sorted.
    healthy : str, optional
        The class the user names healthy.
    parameter : str
        Name of the option giving ``healthy``, for messages.

    Returns
    -------
    reference : str
        ``healthy`` when given; else the one class that names a healthy state
        (:data:`HEALTHY_LABELS`); else the first class.
    why : str
        How it was chosen, for the report.

    Raises
    ------
    InputError
        ``healthy`` is not one of ``classes``.

    Examples
    --------
    >>> reference_class(["b", "h"])
    ('h', 'names a healthy state')
    >>> reference_class(["faulty", "worn"])[0]
    'faulty'
    """
    classes = [str(c) for c in classes]
    if healthy is not None:
        require(healthy in classes, parameter, healthy, "is not a label of the rows ("
                + ", ".join(classes) + ")")
        return healthy, f"given ({parameter})"
    named = [c for c in classes if c.strip().lower() in HEALTHY_LABELS]
    if len(named) == 1:
        return named[0], "names a healthy state"
    return classes[0], ("first in sorted order: " + (
        f"several labels name a healthy state ({', '.join(named)})" if named else
        "no label names a healthy state") + f"; name it with {parameter}")


def not_indicators(names: Sequence[str]) -> dict[str, str]:
    """The columns of ``names`` that are not condition indicators, and why.

    Parameters
    ----------
    names : sequence of str
        Column names.

    Returns
    -------
    dict of str to str
        Name to reason (:data:`NOT_INDICATORS`), in the order of ``names``.

    Examples
    --------
    >>> list(not_indicators(["rms", "mesh_frequency_hz", "stage2_n_averages"]))
    ['mesh_frequency_hz', 'stage2_n_averages']
    """
    out = {}
    for n in names:
        why = next((w for p, w in NOT_INDICATORS if re.search(p, str(n).lower())), None)
        if why is not None:
            out[str(n)] = why
    return out


def indicator_auc(x: np.ndarray, positive: np.ndarray) -> dict[str, float | str | None]:
    """ROC AUC of one indicator for one class against the rest, and its direction.

    Parameters
    ----------
    x : ndarray, shape (n,)
        Indicator values (finite).
    positive : ndarray of bool, shape (n,)
        Members of the class.

    Returns
    -------
    dict
        ``auc`` = max(A, 1 - A) with A the AUC of "larger value means the class"
        (0.5 chance, 1 perfect separation), ``direction`` ``"higher"`` or ``"lower"``
        (the class has the higher or lower values), ``raw_auc`` = A; None values when
        one side is empty.

    References
    ----------
    Fawcett (2006): the AUC is the probability that a random member of the class has a
    larger value than a random non-member (ties count half).
    """
    x = np.asarray(x, dtype=float)
    pos = np.asarray(positive, dtype=bool)
    n1, n0 = int(pos.sum()), int((~pos).sum())
    if n1 == 0 or n0 == 0:
        return {"auc": None, "direction": None, "raw_auc": None}
    order = np.argsort(x, kind="mergesort")
    ranks = np.empty(x.size)
    xs = x[order]
    # mid-ranks of ties (Mann-Whitney U)
    i = 0
    while i < xs.size:
        j = i
        while j + 1 < xs.size and xs[j + 1] == xs[i]:
            j += 1
        ranks[order[i:j + 1]] = 0.5 * (i + j) + 1.0
        i = j + 1
    a = float((ranks[pos].sum() - n1 * (n1 + 1) / 2.0) / (n1 * n0))
    return {"auc": max(a, 1.0 - a), "direction": "higher" if a >= 0.5 else "lower",
            "raw_auc": a}


def separability_report(columns: Mapping[str, Sequence[float]], labels: Sequence[str], *,
                        folds: int = FOLDS, seed: int = 0, healthy: str | None = None,
                        groups: Sequence[str] | None = None, group_name: str = "group",
                        parameter: str = "--healthy") -> dict:
    """Separability of labelled rows of any feature table: per indicator and all together.

    Columns that describe the operating point or the record (:func:`not_indicators`:
    shaft and mesh frequencies, speeds, sample counts) are left out of both.

    Parameters
    ----------
    columns : mapping of str to sequence of float
        Indicator name to values, one per row (None or NaN where missing).
    labels : sequence of str
        Class of each row.
    folds : int
        Stratified folds of the cross-validated classifier (:func:`separability`).
    seed : int
        Seed of the fold shuffle.
    healthy : str, optional
        The reference class (:func:`reference_class`; default: the one label naming a
        healthy state, else the first in sorted order).
    groups : sequence of str, optional
        Group of each row (the source file): the rows of a group stay in one fold.
    group_name : str
        What a group is, for the method text (``"file"``).
    parameter : str
        Name of the option giving ``healthy``, for messages.

    Returns
    -------
    dict
        ``classes`` (sorted), ``counts``, ``reference`` and ``reference_reason``
        (:func:`reference_class`), ``positive`` (with two classes the other one, scored
        against the reference; else None), ``indicators``: rows ``{indicator, class,
        auc, direction, n}`` sorted by decreasing AUC (with three or more classes, one
        row per class against the rest), ``left_out``: rows ``{indicator, reason}``,
        ``classifier``: ``{accuracy, auc, n, n_features, features, folds, grouped_by,
        method}`` of a logistic regression on every complete indicator together.

    Raises
    ------
    InputError
        Fewer than two classes, labels or groups of another length than the columns, or
        a ``healthy`` that is not a class.
    """
    y = np.asarray([str(v) for v in labels])
    classes, counts = np.unique(y, return_counts=True)
    if classes.size < 2:
        raise InputError("labels", ", ".join(classes) or "none",
                         "need at least two classes to score separability")
    for k, v in {**columns, **({"groups": groups} if groups is not None else {})}.items():
        if len(v) != y.size:
            raise InputError(f"column {k}", f"{len(v)} values", f"must have {y.size} (one "
                             "per label)")
    reference, why = reference_class(list(classes), healthy, parameter)
    positive = next(str(c) for c in classes if c != reference) if classes.size == 2 else None
    left = not_indicators(list(columns))
    columns = {k: v for k, v in columns.items() if k not in left}
    targets = [positive] if positive is not None else list(classes)
    rows = []
    for name in sorted(columns):
        x = np.asarray([np.nan if c is None else c for c in columns[name]], dtype=float)
        ok = np.isfinite(x)
        if ok.sum() < 2:
            continue
        for cls in targets:
            r = indicator_auc(x[ok], y[ok] == cls)
            if r["auc"] is None:
                continue
            rows.append({"indicator": name, "class": str(cls), "auc": r["auc"],
                         "direction": r["direction"], "n": int(ok.sum())})
    rows.sort(key=lambda r: (-r["auc"], r["indicator"], r["class"]))
    x, names = columns_matrix(columns)
    g = None if groups is None else np.asarray([str(v) for v in groups])
    if g is not None and np.unique(g).size == g.size:
        g = None  # one row per group: the plain stratified folds
    cv = separability(x, y, folds=folds, seed=seed, groups=g)
    return {
        "classes": [str(c) for c in classes],
        "counts": {str(c): int(n) for c, n in zip(classes, counts, strict=True)},
        "reference": reference, "reference_reason": why, "positive": positive,
        "indicators": rows,
        "left_out": [{"indicator": k, "reason": v} for k, v in sorted(left.items())],
        "classifier": {**cv, "n_features": len(names), "features": names,
                       "grouped_by": None if g is None else group_name,
                       "method": "StandardScaler + LogisticRegression, stratified "
                                 + ("" if g is None else f"grouped (every {group_name}'s "
                                    "rows in one fold) ") + f"{folds}-fold CV (fewer if a "
                                 f"class has fewer {'rows' if g is None else group_name + 's'}"
                                 "); accuracy and ROC AUC of out-of-fold predictions"},
    }


def separability(x: np.ndarray, y: np.ndarray, *, folds: int = FOLDS, seed: int = 0,
                 classes: Sequence[str] | None = None,
                 groups: Sequence[str] | None = None) -> dict:
    """Cross-validated accuracy, macro one-vs-rest ROC AUC and confusion matrix of a
    logistic regression.

    Parameters
    ----------
    x : ndarray, shape (n, p)
        Features.
    y : ndarray, shape (n,)
        Class labels (strings).
    folds : int
        Stratified folds (shuffled with ``seed``); fewer if a class has fewer members
        (fewer groups with ``groups``).
    seed : int
        Seed of the fold shuffle.
    classes : sequence of str, optional
        Order of the rows and columns of the confusion matrix (classes absent from
        ``y`` give rows of zeros); default: no confusion matrix.
    groups : sequence of str, optional
        Group of each row (a source file, a simulation): every group's rows stay in one fold
        (``StratifiedGroupKFold``), so no row is predicted by a model trained on another
        row of its group.

    Returns
    -------
    dict
        ``accuracy`` (fraction of correct out-of-fold predictions), ``auc`` (mean over
        classes of the one-vs-rest AUC, Hand & Till 2001 style macro average), ``n``,
        ``folds`` (the folds used);
        with ``classes`` also ``confusion``: list of rows of counts, ``confusion[i][j]``
        = the cases of true class ``classes[i]`` predicted as ``classes[j]`` out of
        fold (``sklearn.metrics.confusion_matrix``), so row ``i`` sums to the count of
        class ``classes[i]``; ``None`` when no classifier could be scored.

    References
    ----------
    Hastie et al. (2009) secs. 4.4, 7.10; Fawcett (2006).

    Examples
    --------
    >>> import numpy as np
    >>> y = np.array(["a", "b"] * 10)
    >>> x = (y == "b").astype(float)[:, None] + np.linspace(0, 0.1, 20)[:, None]
    >>> r = separability(x, y, classes=["a", "b"])
    >>> r["accuracy"], r["confusion"]
    (1.0, [[10, 0], [0, 10]])
    """
    from sklearn.linear_model import LogisticRegression
    from sklearn.metrics import accuracy_score, confusion_matrix, roc_auc_score
    from sklearn.model_selection import StratifiedGroupKFold, StratifiedKFold, cross_val_predict
    from sklearn.pipeline import make_pipeline
    from sklearn.preprocessing import StandardScaler

    labels, counts = np.unique(y, return_counts=True)
    if groups is not None:  # every fold must hold every class: count a class's groups
        groups = np.asarray(groups)
        counts = np.array([np.unique(groups[y == c]).size for c in labels])
    folds = min(folds, int(counts.min()))  # every fold must hold every class
    if labels.size < 2 or folds < 2 or x.shape[1] == 0:
        out = {"accuracy": math.nan, "auc": math.nan, "n": int(y.size), "folds": folds}
        return out if classes is None else {**out, "confusion": None}
    model = make_pipeline(StandardScaler(), LogisticRegression(max_iter=5000))
    kind = StratifiedKFold if groups is None else StratifiedGroupKFold
    cv = kind(n_splits=folds, shuffle=True, random_state=seed)
    proba = cross_val_predict(model, x, y, cv=cv, groups=groups, method="predict_proba")
    pred = labels[np.argmax(proba, axis=1)]
    if labels.size == 2:
        auc = roc_auc_score(y == labels[1], proba[:, 1])
    else:
        auc = roc_auc_score(y, proba, multi_class="ovr", average="macro", labels=labels)
    out = {"accuracy": float(accuracy_score(y, pred)), "auc": float(auc), "n": int(y.size),
           "folds": folds}
    if classes is not None:
        out["confusion"] = confusion_matrix(y, pred, labels=list(classes)).tolist()
    return out


def simulation_groups(ds) -> np.ndarray:
    """The simulated record of each case of a store: cases of equal number share one.

    A case's simulation is given by its parameters (the store's coordinates along
    ``case``) other than its noise level and noise realisation (``replicate``), with the
    crack depth of an uncracked case and the severity and gear of a healthy one not
    counted (:func:`gearsim.studies.sweep.simulation_params`): the rule by which
    :func:`gearsim.studies.sweep_run.run_study` simulates each group once
    (:meth:`gearsim.studies.sweep.Study.simulation_key`).

    Parameters
    ----------
    ds : xarray.Dataset
        A sweep store or a subset of its cases.

    Returns
    -------
    ndarray of int, shape (n_cases,)
        Simulation number of each case (0, 1, ... in sorted order of the parameters).

    Examples
    --------
    >>> import xarray as xr
    >>> ds = xr.Dataset(coords={"flank": ("case", ["none", "none", "working", "working"]),
    ...                         "crack_depth": ("case", [1e-3, 2e-3, 1e-3, 2e-3]),
    ...                         "noise": ("case", [0.0, 0.1, 0.0, 0.1])})
    >>> simulation_groups(ds).tolist()  # one healthy record, two cracked ones
    [0, 0, 1, 2]
    """
    names = [str(c) for c in ds.coords if ds[c].dims == ("case",)
             and c not in ("case", "case_key")]
    values = {n: ds[n].values.tolist() for n in names}
    keys = [json.dumps(simulation_params({n: values[n][i] for n in names}), sort_keys=True)
            for i in range(ds.sizes["case"])]
    return np.unique(np.asarray(keys, dtype=str), return_inverse=True)[1].ravel()


def require_simulations(labels: Sequence[str], noise: Sequence[float],
                        simulations: Sequence, classes: Sequence[str], parameter: str,
                        value: str, subject: str = "") -> None:
    """Refuse a study or store whose report could score no row: the folds are grouped by
    simulation, so some noise level must have two simulations of every class.

    Parameters
    ----------
    labels, noise, simulations : sequence
        Class, noise level and simulation (any hashable key) of each case.
    classes : sequence of str
        The classes present, in report order.
    parameter, value : str
        Named in the message (``store``, ``--report``).
    subject : str
        Start of the reason (``"the study is "``).

    Raises
    ------
    InputError
        Every noise level has a class with fewer than 2 simulations.
    """
    seen: dict = {}
    for c, z, g in zip(labels, noise, simulations, strict=True):
        seen.setdefault((float(z), str(c)), set()).add(g)
    counts = {z: {c: len(seen.get((z, c), ())) for c in classes} for z, _ in seen}
    z, most = max(counts.items(), key=lambda zc: min(zc[1].values()))
    require(min(most.values()) >= 2, parameter, value, f"{subject}too small to cross-validate:"
            " the folds are grouped by simulation and every noise level has a class of < 2 "
            f"simulations (at noise {z:g}: " + ", ".join(f"{c} {n}" for c, n in most.items())
            + "; noise realisations, and a healthy case's nominal depths or severities, share "
            "one simulation); add torques or speeds")


def separability_table(ds, *, groups: Sequence[str] | None = None,
                       by_simulation: bool = True) -> list[dict]:
    """Separability of the classes per feature group, noise level and depth or severity.

    Parameters
    ----------
    ds : xarray.Dataset
        A sweep store (:func:`gearsim.studies.sweep_run.run_study`); cases whose status
        is not ``"ok"`` are left out. Classes: :func:`class_labels`.
    groups : sequence of str, optional
        Feature groups; default: every group of :data:`FEATURE_GROUPS` and ``"all"``.
    by_simulation : bool
        Group the folds by simulation (:func:`simulation_groups`; the report's way);
        ``False``: fold the cases (rows of one simulation then fall on both sides of a
        split, which inflates the scores: for comparison only).

    Returns
    -------
    list of dict
        Rows ``{group, noise, snr_db, crack_depth_mm, n, n_features, folds, accuracy,
        auc, simulations, confusion}`` for a store of flank classes, with ``severity``
        (fraction of the reference size) in place of ``crack_depth_mm`` for a store of
        fault classes; the depth or severity is ``None`` for rows that pool every depth
        or severity (healthy cases are counted at their nominal depth or severity).
        ``folds``: the folds used (:func:`separability`; < 2: not scored, accuracy and
        AUC NaN); ``simulations``: class -> its simulations in the subset.
        ``confusion``: counts of the out-of-fold predictions, rows true class, columns
        predicted, in the order of the classes present among the successful cases
        (:func:`class_labels` order); ``None`` when no classifier could be scored.
    """
    ok = ds.where(ds["status"] == "ok", drop=True) if "status" in ds else ds
    if ok.sizes.get("case", 0) == 0:
        raise InputError("store", "no successful cases", "need cases with status ok")
    groups = list(groups) if groups is not None else [*FEATURE_GROUPS.values(), "all"]
    coord, order = class_labels(ok)
    labels = np.asarray(ok[coord].values, dtype=str)
    sims = simulation_groups(ok)
    classes = [c for c in order if c in set(labels)]
    if coord == "fault":
        level, key, scale = "severity", "severity", 1.0
    else:
        level, key, scale = "crack_depth", "crack_depth_mm", 1e3
    rows = []
    noises = np.unique(ok["noise"].values)
    levels = np.unique(ok[level].values)
    for noise in noises:
        for value in (None, *levels):
            sel = ok["noise"].values == noise
            if value is not None:
                sel &= ok[level].values == value
            idx = np.flatnonzero(sel)
            sub = ok.isel(case=idx)
            y = labels[idx]
            count = {c: int(np.unique(sims[idx][y == c]).size) for c in classes}
            for g in groups:
                x, names = feature_matrix(sub, g)
                r = separability(x, y, classes=classes,
                                 groups=sims[idx] if by_simulation else None)
                rows.append({
                    "group": g, "noise": float(noise),
                    "snr_db": 0.0 - 20 * math.log10(noise) if noise > 0 else math.inf,
                    key: None if value is None else round(scale * float(value), 6),
                    "n": r["n"], "n_features": len(names), "folds": r["folds"],
                    "accuracy": r["accuracy"], "auc": r["auc"],
                    "simulations": count, "confusion": r["confusion"],
                })
    return rows


def open_store(store: str | Path, parameter: str = "store"):
    """Read a store written by :func:`gearsim.studies.sweep_run.run_study`, checked.

    Parameters
    ----------
    store : str or Path
        The NetCDF store.
    parameter : str
        Name of the argument for messages.

    Returns
    -------
    xarray.Dataset
        The store, loaded into memory.

    Raises
    ------
    InputError
        A missing file, a file that is not NetCDF, or a NetCDF file without the
        variables (:data:`STORE_VARIABLES`) and attributes (:data:`STORE_ATTRS`) of a
        sweep store.
    """
    import xarray as xr

    path = Path(store)
    if not path.exists():
        raise InputError(parameter, str(path), "file not found (run gearsim sweep first)")
    if path.is_dir():
        raise InputError(parameter, str(path), "is a folder; give the store file (.nc)")
    try:
        with xr.open_dataset(path, engine="h5netcdf") as ds:
            ds = ds.load()
    except Exception as exc:  # noqa: BLE001  (any reader failure means: not a store)
        first = (str(exc).strip().splitlines() or [type(exc).__name__])[0]
        raise InputError(parameter, str(path), "is not a sweep store (cannot be read as "
                         f"NetCDF: {first})") from None
    missing = [v for v in STORE_VARIABLES if v not in ds.variables]
    missing += [f"attribute {a}" for a in STORE_ATTRS if a not in ds.attrs]
    if missing or "case" not in ds.dims:
        raise InputError(parameter, str(path), "is not a sweep store written by gearsim "
                         "sweep (missing " + ", ".join(missing or ["dimension case"]) + ")")
    return ds


def diagnostic_report(store: str | Path, out: str | Path, *,
                      out_parameter: str = "--out") -> list[Path]:
    """Write ``separability.csv``, ``separability.json`` and ``separability.png``.

    The CSV has one row per feature group, noise level and depth or severity (pooled:
    ``all``) with the folds used, accuracy and AUC; the JSON the same rows with their
    confusion matrices (``confusion``: rows true class, columns predicted class, in the
    order of ``classes``) and each class's simulations in the row's subset
    (``simulations``), the class counts and simulations of the store, ``grouped_by``
    (``"simulation"``: the folds are grouped by simulation, :func:`simulation_groups`)
    and the method; the figure the accuracy and AUC against noise and depth or severity
    (top) and the confusion matrices of all feature groups together at each noise level
    (bottom, :func:`gearsim.viz.sweep.plot_diagnostic`).
    The folder is checked first and written as a whole
    (:func:`gearsim.io.targets.atomic_folder`): a killed run leaves an earlier report whole.

    Parameters
    ----------
    store : path
        Sweep store (NetCDF, :func:`open_store`); classes from its ``fault`` coordinate
        when present, else ``flank`` (:func:`class_labels`).
    out : path
        Output folder (replaced as a whole).
    out_parameter : str
        Name of the option giving ``out``, for messages.

    Returns
    -------
    list of Path
        CSV, JSON and PNG paths.

    Raises
    ------
    InputError
        An output folder that cannot be written, a file that is not a sweep store, no
        successful case, fewer than two classes among the successful cases, or no noise
        level with two simulations of every class among the successful cases (too few to
        cross-validate with grouped folds, :func:`require_simulations`).

    Warns
    -----
    UserWarning
        When some rows cannot be scored (a subset with fewer than two simulations of a
        class).
    """
    # a folder holding anything else, or the working folder, is refused: it is replaced
    # whole (before: sweep-report --out DIR deleted DIR's files, the store reported on too)
    out = check_output_folder(out, out_parameter, owned=REPORT_NAMES.__contains__)
    store = Path(store)
    ds = open_store(store)
    ok = ds["status"].values == "ok"
    if not ok.any():
        raise InputError("store", str(store), "has no successful case (status ok)")
    coord, order = class_labels(ds)
    labels = np.asarray(ds[coord].values[ok], dtype=str)
    present = [c for c in order if c in set(labels)]
    if len(present) < 2:
        raise InputError("store", str(store), f"has {len(present)} {coord} class"
                         f"{'es' if len(present) != 1 else ''} among its successful cases "
                         f"({', '.join(present) or 'none'}); the report compares at least two"
                         " of " + ", ".join(order))
    counts = {c: int(np.sum(labels == c)) for c in present}
    sims = simulation_groups(ds.isel(case=np.flatnonzero(ok)))
    # rows are per noise level, folds grouped by simulation: one level must have 2
    # simulations of each class
    require_simulations(labels, ds["noise"].values[ok], sims, present, "store", str(store))
    rows = separability_table(ds)
    n_na = sum(1 for r in rows if r["folds"] < 2 and r["n_features"])
    if n_na:  # subsets (a noise level, a depth) with a class of < 2 simulations: said why
        warnings.warn(f"{n_na} of {len(rows)} rows of the report are n/a (accuracy and AUC "
                      "NaN, folds < 2): their subset has < 2 simulations of a class (the folds"
                      " are grouped by simulation); add torques or speeds to score them",
                      UserWarning, stacklevel=2)
    keys = [k for k in rows[0] if k not in ("confusion", "simulations")]

    def fmt(v) -> str:
        if v is None:
            return "all"
        return f"{v:.6g}" if isinstance(v, float) else str(v)

    csv = "\n".join([",".join(keys), *(",".join(fmt(r[k]) for k in keys) for r in rows)]) + "\n"
    doc = {"store": str(store), "study": ds.attrs.get("title", ""),
           "gearsim_version": __version__, "class_coordinate": coord, "classes": present,
           "counts": counts,
           "simulations": {c: int(np.unique(sims[labels == c]).size) for c in present},
           "grouped_by": "simulation",
           "method": f"StandardScaler + LogisticRegression, stratified {FOLDS}-fold CV "
                     f"grouped by simulation ({SIMULATION_GROUPS}); fewer folds where a "
                     "class has fewer simulations in a row's subset (the row's folds; n/a "
                     "below 2); accuracy, macro one-vs-rest ROC AUC and confusion matrix of "
                     "out-of-fold predictions",
           "confusion": "rows: true class, columns: predicted class, both in the order of "
                        "classes; counts of out-of-fold predictions (a row sums to the "
                        "cases of its class in the row's subset)",
           "reference": reference_class(sorted(present))[0],
           "n_cases": int(ds.sizes["case"]), "n_ok": int(np.sum(ok)),
           "rows": [{k: (None if isinstance(v, float) and not math.isfinite(v) else v)
                     for k, v in r.items()} for r in rows]}
    fig = plot_diagnostic(rows, present, title=ds.attrs.get("title", "parameter study"),
                          method=f"stratified {FOLDS}-fold CV grouped by simulation")
    names = REPORT_NAMES
    with atomic_folder(out) as tmp:
        (tmp / names[0]).write_text(csv)
        (tmp / names[1]).write_text(json.dumps(doc, indent=2))
        save(fig, tmp / names[2])
    return [out / n for n in names]
