"""btf.render and btf.fit."""

import numpy as np
import pytest

import btf


def test_render_cornell_to_numpy(cornell_scene):
    image = btf.render(cornell_scene, spp=1, width=16, height=12, seed=3)
    assert image.shape == (12, 16, 3) and image.dtype == np.float32
    assert np.all(np.isfinite(image)) and image.mean() > 0
    again, stats = btf.render(cornell_scene, spp=1, width=16, height=12, seed=3, return_stats=True)
    np.testing.assert_array_equal(image, again)  # deterministic for a seed
    assert stats["spp"] == 1 and stats["width"] == 16 and stats["rays"] > 0


def test_render_missing_scene(tmp_path):
    with pytest.raises(btf.FileError, match="missing-scene.json"):
        btf.render(tmp_path / "missing-scene.json", spp=1)


def test_fit_recovers_a_ggx():
    truth = btf.create({"type": "ggx", "diffuse": [0.3, 0.2, 0.1], "f0": 0.05, "alpha": 0.15})
    fit = btf.fit(truth, model="ggx", starts=2)
    assert fit.model == "ggx"
    p = fit.parameters
    assert p["alpha"] == pytest.approx(0.15, rel=0.1)
    np.testing.assert_allclose(p["diffuse"], [0.3, 0.2, 0.1], atol=0.02)
    assert fit.rel_rmse < 0.1 and fit.warnings == []
    assert [a["theta_o_deg"] for a in fit.albedo] == [0, 30, 60]
    assert all(a["rel_error"] < 0.05 for a in fit.albedo)
    # The fitted model is a material, and the same one a parameter set builds.
    rebuilt = btf.create({"type": fit.model, **p})
    wi, wo = btf.directions([10, 40, 70], 180), btf.direction(30)
    np.testing.assert_allclose(rebuilt.eval(wi, wo), fit.material.eval(wi, wo), rtol=1e-5)


def test_fit_file_round_trip(table_path, tmp_path):
    fit = btf.fit(table_path, model="ggx", starts=1)
    path = tmp_path / "fit.json"
    fit.save(path)
    reopened = btf.open(path)
    wi, wo = btf.directions([10, 40], 180), btf.direction(30)
    np.testing.assert_allclose(reopened.eval(wi, wo), fit.material.eval(wi, wo), rtol=1e-5)
    with pytest.raises(btf.Error, match="nosuchmodel"):
        btf.fit(table_path, model="nosuchmodel")
