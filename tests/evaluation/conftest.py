"""Shared fixtures for the evaluation tests: one tiny simulator dataset (2 seeds x 2 pairs)."""

from __future__ import annotations

from pathlib import Path

import pytest

from sitl.dataset import write_dataset

SEEDS = (1, 2)  # paper_pool: seed 1 = diver position 2 pointing at placard 2, seed 2 = position 3 at 1

# The paper's pool at half resolution (same 82 deg field of view): 4x fewer pixels keeps the tests fast.
SMALL_POOL = """\
base: paper_pool
camera:
  image_size: [800, 600]
  focal_px: 460.0
  principal_point_px: [401.5, 298.0]
"""


@pytest.fixture(scope="session")
def sim_dataset(tmp_path_factory) -> Path:
    """A half-resolution paper_pool dataset of 2 seeds x 2 pairs (800x600 PNG), written once."""
    root = tmp_path_factory.mktemp("eval")
    scenario = root / "small_pool.yaml"
    scenario.write_text(SMALL_POOL)
    return write_dataset(str(scenario), SEEDS, root / "sim", frames_per_seed=2)
