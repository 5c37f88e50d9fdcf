"""Shared test fixtures: where the team's shared data lives, and skipping when it is absent."""

from __future__ import annotations

import os
from pathlib import Path

import pytest
from hypothesis import settings

# Property tests draw the same examples on every run (the suite is deterministic); no example database,
# so a clean checkout and a developer's tree behave the same. HYPOTHESIS_PROFILE=explore for random draws.
settings.register_profile("ci", derandomize=True, database=None, deadline=None, print_blob=True)
settings.register_profile("explore", deadline=None, max_examples=2000)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci"))

ROOT = Path(__file__).resolve().parents[1]
SHARED = Path(os.environ.get("DIP3D_SHARED", ROOT.parent / "shared"))


@pytest.fixture(scope="session")
def shared_dir() -> Path:
    """Return ../shared (or $DIP3D_SHARED), skipping the test when a fresh clone has none."""
    if not (SHARED / "data").is_dir():
        pytest.skip(f"shared data not found at {SHARED} (a fresh clone has no ../shared; set DIP3D_SHARED)")
    return SHARED
