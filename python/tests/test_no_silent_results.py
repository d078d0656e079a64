"""Issue 40, 'no silent wrong results' and 'the paths and devices users pass': each case
that used to be silently wrong is right, or one clear error."""
import pathlib
import warnings

import numpy as np
import pytest

import masq


def test_primitive_count_without_instances_counts_each_geometry_once():
    s = masq.Scene()
    s.add_capsules(np.zeros((3, 3), np.float32), np.ones((3, 3), np.float32), 0.1)
    s.add_spheres(np.zeros((2, 3), np.float32), 0.5)
    assert s.instance_count == 0
    assert s.primitive_count == 5
    s.add_instance(0)
    s.add_instance(0)
    assert s.primitive_count == 6  # what an Accel traces: two instances of three capsules


def test_far_scene_is_refused_not_missed():
    def sphere_at(x):
        s = masq.Scene()
        s.add_spheres(np.array([[x, 0.0, 0.0]], np.float32), 0.1 * x)
        return s

    near = sphere_at(1e18)
    hits = masq.Context("cpu").trace(masq.Accel.build(near), near.camera_rays(16, 16))
    assert (hits["prim"] >= 0).any()
    with pytest.raises(masq.Error, match=r"geometry 0 reaches 1.1e\+19 .*2\^60"):
        masq.Accel.build(sphere_at(1e19))


def test_negative_radius_is_an_error_not_the_default(data_dir):
    with pytest.raises(masq.Error, match="radius -1"):
        masq.Scene.load(f"{data_dir}/hair/tressfx3_bear.tfx", radius=-1)
    with pytest.raises(masq.Error, match="radius nan"):
        masq.Scene.load(f"{data_dir}/hair/tressfx3_bear.tfx", radius=float("nan"))


def test_loader_repairs_are_warnings(data_dir):
    # This real neuron has 815 samples with a negative radius: made positive, and said so.
    with pytest.warns(masq.LoadWarning, match="815 sample.*negative radius made positive"):
        masq.Scene.load(f"{data_dir}/neurons/C031097B-I4.CNG.swc")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        masq.Scene.load(f"{data_dir}/meshes/bun_zipper.ply")  # a clean file warns of nothing


def test_pathlib_paths_load(data_dir):
    s = masq.Scene.load(pathlib.Path(data_dir) / "hair" / "tressfx3_bear.tfx")
    assert s.primitive_count > 0


def test_nff_camera_is_the_files(data_dir, tmp_path):
    # Two views of the same sphere: the file's "v" block decides what camera_rays see.
    def nff(eye):
        p = tmp_path / f"view{eye}.nff"
        p.write_text(f"v\nfrom {eye} 0 0\nat 0 0 0\nup 0 1 0\nangle 30\nhither 1\nresolution 8 8\n"
                     "f 1 0 0 0 0 0 0 0\ns 0 0 0 1\n")
        return masq.Scene.load(p)

    for eye in (-10.0, 10.0):
        rays = nff(eye).camera_rays(4, 4)
        np.testing.assert_allclose(rays["org"], np.tile([eye, 0.0, 0.0], (16, 1)), atol=1e-5)


def test_integer_devices_are_indices(backends):
    gpu = [b for b in backends if b in ("vulkan", "opencl")]
    if not gpu:
        pytest.skip("no Vulkan or OpenCL device here")
    by_int, by_str = masq.Context(gpu[0], device=0), masq.Context(gpu[0], device="0")
    assert by_int.device == by_str.device
