"""Parameter points of a sweep: every combination of the parameters' values (a grid), or a random sample.

A point's key is a hash of its values, so that a run (point and seed) is known again when the sweep is run again,
whatever the order of the points or the keys of the file; two equal points drawn by a random sample are one.
"""
import hashlib
import itertools
import json
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Point:
    """One parameter point: {parameter key: value}, in the sweep file's order."""
    values: dict

    @property
    def key(self):
        text = json.dumps(self.values, sort_keys=True, separators=(",", ":"))
        return hashlib.sha256(text.encode()).hexdigest()[:16]

    def label(self, keys):
        """'key=value, ...' of the given keys."""
        return ", ".join(f"{key}={self.values[key]}" for key in keys)


def run_key(point, seed):
    """The key of one run in the store: the point's key and the seed."""
    return f"{point.key}-{seed}"


def grid_points(values):
    """Every combination of {key: Values} (each with its choices), the first key varying slowest."""
    keys = list(values)
    return [Point(dict(zip(keys, combination)))
            for combination in itertools.product(*(values[key].choices for key in keys))]


def random_points(values, count, seed):
    """`count` draws of every parameter (a numpy Generator seeded with `seed`), equal draws merged."""
    rng = np.random.default_rng(seed)
    points = {}
    for _ in range(count):
        point = Point({key: v.draw(rng) for key, v in values.items()})
        points.setdefault(point.key, point)
    return list(points.values())
