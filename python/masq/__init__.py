"""masq: ray tracing of long, thin primitives (capsules, round cones, spheres, cubic
curves) and triangles, on the cpu, Vulkan, OpenCL and the driver's own ray tracing.

    import masq, numpy as np
    scene = masq.Scene.load("hair.tfx")            # or Scene() and add_capsules(a, b, radius)
    accel = masq.Accel.build(scene, method="masq")
    ctx = masq.Context("best")                     # masq.available_backends()
    hits = ctx.trace(accel, scene.camera_rays(640, 480))
    hits["t"], hits["prim"]                        # prim < 0: no hit

Errors are masq.Error (masq.BackendUnavailable when a backend cannot run here), or
TypeError / ValueError naming the argument for arrays and option names. See
docs/python.md.
"""
from ._masq import (  # noqa: F401
    Accel,
    AccelStats,
    BackendUnavailable,
    Context,
    Error,
    LoadWarning,
    Scene,
    __version__,
    available_backends,
    backends,
    hit_dtype,
    options,
    ray_dtype,
    stats_dtype,
)
