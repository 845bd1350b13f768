"""Rotations as numpy matrices, for placing grains (numpy only)."""

import numpy as np


def randomRotation(rng):
    """A rotation matrix uniformly distributed over SO(3) (a normalised Gaussian quaternion).

    :param rng: a ``numpy.random.Generator``
    """
    w, x, y, z = rng.normal(size=4)
    return quaternionMatrix((w, x, y, z))


def quaternionMatrix(q):
    """The 3x3 rotation matrix of the quaternion *q* = (w, x, y, z), normalised first."""
    w, x, y, z = np.asarray(q, dtype=float) / np.linalg.norm(q)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])
