"""Shared fixtures for the evaluation tests: one tiny simulator dataset (2 seeds x 2 pairs)."""

from __future__ import annotations

from pathlib import Path

import pytest

from sitl.dataset import write_dataset

SEEDS = (1, 2)  # paper_pool: seed 1 = diver position 2 pointing at placard 2, seed 2 = position 3 at 1


@pytest.fixture(scope="session")
def sim_dataset(tmp_path_factory) -> Path:
    """A paper_pool dataset of 2 seeds x 2 pairs (1600x1200 PNG), written once per session."""
    return write_dataset("paper_pool", SEEDS, tmp_path_factory.mktemp("eval") / "sim", frames_per_seed=2)
