"""btf.BtfSource, open_btf, compress / decompress / merge / compare."""

import numpy as np
import pytest

import btf


def test_open_btf_shapes(btf_folder):
    b = btf.open_btf(btf_folder)
    assert (b.width, b.height) == (8, 8)
    assert b.views == list(range(81))
    assert b.view_directions.shape == (81, 3)
    np.testing.assert_allclose(np.linalg.norm(b.view_directions, axis=1), 1, rtol=1e-6)
    assert b.light_directions(0).shape == (81, 3)
    view = b.load_view(40)
    assert view.shape == (81, 8, 8, 3) and view.dtype == np.float32
    assert view.base is not None  # owns the library's buffer, no copy
    assert np.all(np.isfinite(view)) and np.all(view >= 0) and view.max() > 0
    assert b.entry_count == 81 * 81 * 64
    with pytest.raises(IndexError):
        b.load_view(81)


def test_one_texel_btf_holds_the_brdf(table_path):
    """A BRDF as a BTF: value(view, light) = f(light, view) at the set's directions."""
    b = btf.open_btf(table_path)
    m = btf.open(table_path)
    assert (b.width, b.height) == (1, 1)
    for view in (0, 17, 60):
        wo = b.view_directions[view]
        values = b.load_view(view)[:, 0, 0, :]
        np.testing.assert_allclose(values, m.eval(b.light_directions(view), wo), rtol=1e-6, atol=0)


def test_compress_decompress_round_trip(btf_folder, data_dir):
    out = data_dir / "fabric.btfz"
    epsilon = 0.05
    report = btf.compress(btf_folder, out, epsilon=epsilon, levels=3)
    assert report["output"] == str(out) and out.exists()
    assert report["bytes"] == out.stat().st_size
    assert report["ratio_u8"] > 1 and report["epsilon"] == epsilon
    assert report["texels"] == (8, 8) and len(report["views"]) == 81
    # epsilon is a relative L2 tolerance per level: the whole BTF's rel_rmse is within it.
    assert 0 < report["rel_rmse"] <= epsilon

    decoded = btf.decompress(out)
    original = btf.open_btf(btf_folder)
    num = den = 0.0
    for v in original.views:
        a, b = decoded.load_view(v).astype(np.float64), original.load_view(v).astype(np.float64)
        num += np.sum((a - b) ** 2)
        den += np.sum(b ** 2)
    assert np.sqrt(num / den) == pytest.approx(report["rel_rmse"], rel=1e-3)
    assert btf.compare(out, btf_folder)["rel_rmse"] == pytest.approx(report["rel_rmse"], rel=1e-9)

    folder = data_dir / "fabric-decoded"
    again = btf.decompress(out, folder, format="exr")
    assert folder.is_dir() and (again.width, again.height) == (8, 8)
    assert btf.compare(folder, out)["rel_rmse"] < 1e-3


def test_compress_a_source_object_and_refusals(table_path, data_dir):
    source = btf.open_btf(table_path)
    report = btf.compress(source, data_dir / "table.btfz", epsilon=0.05, verify=False)
    assert "rel_rmse" not in report and report["texels"] == (1, 1)
    with pytest.raises(btf.FileError, match="must end in .btfz"):
        btf.compress(table_path, data_dir / "table.zip")
    with pytest.raises(btf.FileError, match="already compressed"):
        btf.compress(data_dir / "table.btfz", data_dir / "again.btfz")


def test_database_and_merge(table_path, rgl_path, data_dir):
    a, b = data_dir / "a.btfz", data_dir / "b.btfz"
    btf.compress(table_path, a, epsilon=0.05, verify=False)
    btf.compress(rgl_path, b, epsilon=0.05, verify=False)
    merged = btf.merge([a, b], data_dir / "merged.btfz")
    assert merged["materials"] == ["plastic-red", "paper_white_rgb"]
    assert merged["bytes"] == (data_dir / "merged.btfz").stat().st_size
    # Lossless: each material decodes as it did in its own file.
    alone = btf.open_btf(a).load_view(5)
    joined = btf.open_btf(data_dir / "merged.btfz", material="plastic-red").load_view(5)
    np.testing.assert_array_equal(alone, joined)

    database = btf.compress([table_path, rgl_path], data_dir / "db.btfz", epsilon=0.05)
    assert [m["name"] for m in database["materials"]] == ["plastic-red", "paper_white_rgb"]
    assert all(m["rel_rmse"] <= 0.05 for m in database["materials"])
