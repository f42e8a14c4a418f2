"""Benchmark: a batch of measured records in one process against one CLI call per record.

Target (issue "Real measured records"): one process analysing 80 records of 100k samples
(statistics, spectrum, envelope, order tracking) in under 30 s on 2 cores; one
``gearsim analyze`` call on one such record in under 2 s wall clock including start-up.

Records: 20 CSV files x 4 channels, 100 000 samples at 25.6 kHz, a 30-tooth gear on a
shaft at 25 Hz with mesh harmonics, once-per-revolution impacts on half the files and
noise (the speed is given, so the shaft and gear tiers, order tracking included, run).
Reference measured in the same run: one ``gearsim analyze`` process per record (the way
the records were analysed before batches), timed on ``--sample`` records and scaled to 80.

Run: ``python benchmarks/bench_measured.py [--files 20] [--sample 4]``.
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

FS = 25_600.0
N = 100_000
F_SHAFT = 25.0
TEETH = 30
CHANNELS = ("a1", "a2", "a3", "a4")


def write_records(folder: Path, n_files: int) -> list[Path]:
    """``n_files`` CSV files of four channels (half of them with impacts)."""
    rng = np.random.default_rng(7)
    t = np.arange(N) / FS
    paths = []
    for i in range(n_files):
        cols = []
        for c in range(len(CHANNELS)):
            x = sum(a * np.cos(2 * np.pi * k * TEETH * F_SHAFT * t + c)
                    for k, a in ((1, 1.0), (2, 0.4), (3, 0.2)))
            if i % 2:
                phase = (t * F_SHAFT) % 1.0
                x = x + 2.0 * np.exp(-phase / 0.004) * np.sin(2 * np.pi * 3000.0 * t)
            cols.append(x + rng.normal(0.0, 0.3, N))
        path = folder / f"{'fault' if i % 2 else 'healthy'}_{i:02d}.csv"
        header = f"# fs = {FS:g}\n" + ",".join(CHANNELS)
        np.savetxt(path, np.column_stack(cols), delimiter=",", header=header, comments="",
                   fmt="%.6g")
        paths.append(path)
    return paths


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--files", type=int, default=20)
    ap.add_argument("--sample", type=int, default=4, help="CLI calls timed for the reference")
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        paths = write_records(folder, args.files)
        n_records = len(paths) * len(CHANNELS)

        # reference: one CLI process per record, sampled
        cli = [sys.executable, "-m", "gearsim.cli", "analyze"]
        opts = ["--shaft-rpm", str(F_SHAFT * 60), "--teeth", str(TEETH), "--json"]
        one = []
        for k in range(args.sample):
            t0 = time.perf_counter()
            subprocess.run([*cli, str(paths[k % len(paths)]), "--channel",
                            CHANNELS[k % len(CHANNELS)], *opts], check=True,
                           capture_output=True)
            one.append(time.perf_counter() - t0)
        per_call = float(np.median(one))

        # gearsim: the whole batch in one process (in-process call of the batch engine)
        from gearsim.studies.batch import run_batch

        t0 = time.perf_counter()
        ds = run_batch([str(p) for p in paths], speed=F_SHAFT, teeth=(TEETH,))
        batch = time.perf_counter() - t0
        rows = ds.sizes["record"]
        t0 = time.perf_counter()
        subprocess.run([*cli, str(folder / "*.csv"), *opts, "--out", str(folder / "t.csv"),
                        "--label-pattern", r"^(healthy|fault)_"], check=True,
                       capture_output=True)
        batch_cli = time.perf_counter() - t0

    print(f"records: {n_records} ({args.files} files x {len(CHANNELS)} channels), "
          f"{N} samples at {FS:g} Hz; table rows {rows}")
    print(f"one CLI call per record (median of {args.sample}): {per_call:.2f} s "
          f"(target < 2 s) -> {n_records} records: {per_call * n_records:.1f} s")
    print(f"one process, run_batch: {batch:.1f} s (target < 30 s); "
          f"ratio {per_call * n_records / batch:.1f}x")
    print(f"one CLI call for the whole batch (glob, labels, CSV table): {batch_cli:.1f} s; "
          f"ratio {per_call * n_records / batch_cli:.1f}x")


if __name__ == "__main__":
    main()
