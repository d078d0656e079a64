"""Traces on every backend that opens here, checked against an independent float64
oracle written here in numpy (spheres and triangles analytically; capsule hits by the
distance of the hit point to the axis), never against masq's own results."""
import numpy as np
import pytest

import masq
from conftest import random_rays, sphere_oracle, sphere_scene


@pytest.mark.parametrize("method", ["ref", "masq", "cluster"])
def test_spheres_match_the_oracle_on_every_backend(backends, method):
    rng = np.random.default_rng(7)
    scene, centers, radii = sphere_scene(rng)
    o, d = random_rays(rng, 4000)
    t_ref, prim_ref = sphere_oracle(o, d, centers, radii)
    accel = masq.Accel.build(scene, method=method)
    for backend in backends:
        hits = masq.Context(backend).trace(accel, o, d)
        hit = hits["prim"] >= 0
        miss_ref = ~np.isfinite(t_ref)
        # A ray within fp32 of a silhouette may go either way: any disagreement must be
        # one that passes a sphere at its radius to a relative 1e-4.
        disagree = np.nonzero(hit != ~miss_ref)[0]
        for i in disagree:
            oc = centers - o[i].astype(np.float64)
            dd = d[i].astype(np.float64)
            miss_distance = np.linalg.norm(oc - np.outer(oc @ dd / (dd @ dd), dd), axis=1)
            assert np.min(np.abs(miss_distance - radii) / radii) < 1e-4, \
                f"{backend} {method}: ray {i} hit={hit[i]} but the oracle says {t_ref[i]}"
        both = hit & ~miss_ref
        assert both.sum() > 500, f"{backend}: too few hits to check ({both.sum()})"
        np.testing.assert_allclose(hits["t"][both], t_ref[both], rtol=2e-4, atol=1e-5,
                                   err_msg=f"{backend} {method}: t differs from the oracle")
        assert np.all(hits["prim"][both] == prim_ref[both]), f"{backend} {method}: nearest sphere differs"
        assert np.all(hits["geom"][hit] == 0) and np.all(hits["inst"][hit] == 0)
        # Unit normals pointing back at the ray.
        n = hits["normal"][hit]
        np.testing.assert_allclose(np.linalg.norm(n, axis=1), 1, atol=1e-4)
        assert np.all(np.sum(n * d[hit], axis=1) < 0)


def test_triangles_and_instances_match_the_oracle(backends):
    # One quad (two triangles) in the z=0 plane placed twice: shifted by +2 in x, and
    # scaled by 2 at z=1. Rays straight down -z from above.
    s = masq.Scene()
    g = s.add_triangles(np.array([[-0.5, -0.5, 0], [0.5, -0.5, 0], [0.5, 0.5, 0], [-0.5, 0.5, 0]], np.float32),
                        np.array([[0, 1, 2], [0, 2, 3]], np.uint32))
    m0 = np.eye(3, 4)
    m0[0, 3] = 2
    m1 = np.diag([2.0, 2.0, 2.0])
    m1 = np.hstack([m1, [[0], [0], [1]]])
    i0 = s.add_instance(g, m0)
    i1 = s.add_instance(g, m1)
    rng = np.random.default_rng(3)
    xy = rng.uniform(-1.6, 3.0, size=(3000, 2))
    o = np.column_stack([xy, np.full(len(xy), 5.0)]).astype(np.float32)
    d = np.tile(np.array([0, 0, -1], np.float32), (len(xy), 1))
    # Oracle: instance 1 (z=1, |x|,|y| <= 1) is nearer than instance 0 (z=0, x in [1.5, 2.5]).
    in1 = (np.abs(xy[:, 0]) <= 1) & (np.abs(xy[:, 1]) <= 1)
    in0 = (np.abs(xy[:, 0] - 2) <= 0.5) & (np.abs(xy[:, 1]) <= 0.5)
    t_ref = np.where(in1, 4.0, np.where(in0, 5.0, np.inf))
    inst_ref = np.where(in1, i1, np.where(in0, i0, -1))
    edge = (np.abs(np.abs(xy[:, 0]) - 1) < 1e-5) | (np.abs(np.abs(xy[:, 1]) - 1) < 1e-5) | \
           (np.abs(np.abs(xy[:, 0] - 2) - 0.5) < 1e-5) | (np.abs(np.abs(xy[:, 1]) - 0.5) < 1e-5)
    for method in ["ref", "masq"]:
        accel = masq.Accel.build(s, method=method)
        for backend in backends:
            hits = masq.Context(backend).trace(accel, o, d)
            ok = ~edge
            assert np.all(hits["inst"][ok] == inst_ref[ok]), f"{backend} {method}: instance ids"
            hit = ok & np.isfinite(t_ref)
            np.testing.assert_allclose(hits["t"][hit], t_ref[hit], rtol=1e-6, err_msg=f"{backend} {method}")
            np.testing.assert_allclose(np.abs(hits["normal"][hit][:, 2]), 1, atol=1e-6)
            assert np.all((hits["u"][hit] >= 0) & (hits["v"][hit] >= 0) & (hits["u"][hit] + hits["v"][hit] <= 1 + 1e-6))


