"""Start-up cost of the CLI: whole processes, best of N, against the imports they cannot avoid.

Run: ``.venv/bin/python benchmarks/bench_startup.py [--repeat N]``

Issue 26 asks for ``gearsim --help`` under 0.3 s, ``gearsim analyze`` of one short
record under 1 s and ``gearsim simulate`` of 1 s under 1.5 s. Each command runs as a
fresh process (``python -m gearsim.cli``, no shell), best of ``--repeat`` runs; beside
it, in the same run, the floor it rests on: an interpreter that only imports typer (what
any typer CLI pays); one that imports ``scipy.signal`` and ``scipy.io`` (what the
analysis of a WAV record needs before it reads a sample; xarray is imported only for a
NetCDF input); and one that imports what a simulation
writing a NetCDF file needs (typer, numba, pint, xarray, ``dask.array``, which xarray
imports when it makes its first variable with dask installed, and h5netcdf) and the
first call of a one-line ``@njit(cache=True)`` function whose cache is on disk: numba
sets up its CPU target (typing and lowering registries) on the first call of any
compiled function, cached or not. Like the ``gearsim`` script (:func:`gearsim.cli.console`)
the floors end with ``os._exit``: the interpreter's teardown of the modules they imported
(0.1-0.45 s) is not part of what a command must pay. Printed: seconds and the ratio to the
floor.
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

HELP_TARGET = 0.3  # s, issue 26
ANALYZE_TARGET = 1.0  # s, issue 26
SIMULATE_TARGET = 1.5  # s, issue 26


def _best(argv: list[str], repeat: int) -> float:
    best = float("inf")
    for _ in range(repeat):
        t0 = time.perf_counter()
        subprocess.run(argv, check=True, capture_output=True)
        best = min(best, time.perf_counter() - t0)
    return best


def main() -> None:
    """Print the start-up times and their ratios to the import floors."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5, help="best of N runs")
    args = parser.parse_args()
    py = sys.executable
    with tempfile.TemporaryDirectory() as tmp:
        import scipy.io.wavfile

        fs = 20_000
        t = np.arange(fs) / fs
        x = np.sin(2 * np.pi * 600 * t) + 0.1 * np.random.default_rng(0).normal(size=fs)
        wav = Path(tmp) / "short.wav"
        scipy.io.wavfile.write(wav, fs, x.astype(np.float32))
        (Path(tmp) / "one_kernel.py").write_text(
            "from numba import njit\n\n\n@njit(cache=True)\ndef f(x):\n    return x + 1.0\n")
        kernel = "import sys; sys.path.insert(0, sys.argv[1]); import one_kernel; one_kernel.f(1.0)"
        end = "; import os; os._exit(0)"  # no module teardown, as the gearsim script
        subprocess.run([py, "-c", kernel, tmp], check=True)  # the kernel's cache on disk
        rows = [
            ("python -c 'import typer' (floor of --help)", [py, "-c", "import typer" + end], None),
            ("gearsim --help", [py, "-m", "gearsim.cli", "--help"], HELP_TARGET),
            ("gearsim example spur-19-48", [py, "-m", "gearsim.cli", "example", "spur-19-48"],
             None),
            ("python -c 'import scipy.signal, scipy.io' (floor of analyze)",
             [py, "-c", "import scipy.signal, scipy.io" + end], None),
            ("gearsim analyze short.wav (1 s, 20 kHz)",
             [py, "-m", "gearsim.cli", "analyze", str(wav)], ANALYZE_TARGET),
            ("import typer numba pint xarray dask.array h5netcdf, one cached kernel "
             "(floor of simulate)",
             [py, "-c", "import typer, numba, pint, xarray, dask.array, h5netcdf; " + kernel
              + end, tmp], None),
            ("gearsim simulate idler-table1 --duration 1",
             [py, "-m", "gearsim.cli", "simulate", "idler-table1", "--duration", "1",
              "--out", str(Path(tmp) / "run.nc")], SIMULATE_TARGET),
        ]
        times = [(name, _best(argv, args.repeat), target) for name, argv, target in rows]
    floors = {"analyze": times[3][1], "simulate": times[5][1]}
    print(f"best of {args.repeat} runs, whole processes")
    for name, sec, target in times:
        floor = next((v for k, v in floors.items() if k in name), times[0][1])
        tail = f"  target {target:g} s: {'met' if sec <= target else 'NOT met'}" if target else ""
        print(f"  {name:84s} {sec:6.3f} s  x{sec / floor:5.2f} of its floor{tail}")


if __name__ == "__main__":
    main()
