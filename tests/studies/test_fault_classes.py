"""Multi-class parameter studies: the ``fault`` and ``severity`` parameters, their store,
the confusion matrices of the diagnostic report, refused input and the CLI."""

from __future__ import annotations

import json

import numpy as np
import pytest

from gearsim import cli
from gearsim.errors import InputError
from gearsim.model.variants import FAULT_CLASSES
from gearsim.studies.diagnostic import (
    diagnostic_report,
    feature_matrix,
    separability,
    simulation_groups,
)
from gearsim.studies.sweep import expand, load_study, loads_study
from gearsim.studies.sweep_case import build_case
from gearsim.studies.sweep_run import groups, parts_dir, run_serial

#: Every fault class at two severities and two torques, 0.15 s at 20 kHz (just over one
#: revolution of the output gear, 0.101 s at 1900 rpm input; the input-shaft sidebands
#: need 0.127 s, hence shafts = "reference"); 216 cases, 34 simulation groups. Its
#: expansion, grouping and case building are checked as they are; the store is run from
#: :data:`STORE_STUDY`.
STUDY = """
[study]
name = "fault classes"
config = "idler-table1"
replicates = 3
seed = 5
shafts = "reference"
[study.dynamics]
duration = "0.15 s"
fs = "20 kHz"
transient = "0.02 s"
[parameters]
fault = ["none", "working", "non-working", "spall", "pitting", "chip", "broken", "pitch",
         "eccentricity"]
severity = [0.5, 1.0]
torque = ["2000 N*m", "4876 N*m"]
noise = [0.0, 0.1]
"""


#: The study whose store the tests read: :data:`STUDY` itself, 216 cases in 34 simulation
#: groups (every class at both severities and both torques, noise-free and noisy, three
#: replicates). The store's cost is the groups, not the cases: building each group's
#: mesh tables, and for the eccentricity class the centre-distance derivative of the
#: mesh stiffness (most of the time): 45 s of CPU. Before the report's folds were grouped
#: by simulation the store was run at the rated torque alone (half the cost), but then
#: the healthy class is one simulation, too few for grouped folds.
STORE_STUDY = STUDY


@pytest.fixture(scope="module", autouse=True)
def _one_blas_thread():
    """One BLAS thread for this module's logistic regressions (the report's 30 rows of
    5-fold L-BFGS fits of a nine-class model): with ``make test``'s two test workers on
    two cores, OpenBLAS's second thread only spins, measured 29 s of CPU for the report
    of the store below against 5.7 s with one thread. The thread count changes no
    assertion: row sums and counts are exact, accuracies have their stated margins."""
    from threadpoolctl import threadpool_limits

    with threadpool_limits(limits=1, user_api="blas"):
        yield


@pytest.fixture(scope="module")
def study():
    return loads_study(STUDY)


@pytest.fixture(scope="module")
def store(tmp_path_factory):
    """:data:`STORE_STUDY` run serially, written as a store."""
    path = tmp_path_factory.mktemp("faults") / "f.nc"
    run_serial(loads_study(STORE_STUDY)).to_netcdf(path, engine="h5netcdf")
    return path


def test_cases_groups_and_store(study, store):
    import xarray as xr

    cases = expand(study)
    assert len(cases) == 9 * 2 * 2 * 2 * 3
    # healthy cases share one simulation per torque whatever their nominal severity
    assert len(groups(study)) == 8 * 2 * 2 + 2
    ds = xr.load_dataset(store, engine="h5netcdf")
    assert ds.sizes["case"] == 9 * 2 * 2 * 2 * 3 == len(cases)
    assert (ds["status"].values == "ok").all()
    assert set(ds["fault"].values) == set(FAULT_CLASSES)
    assert set(ds["torque"].values) == {2000.0, 4876.0}
    assert set(ds["severity"].values) == {0.5, 1.0} and ds["severity"].attrs["units"] == "1"
    # the crack route's coordinates are kept (store layout) but unused
    assert set(ds["flank"].values) == {"none"} and set(ds["crack_depth"].values) == {0.0}
    z = ds.where((ds.noise == 0) & (ds.fault == "none") & (ds.torque == 4876), drop=True)
    assert z.sizes["case"] == 2 * 3  # two nominal severities x three replicates
    assert np.unique(z["td_rms"].values).size == 1  # one simulation, noise-free records
    # while the noise-free records of a fault class differ between its two severities
    b = ds.where((ds.noise == 0) & (ds.fault == "broken") & (ds.torque == 4876), drop=True)
    assert np.unique(b["td_rms"].values).size == 2
    # the report's simulations are the groups simulated: 34
    assert np.unique(simulation_groups(ds)).size == len(groups(study))
    # the case's train is the fault variant; every class on the contact-mesh path
    broken = next(c for c in cases if c.fault == "broken" and c.severity == 0.5)
    gb = build_case(study, broken)
    train, settings = gb.train, gb.dynamics
    assert [(f.kind, f.gear, f.tooth) for f in train.faults] == [("broken", "input", 0)]
    assert not train.cracks and settings.contact_mesh and settings.duration == 0.15
    healthy = build_case(study, cases[0])
    assert not healthy.train.faults and not healthy.train.cracks
    assert healthy.dynamics.contact_mesh
    # a study without fault has neither coordinate, and its keys are as before
    old = loads_study(STUDY.split("[parameters]")[0] + '[parameters]\nflank = ["none", '
                      '"working"]\n')
    assert old.parameters.keys() == {"flank"}
    assert all(c.fault is None and "fault" not in c.params() for c in expand(old))


