"""libbtf for Python: measured materials (BRDFs, BTFs) as numpy arrays.

Materials
    open(path_or_spec)       any material file or spec ('merl-fit:sgd:alum-bronze')
    create(params)           a material from a scene's parameter set (a dict)
    Material.eval/pdf/sample vectorised over numpy rows, loops in C++ without the GIL
    Material.albedo(wo)      directional albedo
Sampling
    sampler_names(), with_sampler(material, 'dp-cdf', ...), chi2_test(material, wo, ...)
BTFs and compression
    open_btf(path), BtfSource.load_view(v), compress(...), decompress(...), merge(...),
    compare(...)
Rendering and fitting
    render(scene_path, spp=...), fit(path_or_material, model='ggx')
Errors
    Error (a RuntimeError) for every libbtf failure; FileError (an Error and an OSError) for
    a file's existence or contents, with .path and .problem.

Directions are unit vectors in the local shading frame: +z is the normal, theta from +z,
phi from +x; wi is the light direction, wo the view, both pointing away from the surface.
See docs/python.md for a walk through a session.
"""

import math as _math

import numpy as _np

from ._core import *  # noqa: F401,F403  (the C++ module: Material, BtfSource, open, create, ...)
from ._core import (  # noqa: F401  (named for linters and help())
    BtfSource,
    Chi2Result,
    Error,
    FileError,
    FitResult,
    Material,
    Samples,
    _bench,
)

__all__ = [
    "Error", "FileError", "Material", "BtfSource", "Samples", "Chi2Result", "FitResult",
    "open", "create", "material_types", "open_btf",
    "sampler_names", "with_sampler", "chi2_test",
    "compress", "decompress", "merge", "compare",
    "render", "fit",
    "direction", "directions", "uniform_samples",
]


def direction(theta_deg, phi_deg=0.0):
    """direction(theta_deg, phi_deg=0) -> array (3,) float32

    The unit vector at polar angle theta (from the normal, +z) and azimuth phi (from +x), in
    degrees.
    """
    t, p = _math.radians(theta_deg), _math.radians(phi_deg)
    return _np.array([_math.sin(t) * _math.cos(p), _math.sin(t) * _math.sin(p), _math.cos(t)], dtype=_np.float32)


def directions(theta_deg, phi_deg=0.0, dtype=_np.float32):
    """directions(theta_deg, phi_deg=0, dtype=float32) -> array (N, 3)

    Unit vectors for arrays of polar angles and azimuths in degrees (broadcast together), e.g.
    a slice in the plane of incidence: directions(np.linspace(-89, 89, 179)) (a negative theta
    is the direction at phi + 180).
    """
    t = _np.radians(_np.asarray(theta_deg, dtype=_np.float64))
    p = _np.radians(_np.asarray(phi_deg, dtype=_np.float64))
    t, p = _np.broadcast_arrays(t, p)
    out = _np.stack([_np.sin(t) * _np.cos(p), _np.sin(t) * _np.sin(p), _np.cos(t)], axis=-1)
    return out.reshape(-1, 3).astype(dtype)


def uniform_samples(n, seed=0, dtype=_np.float32):
    """uniform_samples(n, seed=0, dtype=float32) -> array (n, 2)

    Uniform numbers in [0, 1)^2 for Material.sample (numpy's default generator).
    """
    return _np.random.default_rng(seed).random((n, 2)).astype(dtype)
