"""Shared test fixtures: where the team's shared data lives, and skipping when it is absent."""

from __future__ import annotations

import os
from pathlib import Path
from typing import Callable

import pytest
from hypothesis import settings

# Property tests draw the same examples on every run (the suite is deterministic); no example database,
# so a clean checkout and a developer's tree behave the same. HYPOTHESIS_PROFILE=explore for random draws.
settings.register_profile("ci", derandomize=True, database=None, deadline=None, print_blob=True)
settings.register_profile("explore", deadline=None, max_examples=2000)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci"))

ROOT = Path(__file__).resolve().parents[1]
SHARED = Path(os.environ.get("DIP3D_SHARED", ROOT.parent / "shared"))
SUMMARY_FILE = ROOT / ".pytest_cache" / "summaries.txt"
_SUMMARIES: list[str] = []


@pytest.fixture(scope="session")
def shared_dir() -> Path:
    """Return ../shared (or $DIP3D_SHARED), skipping the test when a fresh clone has none."""
    if not (SHARED / "data").is_dir():
        pytest.skip(f"shared data not found at {SHARED} (a fresh clone has no ../shared; set DIP3D_SHARED)")
    return SHARED


@pytest.fixture
def summary(request) -> Callable[[str], None]:
    """Return a function that records a one-line result (fuzz counts, security counters) for the report.

    The lines are printed after the run in pytest's summary ("fuzz and security summaries", not
    between the dots), kept as the test's ``user_properties`` (JUnit XML) and written to
    ``.pytest_cache/summaries.txt``.
    """
    def add(text: str) -> None:
        _SUMMARIES.append(f"{request.node.nodeid}: {text}")
        request.node.user_properties.append(("summary", text))
    return add


def pytest_terminal_summary(terminalreporter) -> None:
    """Print the recorded summaries after the run and write them to ``.pytest_cache/summaries.txt``."""
    if not _SUMMARIES:
        return
    terminalreporter.section("fuzz and security summaries")
    for line in _SUMMARIES:
        terminalreporter.write_line(line)
    try:
        SUMMARY_FILE.parent.mkdir(parents=True, exist_ok=True)
        SUMMARY_FILE.write_text("\n".join(_SUMMARIES) + "\n")
        terminalreporter.write_line(f"(also in {SUMMARY_FILE})")
    except OSError:
        pass