def test_capsule_hits_lie_on_the_surface(backends):
    rng = np.random.default_rng(11)
    a = rng.uniform(-1, 1, size=(200, 3))
    b = a + rng.normal(scale=0.4, size=(200, 3))
    r = rng.uniform(0.005, 0.05, size=200)
    s = masq.Scene()
    s.add_capsules(a, b, r)
    o, d = random_rays(rng, 20000)
    for backend in backends:
        hits = masq.Context(backend).trace(masq.Accel.build(s, method="masq"), o, d)
        hit = hits["prim"] >= 0
        assert hit.sum() > 200
        p = o[hit].astype(np.float64) + hits["t"][hit, None].astype(np.float64) * d[hit]
        i = hits["prim"][hit]
        ab = b[i] - a[i]
        h = np.clip(np.sum((p - a[i]) * ab, axis=1) / np.sum(ab * ab, axis=1), 0, 1)
        dist = np.linalg.norm(p - (a[i] + h[:, None] * ab), axis=1)
        np.testing.assert_allclose(dist, r[i], rtol=2e-3, atol=2e-5, err_msg=f"{backend}: hit point off the capsule")


def test_ray_array_and_vector_forms_agree_and_counters_count(backends):
    rng = np.random.default_rng(5)
    scene, _, _ = sphere_scene(rng)
    o, d = random_rays(rng, 2000)
    rays = np.zeros(len(o), masq.ray_dtype)
    rays["org"], rays["dir"], rays["tmax"] = o, d, np.inf
    accel = masq.Accel.build(scene, method="masq")
    for backend in backends:
        ctx = masq.Context(backend)
        a = ctx.trace(accel, rays)
        b, stats = ctx.trace(accel, o, d, stats=True)
        assert a.dtype == masq.hit_dtype and stats.dtype == masq.stats_dtype
        assert np.array_equal(a["prim"], b["prim"]) and np.array_equal(a["t"], b["t"])
        hit = b["prim"] >= 0
        assert np.all(stats["isect_calls"][hit] >= 1), backend
        occluded = ctx.occluded(accel, o, d)
        assert occluded.dtype == bool and np.array_equal(occluded, hit), backend
        # tmax bounds the hits: a bound just before each hit leaves nothing.
        t = np.where(hit, b["t"] * 0.999, np.inf)
        assert not np.any(ctx.occluded(accel, o[hit], d[hit], tmax=t[hit]))
        timing = ctx.timing
        assert timing["trace_seconds"] > 0 and set(timing) == {"upload_seconds", "compile_seconds", "trace_seconds"}


def test_camera_rays_and_accel_stats():
    rng = np.random.default_rng(1)
    scene, _, _ = sphere_scene(rng, 30)
    rays = scene.camera_rays(32, 24)
    assert rays.dtype == masq.ray_dtype and rays.shape == (32 * 24,)
    accel = masq.Accel.build(scene, method="masq")
    st = accel.stats
    assert st.instances == 30 and st.bytes > 0 and st.build_seconds >= 0
    assert accel.options["method"] == "masq"
    hits = masq.Context("cpu").trace(accel, rays)
    assert np.any(hits["prim"] >= 0)
    with pytest.raises(ValueError, match="width and height must be positive"):
        scene.camera_rays(0, 10)


def test_loaded_hair_traces_alike_on_every_backend(backends, data_dir):
    scene = masq.Scene.load(f"{data_dir}/hair/tressfx3_ponytail_tail.tfx")
    rays = scene.camera_rays(160, 120)
    accel = masq.Accel.build(scene, method="masq")
    first = None
    for backend in backends:
        hits = masq.Context(backend).trace(accel, rays)
        assert np.count_nonzero(hits["prim"] >= 0) > 100, backend
        if first is None:
            first = hits
            continue
        same = np.mean(hits["prim"] == first["prim"])
        assert same > 0.995, f"{backend}: {same:.4f} of the rays hit what {backends[0]} hit"


