"""btf.dask: a dataset compressed on a LocalCluster of worker processes (loopback only) is a valid
database of the single-machine format and size, every material within the bound the library
guarantees; tiles of one BTF join into one material; a worker killed in mid-task either costs
nothing (the task runs again) or fails the job with a clear error, never leaving an output file;
bad inputs are refused before any task is sent out."""

import os
import shutil
import signal
import subprocess
import sys
import threading
import time

import pytest

if os.environ.get("BTF_PYTHON_PATH"):
    sys.path.insert(0, os.environ["BTF_PYTHON_PATH"])
    # Worker processes import the same package.
    os.environ["PYTHONPATH"] = os.pathsep.join(
        [os.environ["BTF_PYTHON_PATH"]] + [p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p])

distributed = pytest.importorskip("distributed")
import dask  # noqa: E402

import btf  # noqa: E402
import btf.dask  # noqa: E402

PATTERNS = ("fabric", "stones", "leather", "print")
NAMES = [f"{p}.btf" for p in PATTERNS]  # a Bonn file's material is named after the file


def _datagen():
    found = os.environ.get("BTF_DATAGEN") or shutil.which("btf-datagen")
    if not found:
        pytest.skip("btf-datagen not found (set BTF_DATAGEN)")
    return found


def _generate(folder, size, patterns):
    datagen = _datagen()
    paths = []
    for pattern in patterns:
        path = folder / f"{pattern}.btf"
        subprocess.run([datagen, "btf", "--pattern", pattern, "--size", str(size), "--layout", "fmf", "--components",
                        "16", "-o", str(path)], check=True, stdout=subprocess.DEVNULL)
        paths.append(str(path))
    return paths


@pytest.fixture(scope="module")
def inputs(tmp_path_factory):
    return _generate(tmp_path_factory.mktemp("dask-inputs"), 8, PATTERNS)


@pytest.fixture(scope="module")
def larger_inputs(tmp_path_factory):
    """Inputs whose tasks run long enough for a worker to be killed in mid-task."""
    return _generate(tmp_path_factory.mktemp("dask-larger-inputs"), 16, PATTERNS[:2])


def _cluster(workers=2):
    return distributed.LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, host="127.0.0.1",
                                    dashboard_address=None)


@pytest.fixture(scope="module")
def client():
    with _cluster() as cluster, distributed.Client(cluster) as c:
        yield c


def _check_bounds(report):
    for e in report["errors"]:
        assert e["luminance_rel_rmse"] <= e["luminance_bound"], e


def test_dataset_is_a_valid_database_of_the_single_machine_size(inputs, client, tmp_path):
    out = tmp_path / "db.btfz"
    report = btf.dask.compress_dataset(inputs, out, client=client, epsilon=0.05)
    assert report["materials"] == NAMES
    assert report["parts"] == 2 and report["workers"] == 2
    assert os.path.getsize(out) == report["bytes"]
    _check_bounds(report)
    # Readable by the library, each material by name.
    for name in NAMES:
        source = btf.open_btf(str(out), material=name)
        assert (source.width, source.height) == (8, 8)
    # Against the same materials compressed on one machine: about the same bytes and error.
    single = btf.compress(inputs, str(tmp_path / "single.btfz"), epsilon=0.05, verify=False)
    assert report["bytes"] <= 1.10 * single["bytes"], (report["bytes"], single["bytes"])
    alone = btf.dask._core._dataset_errors(str(tmp_path / "single.btfz"), list(zip(NAMES, inputs)))
    ours = sum(e["rel_rmse"] for e in report["errors"])
    theirs = sum(e["rel_rmse"] for e in alone)
    assert ours <= 1.10 * theirs, (ours, theirs)


def test_the_same_partition_gives_the_same_file(inputs, client, tmp_path):
    a = btf.dask.compress_dataset(inputs[:2], tmp_path / "a.btfz", client=client, parts=2, verify=False)
    b = btf.dask.compress_dataset(inputs[:2], tmp_path / "b.btfz", client=client, parts=2, threads=2, verify=False)
    assert a["parts"] == b["parts"] == 2
    assert (tmp_path / "a.btfz").read_bytes() == (tmp_path / "b.btfz").read_bytes()


def test_tiles_of_one_btf_join_into_one_material(inputs, client, tmp_path):
    out = tmp_path / "tiled.btfz"
    report = btf.dask.compress_dataset(inputs[0], out, client=client, tiles=4, epsilon=0.03)
    assert report["materials"] == ["fabric.btf"]
    assert report["parts"] == 4
    _check_bounds(report)
    source = btf.open_btf(str(out))
    assert (source.width, source.height) == (8, 8)


