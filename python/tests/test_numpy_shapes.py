"""Rays as numpy users hold them: any leading shape, (..., 6) rows, broadcast, strided
and transposed arrays, masq's own record fields. Each form is checked against the flat,
contiguous form it stands for and, for the hits themselves, against a float64 sphere
oracle written here (never against masq's own results alone)."""
import numpy as np
import pytest

import masq
from conftest import random_rays, sphere_oracle, sphere_scene


def same_hits(a, b):
    assert a.shape == b.shape, (a.shape, b.shape)
    for field in ("prim", "geom", "inst"):
        assert np.array_equal(a[field], b[field]), field
    assert np.array_equal(a["t"], b["t"]) and np.array_equal(a["normal"], b["normal"])


@pytest.fixture(scope="module")
def setup():
    rng = np.random.default_rng(21)
    scene, centers, radii = sphere_scene(rng, 40, (0.05, 0.2))
    accel = masq.Accel.build(scene, method="masq")
    return masq.Context("cpu"), accel, centers, radii, rng


def test_a_grid_of_rays_gives_a_grid_of_hits(setup):
    ctx, accel, centers, radii, rng = setup
    o, d = random_rays(rng, 6 * 7)
    go, gd = o.reshape(6, 7, 3), d.reshape(6, 7, 3)
    hits = ctx.trace(accel, go, gd)
    assert hits.shape == (6, 7) and hits.dtype == masq.hit_dtype
    same_hits(hits.reshape(-1), ctx.trace(accel, o, d))
    # The hits themselves, against the oracle.
    t_ref = sphere_oracle(o, d, centers, radii)[0].reshape(6, 7)
    both = (hits["prim"] >= 0) & np.isfinite(t_ref)
    assert both.sum() > 5
    np.testing.assert_allclose(hits["t"][both], t_ref[both], rtol=2e-4, atol=1e-5)
    # Counters and occlusion take the same shape.
    again, stats = ctx.trace(accel, go, gd, stats=True)
    assert stats.shape == (6, 7) and stats.dtype == masq.stats_dtype
    assert np.all(stats["isect_calls"][again["prim"] >= 0] >= 1)
    occluded = ctx.occluded(accel, go, gd)
    assert occluded.shape == (6, 7) and np.array_equal(occluded, hits["prim"] >= 0)
    # Three leading axes, and none.
    same_hits(ctx.trace(accel, o.reshape(2, 3, 7, 3), d.reshape(2, 3, 7, 3)).reshape(-1), hits.reshape(-1))
    one = ctx.trace(accel, o[5], d[5])
    assert one.shape == () and one["prim"] == hits.reshape(-1)[5]["prim"]
    assert ctx.trace(accel, np.zeros((0, 4, 3)), np.ones((0, 4, 3))).shape == (0, 4)


def test_six_column_rays_are_origin_then_direction(setup):
    ctx, accel, _, _, rng = setup
    o, d = random_rays(rng, 300)
    six = np.concatenate([o, d], axis=1)
    same_hits(ctx.trace(accel, six), ctx.trace(accel, o, d))
    same_hits(ctx.trace(accel, six.reshape(10, 30, 6)), ctx.trace(accel, o, d).reshape(10, 30))
    assert np.array_equal(ctx.occluded(accel, six, tmax=2.0), ctx.occluded(accel, o, d, tmax=2.0))
    # float64 and a column slice of a wider table (strided rows) read alike.
    table = np.concatenate([np.arange(300)[:, None], six.astype(np.float64)], axis=1)
    same_hits(ctx.trace(accel, table[:, 1:]), ctx.trace(accel, o, d))


def test_a_ray_dtype_array_of_any_shape(setup):
    ctx, accel, _, _, rng = setup
    o, d = random_rays(rng, 240)
    rays = np.zeros(240, masq.ray_dtype)
    rays["org"], rays["dir"], rays["tmax"] = o, d, np.inf
    flat = ctx.trace(accel, rays)
    same_hits(flat, ctx.trace(accel, o, d))
    grid = rays.reshape(12, 20)
    same_hits(ctx.trace(accel, grid), flat.reshape(12, 20))
    # Strided and transposed record arrays: copied once, the same hits.
    same_hits(ctx.trace(accel, rays[::3]), flat[::3])
    same_hits(ctx.trace(accel, grid.T), flat.reshape(12, 20).T)
    assert np.array_equal(ctx.occluded(accel, grid.T), flat.reshape(12, 20).T["prim"] >= 0)


