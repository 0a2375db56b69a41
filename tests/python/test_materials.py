"""btf.Material: the registry's ways in, vectorised eval/pdf/sample against the scalar calls,
precision, shapes, errors, albedo, samplers by name and the chi-square test."""

import numpy as np
import pytest

import btf


def _views():
    return [btf.direction(t, p) for t, p in ((0, 0), (30, 20), (60, 200), (80, 95))]


def _lights(n=200, seed=3):
    """n directions over the whole sphere (some below the horizon, where f is 0)."""
    rng = np.random.default_rng(seed)
    v = rng.normal(size=(n, 3))
    return (v / np.linalg.norm(v, axis=1, keepdims=True)).astype(np.float32)


@pytest.fixture(params=["ggx", "table", "rgl"])
def material(request, ggx, table_path):
    if request.param == "ggx":
        return ggx
    if request.param == "table":
        return btf.open(table_path)
    return btf.open(request.getfixturevalue("rgl_path"))


def test_open_each_kind(ggx, table_path, rgl_path):
    assert ggx.name.startswith("ggx")
    assert not ggx.is_anisotropic
    table = btf.open(str(table_path))  # str and pathlib both work
    assert isinstance(table, btf.Material)
    assert "Material" in repr(table)
    rgl = btf.open(rgl_path)
    assert rgl.eval(btf.direction(30, 180), btf.direction(30)).shape == (3,)


def test_create_error_names_the_key():
    with pytest.raises(btf.Error, match=r"/alpha: expected a positive number, got -1"):
        btf.create({"type": "ggx", "diffuse": 0.5, "f0": 0.04, "alpha": -1})
    with pytest.raises(btf.Error, match="nosuchtype"):
        btf.create({"type": "nosuchtype"})


def test_material_types_lists_ggx():
    types = btf.material_types()
    assert "alpha" in types["ggx"]["keys"]


def test_eval_matches_scalar_calls(material):
    """One wo for all rows (the stream call) and one wo per row (the loop) give the scalar
    calls' floats exactly."""
    wi = _lights()
    for wo in _views():
        many = material.eval(wi, wo)
        assert many.shape == (len(wi), 3) and many.dtype == np.float32
        scalar = np.array([material.eval(w, wo) for w in wi])
        np.testing.assert_array_equal(many, scalar)
        per_row = material.eval(wi, np.repeat(wo[None], len(wi), axis=0))
        np.testing.assert_array_equal(per_row, scalar)
        assert np.all(many[wi[:, 2] <= 0] == 0)  # nothing below the horizon


def test_eval_into_a_given_array(ggx):
    wi, wo = _lights(30), btf.direction(25)
    out = np.empty((30, 3), np.float32)
    assert ggx.eval(wi, wo, out=out) is out
    np.testing.assert_array_equal(out, ggx.eval(wi, wo))
    with pytest.raises(ValueError, match=r"out: expected a writeable, C-contiguous float32 array of shape \(30, 3\)"):
        ggx.eval(wi, wo, out=np.empty((30, 3), np.float64))


def test_float64_in_float64_out(ggx):
    wi, wo = _lights(50), btf.direction(40)
    f32 = ggx.eval(wi, wo)
    f64 = ggx.eval(wi.astype(np.float64), wo.astype(np.float64))
    assert f64.dtype == np.float64
    np.testing.assert_array_equal(f64, f32.astype(np.float64))  # computed in float32 either way
    assert ggx.pdf(wi.astype(np.float64), wo).dtype == np.float64
    s = ggx.sample(wo.astype(np.float64), btf.uniform_samples(10, dtype=np.float64))
    assert s.wi.dtype == np.float64 and s.valid.dtype == bool


def test_shape_errors_name_the_expected_shape(ggx):
    wo = btf.direction(30)
    with pytest.raises(ValueError, match=r"wi: expected an array of shape \(N, 3\) or \(3,\), got shape \(4, 2\)"):
        ggx.eval(np.zeros((4, 2), np.float32), wo)
    with pytest.raises(ValueError, match=r"u: expected an array of shape \(N, 2\)"):
        ggx.sample(wo, np.zeros((5, 3)))
    with pytest.raises(ValueError, match="different row counts"):
        ggx.eval(_lights(5), np.repeat(wo[None], 4, axis=0))
    with pytest.raises(ValueError, match="wi"):
        ggx.eval("not numbers", wo)


