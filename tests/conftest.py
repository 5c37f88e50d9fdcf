"""Shared test fixtures: where the team's shared data lives, and skipping when it is absent."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
SHARED = Path(os.environ.get("DIP3D_SHARED", ROOT.parent / "shared"))


@pytest.fixture(scope="session")
def shared_dir() -> Path:
    """Return ../shared (or $DIP3D_SHARED), skipping the test when a fresh clone has none."""
    if not (SHARED / "data").is_dir():
        pytest.skip(f"shared data not found at {SHARED} (a fresh clone has no ../shared; set DIP3D_SHARED)")
    return SHARED
