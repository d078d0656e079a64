"""masq: ray tracing of long, thin primitives (capsules, round cones, spheres, cubic
curves) and triangles, on the cpu, Vulkan, OpenCL and the driver's own ray tracing.

    import masq, numpy as np
    scene = masq.Scene.load("hair.tfx")            # or Scene() and add_capsules(a, b, radius)
    accel = masq.Accel.build(scene, method="masq")
    ctx = masq.Context("best")                     # masq.available_backends()
    hits = ctx.trace(accel, scene.camera_rays(640, 480).reshape(480, 640))
    hits["t"], hits["prim"]                        # (480, 640); prim < 0: no hit

Errors are masq.Error (masq.BackendUnavailable when a backend cannot run here), or
TypeError / ValueError naming the argument for arrays and option names. See
docs/python.md.
"""
from typing import Optional

import numpy as np
import numpy.typing as npt

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
    pinhole_rays,
    ray_dtype,
    stats_dtype,
)


def hit_positions(hits: np.ndarray, origins: npt.ArrayLike, directions: Optional[npt.ArrayLike] = None) -> np.ndarray:
    """World-space hit points origins + t * directions, shaped hits.shape + (3,), float32;
    NaN where a ray hit nothing (prim < 0).

    The rays are given as to Context.trace: origins and directions (..., 3), (..., 6) rays
    holding both, or a masq.ray_dtype array. The sum is taken in float64 and rounded once.
    (A position field in hit_dtype would change the library's Hit layout, which the trace
    writes into directly.)
    """
    hits = np.asarray(hits)
    if hits.dtype != hit_dtype:
        raise TypeError(f"hit_positions: hits: expected dtype masq.hit_dtype, got {hits.dtype}")
    o = np.asarray(origins)
    if o.dtype == ray_dtype:
        if directions is not None:
            raise ValueError("hit_positions: directions: not used with a ray_dtype array (it holds them)")
        o, d = o["org"], o["dir"]
    elif directions is None:
        if o.ndim < 1 or o.shape[-1] != 6:
            raise TypeError("hit_positions: directions: missing (pass origins and directions as (..., 3) arrays, "
                            f"(..., 6) rays or one masq.ray_dtype array; origins has shape {o.shape})")
        o, d = o[..., :3], o[..., 3:]
    else:
        d = np.asarray(directions)
    try:
        p = o.astype(np.float64) + hits["t"][..., None].astype(np.float64) * d.astype(np.float64)
        p = np.broadcast_to(p, hits.shape + (3,))
    except ValueError as e:
        raise ValueError(f"hit_positions: the rays (origins {o.shape}, directions {d.shape}) do not match "
                         f"hits of shape {hits.shape}: {e}") from None
    return np.where((hits["prim"] >= 0)[..., None], p, np.nan).astype(np.float32)