def test_report_confusion_matrices(store, tmp_path):
    csv, js, png = diagnostic_report(store, tmp_path / "rep")
    doc = json.loads(js.read_text())
    assert doc["class_coordinate"] == "fault" and doc["classes"] == list(FAULT_CLASSES)
    # 2 severities x 2 torques x 2 noise levels x 3 replicates per class
    assert doc["counts"] == {c: 24 for c in FAULT_CLASSES}
    # folds grouped by simulation: the healthy class has one per torque, so 2 folds
    assert doc["grouped_by"] == "simulation"
    assert doc["simulations"] == {c: 2 if c == "none" else 4 for c in FAULT_CLASSES}
    assert csv.read_text().startswith("group,noise,snr_db,severity,n,")
    assert png.stat().st_size > 20_000
    for r in doc["rows"]:
        m = np.asarray(r["confusion"])
        assert m.shape == (9, 9)
        # rows sum to the class counts of the subset (one noise level): pooled 2
        # severities x 2 torques x 3 replicates, per severity 6
        per_class = 12 if r["severity"] is None else 6
        assert m.sum(axis=1).tolist() == [per_class] * 9, r
        assert r["folds"] == 2
        assert np.trace(m) / m.sum() == pytest.approx(r["accuracy"])


def test_zero_noise_separates_broken_and_chip_from_healthy_across_torque(store):
    """Noise-free, all features, folds grouped by simulation (2: trained at one torque,
    tested at the other): healthy against broken and against chip measured 1.00
    (tolerance 0.9); in the nine-class report no healthy case is taken for broken, pitch
    or spall, nor one of them for healthy (measured: none). Before, the folds split the
    cases, and healthy against every class scored 1.00: the noise-free replicates of a
    simulation are one record, found again in the training folds. Grouped, healthy
    against spall, pitch and pitting scored 0.50 in these 0.15 s records, against the
    working crack 0.50."""
    import xarray as xr

    ds = xr.load_dataset(store, engine="h5netcdf")
    z = ds.where(ds.noise == 0, drop=True)
    for kind in ("broken", "chip"):
        sub = z.where((z.fault == "none") | (z.fault == kind), drop=True)
        x, _ = feature_matrix(sub, "all")
        r = separability(x, np.asarray(sub["fault"].values, dtype=str),
                         groups=simulation_groups(sub))
        assert r["folds"] == 2 and r["accuracy"] >= 0.9 and r["auc"] >= 0.9, (kind, r)
    rep = separability(*_all(z), classes=FAULT_CLASSES, groups=simulation_groups(z))
    m = np.asarray(rep["confusion"])
    idx = [FAULT_CLASSES.index(k) for k in ("broken", "pitch", "spall")]
    assert m[0, idx].sum() == 0 and m[idx, 0].sum() == 0, m


def _all(ds):
    x, _ = feature_matrix(ds, "all")
    return x, np.asarray(ds["fault"].values, dtype=str)


@pytest.mark.parametrize("edit,parameter,message", [
    (('"pitch",', '"pitch", "rust",'), "parameters.fault[8]", "must be one of none, working"),
    (("severity = [0.5, 1.0]", "severity = [0, 1.0]"), "parameters.severity[0]",
     "parameters.severity[0] = 0: must be > 0 and <= 1 and finite"),
    (("severity = [0.5, 1.0]", "severity = [0.5, 1.5]"), "parameters.severity[1]",
     "parameters.severity[1] = 1.5: must be > 0 and <= 1 and finite"),
    (("severity = [0.5, 1.0]", "severity = {min = 0.5, max = 2, num = 3}"),
     "parameters.severity.max", "<= 1"),
    (("severity = [0.5, 1.0]", 'severity = [0.5, 1.0]\nflank = ["none", "working"]'),
     "parameters.flank", "cannot be combined with parameters.fault"),
    (("severity = [0.5, 1.0]", 'severity = [0.5, 1.0]\ncrack_depth = ["1 mm"]'),
     "parameters.crack_depth", "cannot be combined with parameters.fault"),
    (("fault = [", "faults_were = ["), "parameters.faults_were", "unknown parameter"),
])
def test_bad_fault_input_refused(edit, parameter, message):
    text = STUDY.replace(*edit)
    assert text != STUDY
    with pytest.raises(InputError) as err:
        loads_study(text)
    assert err.value.parameter == parameter and message in str(err.value)
    assert len(str(err.value).splitlines()) == 1


