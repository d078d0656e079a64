"""Shared fixtures: the backends that open here, and small scenes with known geometry."""
import os

import numpy as np
import pytest

import masq


@pytest.fixture(scope="session")
def backends():
    """Every backend that opens on this machine (cpu always does)."""
    return masq.available_backends()


@pytest.fixture(scope="session")
def data_dir():
    """The real scenes (../shared/data beside the repository, or MASQ_DATA_DIR)."""
    d = os.environ.get("MASQ_DATA_DIR") or os.path.join(os.path.dirname(__file__), "..", "..", "..", "shared", "data")
    if not os.path.isdir(d):
        pytest.skip(f"no scene data at {d}")
    return d


def random_rays(rng, n, box=1.5):
    """Rays from random points on a sphere around the origin towards random points near it."""
    o = rng.normal(size=(n, 3))
    o *= 3.0 / np.linalg.norm(o, axis=1, keepdims=True)
    target = rng.uniform(-box, box, size=(n, 3)) * 0.5
    return o.astype(np.float32), (target - o).astype(np.float32)
