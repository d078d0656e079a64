"""Bad input: every array and option error names the argument; masq's own errors keep
masq's message; files name themselves."""
import numpy as np
import pytest

import masq


def capsule_scene():
    s = masq.Scene()
    s.add_capsules(np.zeros((2, 3), np.float32), np.ones((2, 3), np.float32), 0.1)
    return s


@pytest.mark.parametrize("bad, error, words", [
    (np.zeros((4, 3), np.int32), TypeError, ["a:", "float32 or float64", "int32"]),
    (np.zeros((4, 2), np.float32), ValueError, ["a:", "shape (n, 3)", "(4, 2)"]),
    (np.array([[0, 0, 0], [0, np.nan, 0]], np.float32), ValueError, ["a:", "NaN", "row 1"]),
    (np.array([[0, 0, 0], [np.inf, 0, 0]], np.float64), ValueError, ["a:", "infinite", "row 1"]),
    (np.zeros((4, 3), np.complex64), TypeError, ["a:", "complex"]),
    (None, TypeError, ["a:", "None"]),
])
def test_capsule_arrays_name_the_argument(bad, error, words):
    s = masq.Scene()
    b = np.ones((len(bad) if bad is not None else 1, 3), np.float32)
    with pytest.raises(error) as e:
        s.add_capsules(bad, b, 0.1)
    for w in words:
        assert w in str(e.value), str(e.value)
    assert "Scene.add_capsules" in str(e.value)


def test_row_counts_and_radii_are_checked():
    s = masq.Scene()
    with pytest.raises(ValueError, match="b: 2 rows where 3"):
        s.add_capsules(np.zeros((3, 3)), np.zeros((2, 3)), 0.1)
    with pytest.raises(ValueError, match="radius: .*3 rows where 2"):
        s.add_capsules(np.zeros((2, 3)), np.ones((2, 3)), np.ones(3))
    with pytest.raises(ValueError, match="radius: NaN"):
        s.add_spheres(np.zeros((2, 3)), float("nan"))
    with pytest.raises(TypeError, match="radius: expected a number"):
        s.add_spheres(np.zeros((2, 3)), "thick")
    with pytest.raises(ValueError, match=r"points: expected shape \(n, 4, 3\)"):
        s.add_curves(np.zeros((2, 3, 3)), 0.1)
    with pytest.raises(ValueError, match="ra: NaN in row 1"):
        s.add_round_cones(np.zeros((2, 3)), np.array([0.1, np.nan]), np.ones((2, 3)), 0.1)


def test_triangle_indices_are_checked():
    s = masq.Scene()
    v = np.zeros((3, 3), np.float32)
    with pytest.raises(TypeError, match="indices: expected an integer array"):
        s.add_triangles(v, np.zeros((1, 3), np.float32))
    with pytest.raises(ValueError, match="indices: row 0 names vertex 3 of 3"):
        s.add_triangles(v, np.array([[0, 1, 3]]))
    with pytest.raises(ValueError, match=r"indices: index -1 in row 0 is outside"):
        s.add_triangles(v, np.array([[0, 1, -1]]))


def test_transforms_are_checked():
    s = capsule_scene()
    with pytest.raises(ValueError, match="transform: expected a 3x4"):
        s.add_instance(0, np.eye(4))
    m = np.eye(3, 4)
    m[1, 3] = np.inf
    with pytest.raises(ValueError, match=r"transform: element \[1, 3\] is not finite"):
        s.add_instance(0, m)
    with pytest.raises(masq.Error, match="geometry"):
        s.add_instance(7)


@pytest.mark.parametrize("argument, value", [
    ("method", "masquerade"), ("mode", "exact"), ("builder", "lbvh"), ("nodes", "w16"), ("curve_isect", "newton")])
def test_unknown_option_names_name_the_argument_and_the_choices(argument, value):
    with pytest.raises(ValueError) as e:
        masq.Accel.build(capsule_scene(), **{argument: value})
    text = str(e.value)
    assert f"{argument}: unknown" in text and f"'{value}'" in text and "expected" in text


def test_option_names_are_the_tables():
    assert set(masq.options["method"]) == {"ref", "masq", "cluster", "auto"}
    for argument, names in masq.options.items():
        for name in names:
            accel = masq.Accel.build(capsule_scene(), **{argument: name})
            assert accel.options[argument] == name


