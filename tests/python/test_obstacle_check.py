"""make paparazzi-check's obstacle step (finken.paparazzi.obstacle_check): its figures from the merged logs, on
logs made here (the step itself runs with a Paparazzi tree, in make paparazzi-check)."""
import numpy as np
import pytest

from finken.flight.truth import Obstacle
from finken.paparazzi.obstacle_check import deepest_reach_m, starts_of

PILLAR = Obstacle(np.zeros((48, 2)), 3.0, (1.1, 2.5, 0.2))


def poses(rows):
    t, vehicle, x, y = map(np.array, zip(*rows))
    return {"t": t, "vehicle": vehicle, "x": x, "y": y}


def test_each_vehicles_first_pose_is_its_start():
    log = poses([(0.0, 2, 1.0, 1.5), (0.0, 1, 2.0, 2.5), (0.1, 2, 9.0, 9.0), (0.1, 1, 8.0, 8.0)])
    assert starts_of(log) == {1: (2.0, 2.5), 2: (1.0, 1.5)}


def test_the_deepest_reach_into_a_round_obstacle():
    touching = poses([(0.0, 1, 1.1 + 0.4, 2.5), (0.1, 1, 1.1, 2.5 - 0.5)])
    assert deepest_reach_m(touching, [PILLAR], 0.2) == pytest.approx(0.0, abs=1e-12)
    inside = poses([(0.0, 1, 1.1 + 0.37, 2.5), (0.1, 1, 3.0, 3.0)])
    assert deepest_reach_m(inside, [PILLAR], 0.2) == pytest.approx(0.03)
    assert deepest_reach_m(inside, [], 0.2) == -np.inf
    with pytest.raises(ValueError, match="only round obstacles"):
        deepest_reach_m(inside, [Obstacle(np.zeros((4, 2)), 0.75, None)], 0.2)
