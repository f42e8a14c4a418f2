"""Shared fixtures."""

from __future__ import annotations

import pytest

from gearsim.model import load


@pytest.fixture(scope="session")
def table1():
    """The built-in Table-1 idler train (with its example crack)."""
    return load("idler-table1").train


@pytest.fixture(scope="session")
def spur():
    """The built-in 19/48 spur pair."""
    return load("spur-19-48").train