def test_ray_arrays_name_the_argument():
    ctx = masq.Context("cpu")
    accel = masq.Accel.build(capsule_scene())
    o = np.zeros((4, 3), np.float32)
    d = np.ones((4, 3), np.float32)
    with pytest.raises(ValueError, match=r"Context.trace: directions: leading shape \(3,\) does not broadcast "
                                         r"against origins' leading shape \(4,\)"):
        ctx.trace(accel, o, d[:3])
    with pytest.raises(ValueError, match=r"Context.trace: tmax: shape \(3,\) does not broadcast against the rays'"):
        ctx.trace(accel, o, d, tmax=np.ones(3))
    with pytest.raises(ValueError, match="Context.trace: origins: NaN in row 2"):
        bad = o.copy()
        bad[2, 0] = np.nan
        ctx.trace(accel, bad, d)
    with pytest.raises(ValueError, match="Context.trace: tmin: infinite"):
        ctx.trace(accel, o, d, tmin=np.inf)
    with pytest.raises(TypeError, match=r"Context.trace: directions: missing .*origins has shape \(4, 3\)"):
        ctx.trace(accel, o)
    with pytest.raises(ValueError, match=r"Context.trace: origins: expected shape \(..., 3\), got \(4, 6\) "
                                         r"\(\(..., 6\) rays hold their directions"):
        ctx.trace(accel, np.zeros((4, 6)), d)
    with pytest.raises(ValueError, match=r"Context.trace: rays: NaN \(direction\) in row 1 \(column 4\)"):
        six = np.ones((2, 6))
        six[1, 4] = np.nan
        ctx.trace(accel, six)
    with pytest.raises(ValueError, match=r"Context.trace: directions: infinite value in ray \[1, 0\] \(column 2\)"):
        grid = np.ones((2, 2, 3))
        grid[1, 0, 2] = np.inf
        ctx.trace(accel, np.zeros((2, 2, 3)), grid)
    with pytest.raises(TypeError, match="Context.trace: directions: expected a float32 or float64 array"):
        ctx.trace(accel, o, np.ones((4, 3), np.int32))
    rays = np.zeros(4, masq.ray_dtype)
    rays["dir"] = 1
    rays["tmax"] = np.inf
    rays["org"][3, 1] = np.nan
    with pytest.raises(ValueError, match="rays: ray 3 has a NaN origin"):
        ctx.trace(accel, rays)
    with pytest.raises(ValueError, match="directions: not used with a ray_dtype array"):
        ctx.trace(accel, rays, d)
    with pytest.raises(ValueError, match="tmax: not used with a ray_dtype array"):
        ctx.trace(accel, rays[:3], tmax=1.0)
    strided = np.zeros((2, 6), masq.ray_dtype)[:, ::2]
    strided["dir"] = 1
    strided["tmin"][1, 2] = np.inf
    with pytest.raises(ValueError, match=r"rays: ray \[1, 2\] has an infinite tmin"):
        ctx.trace(accel, strided)


def test_masq_errors_keep_masqs_message(tmp_path):
    missing = tmp_path / "no_such.tfx"
    with pytest.raises(masq.Error, match="no_such.tfx"):
        masq.Scene.load(str(missing))
    bad = tmp_path / "broken.swc"
    bad.write_text("1 1 0 0 0 1 -1\n2 1 0 0 x 1 1\n")
    with pytest.raises(masq.Error, match="broken.swc:2: z 'x' is not a number"):
        masq.Scene.load(str(bad))
    loop = tmp_path / "loop.swc"
    loop.write_text("1 1 0 0 0 1 -1\n2 3 1 0 0 0.5 1\n3 3 2 0 0 0.5 4\n4 3 3 0 0 0.5 3\n")
    with pytest.raises(masq.Error, match=r"loop.swc:3: parent links form a loop with no root: sample 3 -> 4 -> 3"):
        masq.Scene.load(str(loop))
    with pytest.raises(masq.Error, match="unknown backend 'warp'"):
        masq.Context("warp")
    with pytest.raises(masq.Error, match="no device to choose"):
        masq.Context("cpu", device="0")
    with pytest.raises(masq.Error, match="empty|no geometr"):
        masq.Accel.build(masq.Scene())
    assert issubclass(masq.BackendUnavailable, masq.Error)


def test_a_named_device_is_honoured_or_named_in_the_error(backends):
    if "vulkan" not in backends:
        pytest.skip("no vulkan backend here")
    with pytest.raises(masq.Error, match="no-such-gpu"):
        masq.Context("vulkan", device="no-such-gpu")
    ctx = masq.Context("vulkan", device="0")
    assert ctx.device and ctx.backend == "vulkan"


def test_out_is_written_in_place_or_refused_naming_it():
    ctx = masq.Context("cpu")
    s = masq.Scene()
    s.add_spheres(np.array([[0, 0, 5]], np.float32), 1.0)
    accel = masq.Accel.build(s)
    o = np.zeros((2, 3), np.float32)
    d = np.array([[0, 0, 1], [0, 1, 0]], np.float32)
    out = np.empty(2, masq.hit_dtype)
    hits = ctx.trace(accel, o, d, out=out)
    assert hits is out and out["prim"][0] == 0 and out["prim"][1] < 0 and abs(out["t"][0] - 4) < 1e-5
    with pytest.raises(ValueError, match=r"out: expected 2 records of shape \(2,\) \(one per ray\), got shape \(3,\)"):
        ctx.trace(accel, o, d, out=np.empty(3, masq.hit_dtype))
    with pytest.raises(TypeError, match="out: expected dtype masq.hit_dtype"):
        ctx.trace(accel, o, d, out=np.empty(2, masq.ray_dtype))
    with pytest.raises(ValueError, match="out: the array is not C-contiguous"):
        ctx.trace(accel, o, d, out=np.empty(4, masq.hit_dtype)[::2])
    ro = np.empty(2, masq.hit_dtype)
    ro.flags.writeable = False
    with pytest.raises(ValueError, match="out: the array is read-only"):
        ctx.trace(accel, o, d, out=ro)
