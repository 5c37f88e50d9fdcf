"""sitl.variants: random scenario files for a generalization check (layout rules, determinism, loading)."""

from __future__ import annotations

import numpy as np
import pytest

from sitl.scenario import load_scenario
from sitl.variants import CAMERA_DEPTH_M, _angle_deg, _apart, _xyz, main, write_variants


def test_variants_load_and_follow_the_layout_rules(tmp_path):
    paths = write_variants(tmp_path, 6, 3, ["clear", "murky"], 15.0)
    assert [p.name for p in paths] == [f"variant_3_{k:02d}.yaml" for k in range(6)]
    for k, path in enumerate(paths):
        sc = load_scenario(str(path), 0)
        assert 3 <= len(sc.placards) <= 5 and sc.target_id in [p.id for p in sc.placards]
        assert ("murky" in path.read_text()) == (k % 2 == 1)
        chest = np.asarray(sc.diver.chest_ned_m)
        centres = [np.asarray(p.centre_ned_m) for p in sc.placards]
        for i in range(len(centres)):
            for j in range(i):
                assert _angle_deg(centres[i] - chest, centres[j] - chest) >= 15.0 - 0.5   # file rounding
        # the diver points with the arm on the placards' side
        side = np.mean([c[1] for c in centres]) - chest[1]
        assert sc.diver.arm == ("right" if side > 0 else "left")


def test_variants_are_made_again_from_their_seed(tmp_path):
    a = [p.read_text() for p in write_variants(tmp_path / "a", 3, 11, ["clear"], 15.0)]
    b = [p.read_text() for p in write_variants(tmp_path / "b", 3, 11, ["clear"], 15.0)]
    assert a == b


def test_xyz_and_angle():
    assert np.allclose(_xyz(2.0, 90.0, 1.0), [0.0, 2.0, 1.0], atol=1e-12)
    assert _angle_deg(np.array([1.0, 0, 0]), np.array([1.0, 1.0, 0])) == pytest.approx(45.0)


def test_cli_writes_files_and_refuses_bad_water(tmp_path, capsys):
    assert main(["--count", "2", "--seed", "1", "--out", str(tmp_path)]) == 0
    assert len(capsys.readouterr().out.split()) == 2
    with pytest.raises(SystemExit):
        main(["--out", str(tmp_path), "--water", "lava"])
    assert "lava" in capsys.readouterr().err


def test_a_placard_hidden_behind_a_nearer_one_is_refused():
    """Seen from the camera, two placards' centres 5 deg apart overlap (half-diagonals 7.5 and 3.6 deg)."""
    camera = np.array([0.0, 0.0, CAMERA_DEPTH_M])
    near, far = _xyz(1.77, -5.9, 1.0), _xyz(3.13, -9.5, 0.8)
    assert _apart([near, far], camera, 3.0) and not _apart([near, far], camera, 3.0, [0.23, 0.2])
    assert _apart([near, _xyz(3.13, -25.0, 0.8)], camera, 3.0, [0.23, 0.2])


def test_small_share_points_at_a_placard_too_small_to_detect(tmp_path):
    """--small-share 1: every layout's target is its 4 cm placard, under the same separation rules;
    --small-share 0 leaves the layouts of the seed as they were."""
    from sitl.variants import SMALL_RANGE_M, SMALL_SIZE_M
    for path in write_variants(tmp_path / "small", 4, 5, ["clear", "murky"], 15.0, small_share=1.0):
        sc = load_scenario(str(path), 0)
        target = next(p for p in sc.placards if p.id == sc.target_id)
        assert target.size_m == pytest.approx(SMALL_SIZE_M) and "nothing there" in path.read_text()
        assert 3 <= len(sc.placards) <= 5 and sum(p.size_m < 0.1 for p in sc.placards) == 1
        assert SMALL_RANGE_M[0] - 0.6 <= np.linalg.norm(np.asarray(target.centre_ned_m)[:2]) <= SMALL_RANGE_M[1] + 0.6
        chest = np.asarray(sc.diver.chest_ned_m)
        others = [np.asarray(p.centre_ned_m) - chest for p in sc.placards if p.id != sc.target_id]
        assert min(_angle_deg(np.asarray(target.centre_ned_m) - chest, o) for o in others) >= 15.0 - 0.5
    plain = [p.read_text() for p in write_variants(tmp_path / "a", 3, 5, ["clear"], 15.0)]
    none = [p.read_text() for p in write_variants(tmp_path / "b", 3, 5, ["clear"], 15.0, small_share=0.0)]
    assert plain == none and all("target: random" in t for t in plain)