def test_strided_broadcast_and_other_layouts_give_the_contiguous_hits(setup):
    ctx, accel, _, _, rng = setup
    o, d = random_rays(rng, 200)
    want = ctx.trace(accel, o, d)
    wide = np.zeros((400, 3), np.float32)
    wide[::2] = d
    same_hits(ctx.trace(accel, o, wide[::2]), want)                      # every other row
    same_hits(ctx.trace(accel, np.asfortranarray(o), d), want)            # column-major
    same_hits(ctx.trace(accel, np.ascontiguousarray(o.T).T, d), want)     # a transposed (3, n)
    same_hits(ctx.trace(accel, o[::-1][::-1], d[:, ::-1][:, ::-1]), want) # negative strides undone
    rev = ctx.trace(accel, o[::-1], d[::-1])                               # negative strides
    same_hits(rev[::-1], want)
    same_hits(ctx.trace(accel, o.astype(np.float64)[:, :], d.astype(np.float16).astype(np.float64)),
              ctx.trace(accel, o, d.astype(np.float16).astype(np.float32)))
    # One light for every ray: np.broadcast_to, a (3,) origin, a (1, 3) one.
    light = np.array([0.0, 3.0, 0.0], np.float32)
    towards = rng.uniform(-1, 1, size=(200, 3)).astype(np.float32) - light
    ref = ctx.trace(accel, np.tile(light, (200, 1)), towards)
    same_hits(ctx.trace(accel, np.broadcast_to(light, towards.shape), towards), ref)
    same_hits(ctx.trace(accel, light, towards), ref)
    same_hits(ctx.trace(accel, light[None], towards), ref)
    # A direction grid from one eye: origins (3,), directions (H, W, 3).
    grid = ctx.trace(accel, light, towards.reshape(10, 20, 3))
    same_hits(grid.reshape(-1), ref)
    # Lists are arrays too.
    same_hits(ctx.trace(accel, o.tolist(), d.tolist()), want)


def test_masqs_own_fields_go_back_in(setup):
    ctx, accel, centers, radii, rng = setup
    o, d = random_rays(rng, 500)
    rays = np.zeros(500, masq.ray_dtype)
    rays["org"], rays["dir"], rays["tmax"] = o, d, np.inf
    hits = ctx.trace(accel, rays)
    same_hits(ctx.trace(accel, rays["org"], rays["dir"]), hits)
    same_hits(ctx.trace(accel, rays["org"], rays["dir"], rays["tmin"], rays["tmax"]), hits)
    # From each hit point along its normal: rays leave the sphere they hit. hits['normal']
    # is a strided view into the 48-byte records; its contiguous copy must give the same.
    hit = hits["prim"] >= 0
    p = masq.hit_positions(hits, rays)[hit]
    n = hits["normal"][hit]
    away = ctx.trace(accel, p, n, tmin=1e-3)
    same_hits(away, ctx.trace(accel, p, np.ascontiguousarray(n), tmin=1e-3))
    # A ball is convex: a ray leaving it along the outward normal never meets it again.
    assert not np.any(away["prim"] == hits["prim"][hit])


