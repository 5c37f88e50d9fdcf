"""The simulator's closest-approach figure: vehicle centre to each placard's square, metres."""

from __future__ import annotations

import math

import numpy as np
import pytest

from sitl.clearance import closest_approach_m, closest_other_m, square_distance_m
from sitl.scenario_model import Placard

# A 0.3 m placard 2 m north of the origin at 1 m depth, facing south (toward a vehicle at the origin).
FACING = Placard(id=1, centre_ned_m=(2.0, 0.0, 1.0), normal_ned=(-1.0, 0.0, 0.0), size_m=0.3)


@pytest.mark.parametrize("point, expected", [
    ((1.0, 0.0, 1.0), 1.0),             # straight in front of the face: the distance to the plane
    ((2.0, 0.0, 1.0), 0.0),             # on the face
    ((2.0, 0.5, 1.0), 0.35),            # beside it in its plane: to the nearest edge
    ((2.0, 0.15 + 0.3, 1.15 + 0.4), 0.5),  # beyond a corner: to the corner (0.3, 0.4 -> 0.5)
])
def test_square_distance_is_to_the_nearest_point_of_the_face(point, expected):
    assert square_distance_m(np.array([point]), FACING)[0] == pytest.approx(expected, abs=1e-9)


def test_closest_approach_takes_the_least_over_the_path_per_placard():
    other = Placard(id=2, centre_ned_m=(1.0, 1.0, 1.0), normal_ned=(-1.0, 0.0, 0.0), size_m=0.3)
    path = [(n, 0.0, 1.0) for n in np.linspace(0.0, 1.2, 13)]  # drives north toward placard 1, stops 0.8 m short
    closest = closest_approach_m(path, [FACING, other])
    assert closest[1] == pytest.approx(0.8, abs=1e-9)
    assert closest[2] == pytest.approx(0.85, abs=1e-9)  # passes it at 1 m east, its near edge 0.15 m nearer
    assert closest_other_m(closest, target_id=1) == closest[2]
    assert closest_other_m({1: 0.8}, target_id=1) is None
    assert closest_approach_m([], [FACING]) == {}
    assert math.isfinite(closest_other_m(closest, target_id=3))


def test_the_diver_distance_is_to_the_nearest_body_axis_over_the_run():
    from sitl.clearance import body_distance_m, closest_diver_m
    from sitl.scenario import load_scenario
    sc = load_scenario("paper_pool", 0)
    target = np.asarray(sc.placard(sc.target_id).centre_ned_m)
    joints = sc.diver.joints(target, 0.0)
    assert body_distance_m(joints["chest"], joints) == pytest.approx(0.0, abs=1e-9)
    beside = joints["chest"] + np.array([0.0, 0.0, -0.5])  # 0.5 m above the chest: 0.23 m above the head
    assert body_distance_m(beside, joints) == pytest.approx(0.5 - 0.27, abs=1e-9)
    run = [(0.0, 0.0, 0.0, 1.0), (1.0, *(joints["head"] + [0.0, 0.0, -0.4]))]  # ends 0.4 m above the head
    assert closest_diver_m(run, sc.diver, target) == pytest.approx(0.4, abs=0.05)  # the diver sways 3 cm
    assert closest_diver_m([], sc.diver, target) is None