def test_threads_trace_at_once_as_they_would_one_after_the_other(backends):
    # Traces release the GIL: Python threads on their own Contexts run at once and must
    # give what each gives alone.
    import threading
    rng = np.random.default_rng(9)
    scene, _, _ = sphere_scene(rng, 200)
    o, d = random_rays(rng, 50000)
    accel = masq.Accel.build(scene, method="masq")
    alone = {b: masq.Context(b).trace(accel, o, d) for b in backends}
    results, errors = {}, []

    def run(key, backend):
        try:
            ctx = masq.Context(backend)
            for _ in range(3):
                results[key] = ctx.trace(accel, o, d)
        except Exception as e:  # reported below, with the thread's backend
            errors.append(f"{backend}: {e}")

    threads = [threading.Thread(target=run, args=((b, k), b)) for b in backends for k in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors, errors
    for (b, _), hits in results.items():
        assert np.array_equal(hits["prim"], alone[b]["prim"]) and np.array_equal(hits["t"], alone[b]["t"]), b


def ribbon_oracle(o, d, p0, r0, p1, r1, n):
    """Nearest t >= 0 of each ray against every ribbon (inf: none), its index, and the
    crossing's clearance (distance to the strip's nearest edge over the half-width there):
    float64, by the plane through the axis that holds the width direction."""
    o = o.astype(np.float64)[:, None, :]
    d = d.astype(np.float64)[:, None, :]
    a = p1 - p0
    w = np.cross(n, a)
    w /= np.linalg.norm(w, axis=1, keepdims=True)
    m = np.cross(a, w)
    m /= np.linalg.norm(m, axis=1, keepdims=True)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.sum((p0[None] - o) * m[None], axis=2) / np.sum(d * m[None], axis=2)
        q = o + t[..., None] * d - p0[None]
        s = np.sum(q * a[None], axis=2) / np.sum(a * a, axis=1)[None]
        v = np.sum(q * w[None], axis=2)
        r = r0[None] + s * (r1 - r0)[None]
        on = (t >= 0) & (s >= 0) & (s <= 1) & (np.abs(v) <= r)
        clear = np.minimum(np.abs(r - np.abs(v)) / np.maximum(r, 1e-30), np.minimum(np.abs(s), np.abs(1 - s)))
    t = np.where(on, t, np.inf)
    k = t.argmin(axis=1)
    rows = np.arange(len(k))
    return t[rows, k], k, clear[rows, k], s[rows, k], v[rows, k] / r[rows, k]


def test_ribbons_match_the_oracle_on_every_backend(backends):
    rng = np.random.default_rng(13)
    k = 150
    p0 = rng.uniform(-1, 1, size=(k, 3))
    p1 = p0 + rng.normal(scale=0.3, size=(k, 3))
    r0 = rng.uniform(0.02, 0.08, size=k)
    r1 = rng.uniform(0.0, 0.08, size=k)
    n = rng.normal(size=(k, 3))
    s = masq.Scene()
    s.add_ribbons(p0, r0, p1, r1, n)
    # The oracle on the fp32 values masq holds (the scene stores float32).
    p0, r0, p1, r1, n = (x.astype(np.float32).astype(np.float64) for x in (p0, r0, p1, r1, n))
    o, d = random_rays(rng, 4000)
    t_ref, prim_ref, clear, u_ref, v_ref = ribbon_oracle(o, d, p0, r0, p1, r1, n)
    miss_ref = ~np.isfinite(t_ref)
    for method in ("ref", "masq", "cluster"):
        accel = masq.Accel.build(s, method=method)
        for backend in backends:
            hits = masq.Context(backend).trace(accel, o, d)
            hit = hits["prim"] >= 0
            same = (hit == ~miss_ref) & (~hit | (hits["prim"] == prim_ref))
            # Only rays within fp32 of an edge (or of a ribbon hiding another) may differ.
            assert np.sum(~same) <= 4, f"{backend} {method}: {np.sum(~same)} rays differ from the oracle"
            both = same & hit & (clear > 1e-3)
            assert both.sum() > 300, f"{backend} {method}: too few hits to check ({both.sum()})"
            np.testing.assert_allclose(hits["t"][both], t_ref[both], rtol=1e-4, atol=1e-5,
                                       err_msg=f"{backend} {method}: t differs from the oracle")
            np.testing.assert_allclose(hits["u"][both], u_ref[both], atol=1e-4, err_msg=f"{backend} {method}: u")
            np.testing.assert_allclose(hits["v"][both], v_ref[both], atol=1e-3, err_msg=f"{backend} {method}: v")
            # The normal: unit, on n's side of the plane (not turned towards the ray).
            i = hits["prim"][both]
            nrm = hits["normal"][both].astype(np.float64)
            np.testing.assert_allclose(np.linalg.norm(nrm, axis=1), 1, atol=1e-4)
            axis = (p1 - p0)[i] / np.linalg.norm((p1 - p0)[i], axis=1, keepdims=True)
            perp = n[i] - np.sum(n[i] * axis, axis=1, keepdims=True) * axis
            np.testing.assert_allclose(nrm, perp / np.linalg.norm(perp, axis=1, keepdims=True), atol=1e-4,
                                       err_msg=f"{backend} {method}: normal")