def test_bounds_broadcast_against_the_rays(setup):
    ctx, accel, centers, radii, rng = setup
    o, d = random_rays(rng, 8 * 9)
    go, gd = o.reshape(8, 9, 3), d.reshape(8, 9, 3)
    t_ref = sphere_oracle(o, d, centers, radii)[0].reshape(8, 9)
    per_column = np.linspace(0.5, 4.0, 9)  # (9,): one bound per column of the grid
    hits = ctx.trace(accel, go, gd, tmax=per_column)
    same_hits(hits, ctx.trace(accel, go, gd, tmax=np.broadcast_to(per_column, (8, 9)).copy()))
    # Independent: a hit within the bound where the oracle's nearest lies well inside it,
    # none where it lies well beyond.
    bound = np.broadcast_to(per_column, (8, 9))
    inside = t_ref < bound * 0.999
    beyond = t_ref > bound * 1.001
    assert np.all(hits["prim"][inside] >= 0) and np.all(hits["prim"][beyond] < 0)
    assert np.all(hits["t"][hits["prim"] >= 0] <= bound[hits["prim"] >= 0])
    # A per-row tmin of shape (8, 1), and a ray_dtype grid traced in place into `out`.
    near = ctx.trace(accel, go, gd, tmin=np.full((8, 1), 1.0))
    assert np.all(near["t"][near["prim"] >= 0] >= 1.0)
    out = np.empty((8, 9), masq.hit_dtype)
    assert ctx.trace(accel, go, gd, out=out) is out
    same_hits(out, ctx.trace(accel, go, gd))
    with pytest.raises(ValueError, match=r"out: expected 72 records of shape \(8, 9\)"):
        ctx.trace(accel, go, gd, out=np.empty(72, masq.hit_dtype))


def test_hit_positions_lie_on_the_spheres(setup):
    ctx, accel, centers, radii, rng = setup
    o, d = random_rays(rng, 2000)
    hits = ctx.trace(accel, o, d)
    p = masq.hit_positions(hits, o, d)
    assert p.shape == (2000, 3) and p.dtype == np.float32
    hit = hits["prim"] >= 0
    assert hit.sum() > 100 and np.all(np.isnan(p[~hit]))
    dist = np.linalg.norm(p[hit].astype(np.float64) - centers[hits["prim"][hit]], axis=1)
    np.testing.assert_allclose(dist, radii[hits["prim"][hit]], rtol=1e-4, atol=1e-5)
    np.testing.assert_allclose(p[hit], o[hit] + hits["t"][hit, None] * d[hit], rtol=1e-6, atol=1e-6)
    # The other ray forms, and grids.
    six = np.concatenate([o, d], axis=1)
    rays = np.zeros(2000, masq.ray_dtype)
    rays["org"], rays["dir"] = o, d
    np.testing.assert_array_equal(masq.hit_positions(hits, six), p)
    np.testing.assert_array_equal(masq.hit_positions(hits, rays), p)
    grid = ctx.trace(accel, o.reshape(40, 50, 3), d.reshape(40, 50, 3))
    np.testing.assert_array_equal(masq.hit_positions(grid, o.reshape(40, 50, 3), d.reshape(40, 50, 3)),
                                  p.reshape(40, 50, 3))
    with pytest.raises(TypeError, match="hit_positions: hits: expected dtype masq.hit_dtype"):
        masq.hit_positions(rays, o, d)
    with pytest.raises(TypeError, match="hit_positions: directions: missing"):
        masq.hit_positions(hits, o)


def test_scene_arrays_of_any_layout_are_copied_not_refused():
    rng = np.random.default_rng(4)
    a = rng.uniform(-1, 1, size=(50, 3))
    b = a + rng.normal(scale=0.3, size=(50, 3))
    r = rng.uniform(0.01, 0.05, size=50)
    plain = masq.Scene()
    plain.add_capsules(a.astype(np.float32), b.astype(np.float32), r.astype(np.float32))
    odd = masq.Scene()
    wide = np.zeros((100, 3))
    wide[::2] = b
    odd.add_capsules(np.asfortranarray(a), wide[::2], np.repeat(r, 2)[::2])
    for key in ("a", "b", "radius"):
        np.testing.assert_array_equal(odd.geometry(0)[key], plain.geometry(0)[key])
    # A broadcast radius and broadcast end points; transposed triangle indices.
    s = masq.Scene()
    s.add_capsules(np.broadcast_to(a[0], (4, 3)), b[:4], np.broadcast_to(np.float32(0.1), (4,)))
    g = s.geometry(0)
    assert np.all(g["a"] == a[0].astype(np.float32)) and np.all(g["radius"] == np.float32(0.1))
    idx = np.array([[0, 1, 2], [0, 2, 3]]).T.copy().T
    assert not idx.flags.c_contiguous
    s.add_triangles(np.eye(4, 3), idx)
    np.testing.assert_array_equal(s.geometry(1)["indices"], [[0, 1, 2], [0, 2, 3]])
