"""Every run gets its own folder; nothing overwrites a previous run."""

from __future__ import annotations

from datetime import datetime, timezone

import pytest

from dip3d_vehicle.errors import Dip3dError
from dip3d_vehicle.run_folder import explicit_run_folder, new_run_folder


def test_two_runs_in_the_same_second_get_two_folders(tmp_path):
    when = datetime(2026, 11, 23, 10, 0, 0, tzinfo=timezone.utc)
    a = new_run_folder(tmp_path / "runs", "paper_pool", 3, when)
    b = new_run_folder(tmp_path / "runs", "paper_pool", 3, when)
    assert a.name == "20261123-100000_paper_pool_s3" and b.name == a.name + "_2"
    assert a.is_dir() and b.is_dir()


def test_scenario_file_names_are_made_safe(tmp_path):
    assert new_run_folder(tmp_path, "my pool/v2", 0).name.endswith("_my-pool-v2_s0")


def test_explicit_folder_must_be_new_or_empty(tmp_path):
    assert explicit_run_folder(tmp_path / "new").is_dir()
    assert explicit_run_folder(tmp_path / "new") == tmp_path / "new"  # still empty: fine
    (tmp_path / "new" / "run.log").write_text("x")
    with pytest.raises(Dip3dError, match="already holds files"):
        explicit_run_folder(tmp_path / "new")
    (tmp_path / "file").write_text("x")
    with pytest.raises(Dip3dError, match="must be a folder"):
        explicit_run_folder(tmp_path / "file")
