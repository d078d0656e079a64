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


def sphere_scene(rng, n=60, radii=(0.02, 0.15)):
    """n random spheres in [-1, 1]^3 with radii uniform in `radii`: the scene and its arrays."""
    centers = rng.uniform(-1, 1, size=(n, 3))
    r = rng.uniform(radii[0], radii[1], size=n)
    s = masq.Scene()
    s.add_spheres(centers, r)
    return s, centers, r


def sphere_oracle(o, d, centers, radii):
    """Nearest t >= 0 of each ray (rows of o, d) against every sphere (inf: none), and the
    sphere's index: float64, analytically."""
    o = o.reshape(-1, 3).astype(np.float64)[:, None, :]
    d = d.reshape(-1, 3).astype(np.float64)[:, None, :]
    oc = o - centers[None, :, :]
    a = np.sum(d * d, axis=2)
    b = np.sum(oc * d, axis=2)
    c = np.sum(oc * oc, axis=2) - radii[None, :] ** 2
    disc = b * b - a * c
    with np.errstate(invalid="ignore"):
        root = np.sqrt(disc)
    t0 = (-b - root) / a
    t1 = (-b + root) / a
    t = np.where(t0 >= 0, t0, t1)
    t = np.where((disc >= 0) & (t >= 0), t, np.inf)
    return t.min(axis=1), t.argmin(axis=1)
