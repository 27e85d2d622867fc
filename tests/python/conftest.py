"""Shared helpers of the Python module's tests (run by tests/python.cmake, or by hand:
/usr/bin/python3 -m pytest tests/python with gigatet installed in that interpreter)."""
import os

import numpy as np
import pytest

try:
    from hypothesis import HealthCheck, settings

    # no example database in the source tree; modest example counts keep ./dev test short
    settings.register_profile(
        "gigatet", database=None, deadline=None, derandomize=False,
        max_examples=int(os.environ.get("GTET_HYPOTHESIS_EXAMPLES", "60")),
        suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
    settings.load_profile("gigatet")
except ImportError:  # pragma: no cover
    pass


def sorted_rows(a):
    """Rows sorted within, then the rows in lexicographic order: a set of simplices."""
    a = np.sort(np.asarray(a), axis=1)
    if len(a) == 0:
        return a
    return a[np.lexsort(a.T[::-1])]


def tets_as_coordinates(d):
    """The tets of a Delaunay as a sorted array of their sorted vertex coordinates: a set of
    tets over points, whatever the numbering."""
    p = d.points
    rows = []
    for t in d.simplices:
        rows.append(tuple(sorted(tuple(p[v]) for v in t)))
    return sorted(rows)


@pytest.fixture
def rng():
    return np.random.default_rng(12345)
