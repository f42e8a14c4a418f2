"""The unit registry's disk cache only saves time: a cache that cannot be made or read
gives the same registry, parsed afresh (each case in a fresh interpreter, since the
registry is made once per process)."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

PROBE = ("from gearsim.units import to_si; "
         "print(repr(to_si('206 GPa', 'pressure', 'E')), repr(to_si('1900 rpm', 'speed', 'n')))")

def _expected() -> str:  # this process's registry, however it was made
    from gearsim.units import to_si

    return f"{to_si('206 GPa', 'pressure', 'E')!r} {to_si('1900 rpm', 'speed', 'n')!r}"


EXPECTED = _expected()


def _run(cache: Path) -> str:
    env = {**os.environ, "GEARSIM_CACHE": str(cache)}
    out = subprocess.run([sys.executable, "-c", PROBE], env=env, capture_output=True,
                         text=True, check=True)
    return out.stdout.strip()


def test_registry_made_then_read_from_its_cache(tmp_path):
    assert _run(tmp_path) == EXPECTED  # parses the definitions and writes the cache
    folders = list(tmp_path.glob("pint-*"))
    assert len(folders) == 1 and any(folders[0].iterdir())
    assert _run(tmp_path) == EXPECTED  # from the cache


def test_cache_half_written_is_parsed_afresh(tmp_path):
    _run(tmp_path)
    for f in (tmp_path / next(p.name for p in tmp_path.glob("pint-*"))).iterdir():
        f.write_bytes(f.read_bytes()[:7])  # every cache file cut short
    assert _run(tmp_path) == EXPECTED


@pytest.mark.skipif(os.geteuid() == 0, reason="root writes into read-only folders")
def test_cache_folder_that_cannot_be_made(tmp_path):
    ro = tmp_path / "ro"
    ro.mkdir()
    ro.chmod(0o500)
    try:
        assert _run(ro / "cache") == EXPECTED
    finally:
        ro.chmod(0o700)


def test_cache_path_that_is_a_file(tmp_path):
    # the cache folder's place taken by a file: no folder can be made there
    blocker = tmp_path / "file"
    blocker.write_text("not a folder")
    assert _run(blocker) == EXPECTED