class _NoCluster:
    """A client that fails the test when anything is sent to it."""

    def __getattr__(self, name):
        raise AssertionError(f"client.{name} was used before the inputs were validated")


def test_bad_inputs_are_refused_before_any_task(inputs, tmp_path):
    missing = str(tmp_path / "missing.btf")
    with pytest.raises(btf.FileError) as e:
        btf.dask.compress_dataset([inputs[0], missing], tmp_path / "out.btfz", client=_NoCluster())
    assert "missing.btf" in str(e.value)
    with pytest.raises(btf.FileError, match="btfz"):
        btf.dask.compress_dataset(inputs, tmp_path / "out.zip", client=_NoCluster())
    with pytest.raises(btf.Error, match="both named"):
        btf.dask.compress_dataset([inputs[0], inputs[0]], tmp_path / "out.btfz", client=_NoCluster())
    with pytest.raises(ValueError, match="epsilon"):
        btf.dask.compress_dataset(inputs, tmp_path / "out.btfz", client=_NoCluster(), epsilon=1.5)
    with pytest.raises(btf.FileError, match="folder"):
        btf.dask.compress_dataset(inputs, tmp_path / "no" / "out.btfz", client=_NoCluster())
    assert not (tmp_path / "out.btfz").exists()


def _kill_a_worker_in_mid_task(client, prefix, timeout=60):
    """SIGKILLs the process of the first worker seen processing a task whose key starts with `prefix`."""
    pids = client.run(os.getpid)
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        for address, keys in client.processing().items():
            if any(str(k).startswith(prefix) for k in keys):
                os.kill(pids[address], signal.SIGKILL)
                return address
        time.sleep(0.005)
    raise AssertionError(f"no task {prefix}* was seen running")


def _run_in_thread(call):
    box = {}

    def run():
        try:
            box["report"] = call()
        except BaseException as e:  # noqa: B036 (handed to the test thread)
            box["error"] = e

    thread = threading.Thread(target=run)
    thread.start()
    return thread, box


def _leftovers(folder):
    return sorted(p.name for p in folder.iterdir())


def test_a_worker_killed_in_mid_task_costs_nothing(larger_inputs, tmp_path):
    # The nanny starts a new worker; the scheduler runs the lost task again (it is pure).
    out = tmp_path / "db.btfz"
    with _cluster() as cluster, distributed.Client(cluster) as c:
        thread, box = _run_in_thread(
            lambda: btf.dask.compress_dataset(larger_inputs, out, client=c, parts=2, epsilon=0.05))
        _kill_a_worker_in_mid_task(c, "btf-recode")
        thread.join(180)
    assert "error" not in box, box.get("error")
    _check_bounds(box["report"])
    assert box["report"]["materials"] == NAMES[:2]
    assert _leftovers(tmp_path) == ["db.btfz"]


def test_a_job_that_loses_its_workers_fails_clearly_without_output(larger_inputs, tmp_path):
    # With no failure allowed, the first worker lost in mid-task fails the job.
    out = tmp_path / "db.btfz"
    with dask.config.set({"distributed.scheduler.allowed-failures": 0}):
        with _cluster() as cluster, distributed.Client(cluster) as c:
            thread, box = _run_in_thread(lambda: btf.dask.compress_dataset(larger_inputs, out, client=c, parts=2))
            _kill_a_worker_in_mid_task(c, "btf-map")
            thread.join(180)
    assert isinstance(box.get("error"), btf.dask.ClusterError), box
    assert "nothing was written" in str(box["error"])
    assert _leftovers(tmp_path) == []


def test_command_line(inputs, tmp_path):
    help_text = subprocess.run([sys.executable, "-m", "btf.dask", "--help"], check=True, capture_output=True,
                               text=True).stdout
    assert "--scheduler" in help_text and "--local-workers" in help_text
    out = tmp_path / "cli.btfz"
    run = subprocess.run([sys.executable, "-m", "btf.dask", *inputs[:2], "-o", str(out), "--local-workers", "2",
                          "--epsilon", "0.05"], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    assert "2 materials" in run.stdout
    assert out.exists()
    bad = subprocess.run([sys.executable, "-m", "btf.dask", str(tmp_path / "nothing"), "-o", str(tmp_path / "x.btfz"),
                          "--local-workers", "1"], capture_output=True, text=True)
    assert bad.returncode == 1 and "nothing" in bad.stderr
