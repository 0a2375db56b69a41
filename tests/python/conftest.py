"""pytest set-up of the Python package's tests.

The package under test is the one a build made: ctest sets BTF_PYTHON_PATH to <build>/python
(python/CMakeLists.txt), which goes first on sys.path. Without it the tests take whatever
`import btf` finds (the .pth file tools/setup/run.sh writes points at build/python).
BTF_DATAGEN names the btf-datagen binary that makes the test data; BTF_SHARED_DATA_DIR the folder
of real measured data (tests of it skip, saying so, when it is absent).
"""

import os
import pathlib
import subprocess
import sys

import pytest

_package_path = os.environ.get("BTF_PYTHON_PATH")
if _package_path:
    sys.path.insert(0, _package_path)

import btf  # noqa: E402  (after the path above)

_REPO = pathlib.Path(__file__).resolve().parents[2]


def _datagen():
    path = os.environ.get("BTF_DATAGEN")
    if path:
        return pathlib.Path(path)
    for build in ("build-py", "build"):
        candidate = _REPO / build / "bin" / "btf-datagen"
        if candidate.exists():
            return candidate
    pytest.skip("btf-datagen not found: set BTF_DATAGEN (ctest does) or build it")


def _shared_data():
    path = os.environ.get("BTF_SHARED_DATA_DIR")
    return pathlib.Path(path) if path else _REPO.parent / "shared" / "data" / "real"


def run_datagen(*args):
    """Runs btf-datagen with these arguments; fails the test with its output if it fails."""
    result = subprocess.run([str(_datagen()), *map(str, args)], capture_output=True, text=True)
    if result.returncode != 0:
        pytest.fail(f"btf-datagen {' '.join(map(str, args))} failed:\n{result.stdout}\n{result.stderr}")
    return result


@pytest.fixture(scope="session")
def data_dir(tmp_path_factory):
    return tmp_path_factory.mktemp("btf-data")


@pytest.fixture(scope="session")
def ggx():
    """A red plastic GGX, from the parameter set a scene would hold."""
    return btf.create({"type": "ggx", "diffuse": [0.5, 0.1, 0.1], "f0": 0.04, "alpha": 0.2})


@pytest.fixture(scope="session")
def table_path(data_dir):
    """A measured-style MERL-layout table (preset plastic-red: noise and holes)."""
    path = data_dir / "plastic-red.binary"
    run_datagen("--preset", "plastic-red", "--seed", "1", "-o", path)
    return path


@pytest.fixture(scope="session")
def rgl_path():
    path = _shared_data() / "rgl_bsdf" / "paper_white_rgb.bsdf"
    if not path.exists():
        pytest.skip(f"the shared RGL file {path} is absent (real data lives beside the checkout)")
    return path


@pytest.fixture(scope="session")
def btf_folder(data_dir):
    """A synthetic measured BTF: 8 x 8 texels at the 81 x 81 UBO2003 directions."""
    path = data_dir / "fabric"
    run_datagen("btf", "--pattern", "fabric", "--size", "8", "--seed", "1", "-o", path)
    return path


@pytest.fixture(scope="session")
def cornell_scene(data_dir):
    """The Cornell box validation scene (its measured materials generated, the RGL one shared)."""
    rgl = _shared_data() / "rgl_bsdf" / "vch_golden_yellow_rgb.bsdf"
    meshes = _shared_data() / "meshes"
    if not rgl.exists() or not meshes.exists():
        pytest.skip(f"the Cornell box needs the shared data ({rgl}, {meshes}), which is absent")
    path = data_dir / "cornell"
    run_datagen("scene", "cornell", "-o", path, "--resolution", "16", "--spp", "1")
    return path / "scene.json"