def test_severity_without_fault_refused():
    text = (STUDY.split("[parameters]")[0]
            + '[parameters]\nflank = ["none", "working"]\nseverity = [0.5]\n')
    with pytest.raises(InputError) as err:
        loads_study(text)
    assert err.value.parameter == "parameters.severity"
    assert str(err.value) == ("parameters.severity = [0.5]: needs parameters.fault (the "
                              "fault classes it sizes)")


def _cli(capsys, *args):
    code = cli.run([str(a) for a in args])
    out = capsys.readouterr()
    return code, out.out, out.err


def test_cli_sweep_with_faults(capsys, tmp_path):
    """``gearsim sweep`` on a study file with ``fault``: store and report; bad input one
    line, exit 2, nothing written; the built-in ``faults`` study parses."""
    import xarray as xr

    text = (STUDY.split("[parameters]")[0] + "[parameters]\n"
            'fault = ["none", "broken"]\nseverity = [1.0]\ntorque = ["2000 N*m", "4876 N*m"]\n'
            "noise = [0.0]\n").replace("replicates = 3", "replicates = 2")
    path = tmp_path / "faults.toml"
    path.write_text(text)
    out = tmp_path / "f.nc"
    code, stdout, err = _cli(capsys, "sweep", path, "--out", out, "--workers", 1,
                             "--no-progress", "--report", tmp_path / "rep")
    assert code == 0, err
    assert "8 cases (8 computed, 0 resumed, 0 failed)" in stdout
    # two simulations a class (one per torque): two folds, each trained at one torque
    assert "folds grouped by simulation (none 2, broken 2 simulations); 2 folds" in stdout
    ds = xr.load_dataset(out, engine="h5netcdf")
    assert ds["fault"].values.tolist() == ["none"] * 4 + ["broken"] * 4
    doc = json.loads((tmp_path / "rep" / "separability.json").read_text())
    pooled = [r for r in doc["rows"] if r["group"] == "all" and r["severity"] is None]
    assert doc["classes"] == ["none", "broken"] and pooled[0]["confusion"] == [[4, 0], [0, 4]]
    assert doc["reference"] == "none"  # the healthy class (sorted first would be broken)

    bad = tmp_path / "bad.toml"
    bad.write_text(text.replace("severity = [1.0]", 'severity = [1.0]\nflank = ["none"]'))
    code, stdout, err = _cli(capsys, "sweep", bad, "--out", tmp_path / "b.nc", "--no-progress")
    assert code == 2 and stdout == ""
    assert err.strip().splitlines() == [
        'gearsim: error: parameters.flank = [\'none\']: cannot be combined with '
        "parameters.fault: a study varies either the crack (flank, crack_depth) or the "
        "fault class (fault, severity; the working and non-working crack are fault classes "
        "too); remove one of them"]
    assert not (tmp_path / "b.nc").exists() and not parts_dir(tmp_path / "b.nc").exists()

    one = tmp_path / "one.toml"
    one.write_text(text.replace('fault = ["none", "broken"]', 'fault = ["broken"]'))
    code, _, err = _cli(capsys, "sweep", one, "--out", tmp_path / "o.nc", "--no-progress",
                        "--report", tmp_path / "orep")
    assert code == 2 and "1 fault class (broken)" in err

    st = load_study("faults")
    # 9 classes x 3 severities x 3 torques x 2 speeds x 5 noise levels x 3 realisations;
    # 8 x 3 x 6 faulty simulations and 6 healthy ones (one per operating point)
    assert st.parameters["fault"] == FAULT_CLASSES and len(expand(st)) == 2430
    assert len(groups(st)) == 150
    code, stdout, _ = _cli(capsys, "sweep", "faults", "--show")
    assert code == 0 and stdout == st.text


def test_diagnostic_groups_take_the_further_stages_of_a_compound_train():
    """The features of a compound train's stage k >= 2 (``stage{k}_`` + a group's name)
    were in no feature group, not even "all": the diagnostic never saw the second stage."""
    import xarray as xr

    rng = np.random.default_rng(0)
    names = ["sb_ser_o1_shaft1", "stage2_sb_ser_o1_shaft3", "td_rms", "stage2_mesh_amplitude_o1"]
    ds = xr.Dataset({n: ("case", rng.uniform(1.0, 2.0, 6)) for n in names})
    assert feature_matrix(ds, "sideband")[1] == ["sb_ser_o1_shaft1", "stage2_sb_ser_o1_shaft3"]
    # mesh amplitudes are in no group, for stage 1 (mesh_amplitude_o*) as for the others
    assert feature_matrix(ds, "all")[1] == ["sb_ser_o1_shaft1", "stage2_sb_ser_o1_shaft3",
                                            "td_rms"]