def test_sample_agrees_with_pdf_and_eval(material):
    u = btf.uniform_samples(4000, seed=5)
    for wo in _views()[:3]:
        s = material.sample(wo, u)
        assert s.wi.shape == (len(u), 3) and s.weight.shape == (len(u), 3)
        assert s.pdf.shape == (len(u),) and s.valid.shape == (len(u),)
        assert s.valid.mean() > 0.5
        ok = s.valid
        # The pdf sample() reports is pdf() of the drawn direction, bit for bit.
        np.testing.assert_array_equal(material.pdf(s.wi[ok], wo), s.pdf[ok])
        # weight = f cos(theta_i) / pdf
        f = material.eval(s.wi[ok], wo)
        expected = f * s.wi[ok, 2:3] / s.pdf[ok, None]
        np.testing.assert_allclose(s.weight[ok], expected, rtol=2e-4, atol=1e-6)
        assert np.all(s.pdf[~ok] == 0) and np.all(s.wi[~ok] == 0)


def test_chi2_through_the_binding(ggx):
    # The material's own sampler: 200,000 draws per view, 20 x 40 cells, significance 0.01,
    # seed 1, at two views.
    for theta in (20, 65):
        r = btf.chi2_test(ggx, theta, samples=200_000, significance=0.01, seed=1)
        assert r.accepted, f"{ggx.name} at theta_o {theta}: {r.message} (200,000 draws, alpha = 0.01)"
        assert r.sample_count == 200_000 and r.p_value >= 0.01
        assert r.observed.shape == (20, 40) and r.expected.shape == (20, 40)
        assert r.observed.sum() + r.failed_samples == pytest.approx(200_000)
    # A DP-CDF sampler over it (coarse tables keep the piecewise-constant quadrature short):
    # 100,000 draws, 20 x 40 cells, significance 0.01, seed 1.
    dp = btf.with_sampler(ggx, "dp-cdf", theta_o_bins=4, parameterization="incident", cos_theta_bins=16, phi_bins=32)
    r = btf.chi2_test(dp, 40, samples=100_000, significance=0.01, seed=1)
    assert r.accepted, f"{dp.name}: {r.message} (100,000 draws, alpha = 0.01)"


def test_chi2_of_a_hemisphere_warp(ggx):
    # 100,000 draws, 20 x 40 cells, significance 0.01, seed 1: the cosine warp beside the GGX.
    r = btf.chi2_test(btf.with_sampler(ggx, "cosine"), 30, samples=100_000, significance=0.01)
    assert r.accepted, f"{r.message} (100,000 draws, alpha = 0.01)"
    assert r.failed_samples == 0 and bool(r)


def test_samplers_by_name(ggx):
    names = btf.sampler_names()
    assert {"uniform", "cosine", "material", "dp-cdf", "quadtree", "tabulated"} <= set(names)
    cosine = btf.with_sampler(ggx, "cosine")
    wi, wo = _lights(20), btf.direction(30)
    np.testing.assert_array_equal(cosine.eval(wi, wo), ggx.eval(wi, wo))  # eval stays the material's
    np.testing.assert_allclose(cosine.pdf(wi, wo), np.maximum(wi[:, 2], 0) / np.pi, rtol=1e-5)
    with pytest.raises(ValueError, match="unknown sampler 'nope'"):
        btf.with_sampler(ggx, "nope")
    with pytest.raises(TypeError, match="unknown option 'bins'"):
        btf.with_sampler(ggx, "dp-cdf", bins=3)


def test_missing_file_names_the_path(tmp_path):
    missing = tmp_path / "no-such-material.binary"
    with pytest.raises(btf.FileError) as caught:
        btf.open(missing)
    assert str(missing) in str(caught.value)
    assert caught.value.path == str(missing)
    assert isinstance(caught.value, OSError) and isinstance(caught.value, btf.Error)
    assert isinstance(caught.value, RuntimeError)


def test_albedo(ggx):
    quadrature = ggx.albedo(30)
    assert quadrature.shape == (3,) and np.all((quadrature > 0) & (quadrature < 1))
    value, error = ggx.estimate_albedo(btf.direction(30), samples=200_000, seed=2)
    assert np.all(np.abs(value - quadrature) < 5 * error + 1e-3)
    np.testing.assert_allclose(ggx.albedo(btf.direction(30)), quadrature)
    with pytest.raises(ValueError, match="theta"):
        ggx.albedo(120)
