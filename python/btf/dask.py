"""Compress a material dataset on a Dask cluster into one .btfz database.

    import btf.dask
    report = btf.dask.compress_dataset(["fabric1/", "fabric2/", "leather.btf"], "db.btfz",
                                       scheduler="tcp://head:8786", epsilon=0.05)
    report = btf.dask.compress_dataset(["carpet.btf"], "carpet.btfz", local_workers=2, tiles=4)

or from a shell: python3 -m btf.dask INPUT... -o OUT.btfz (--scheduler ADDRESS | --local-workers N)

The database has the format of `btf compress A B C db.btfz` (shared level-1, chromaticity and
level-2 codebooks; docs/compress.md), and every material keeps the error bound it has when
compressed alone. The work is map, reduce, re-code, join (compress/vq_dataset.h):

  map      each part (some materials, or one texel tile of one BTF) is compressed alone on a
           worker; its shared codebooks come back as bytes
  reduce   one task merges the parts' codebooks, inserting their entries one by one and reusing an
           entry already merged when within the tolerance (FLANN search)
  re-code  each part is compressed again on a worker, its codebooks starting from the merged ones:
           every reuse is checked against the part's own data, so the result is not a lossy join
  join     the client merges the re-coded parts losslessly (each shared entry stored once) and
           writes the file atomically: a failed or interrupted job leaves no output file

Every task is a pure function of its inputs (the same bytes on any worker, on any retry), so a
task lost with its worker is run again elsewhere. Inputs are paths (or specs) that every worker
opens itself: they must be readable under the same path on every host. Results travel through the
scheduler as bytes; no shared folder is needed. See docs/dask.md.
"""

import argparse
import os
import sys
import time
import urllib.parse

from . import _core
from ._core import Error, FileError

__all__ = ["compress_dataset", "ClusterError", "main"]


class ClusterError(Error):
    """The cluster could not finish the job (workers lost, scheduler gone). Nothing was written."""


# ---- the tasks (run on workers; module-level so that workers import them by name) ------------------

def _task_threads(options, host_threads):
    """The library threads of one task: the host's cores shared among the worker threads on it."""
    if options["threads"] != 0:
        return options
    threads = 0
    try:
        from distributed import get_worker

        worker = get_worker()
        host = urllib.parse.urlparse(worker.address).hostname
        own = worker.state.nthreads if hasattr(worker, "state") else worker.nthreads
        total = max(1, host_threads.get(host, own))
        threads = max(1, len(os.sched_getaffinity(0)) // total)
    except (ImportError, ValueError):
        pass
    return dict(options, threads=threads)


def _map_task(items, options, host_threads):
    return _core._dataset_map(items, _task_threads(options, host_threads))


def _reduce_task(labels, *parts):
    return _core._dataset_merge_codebooks(list(parts), labels)


def _recode_task(items, options, host_threads, seed):
    return _core._dataset_recode(items, _task_threads(options, host_threads), seed)


# ---- the client ------------------------------------------------------------------------------

def _check_options(epsilon, chroma_epsilon, energy_floor, levels):
    if not 0.0 <= epsilon < 1.0:
        raise ValueError(f"epsilon = {epsilon} is invalid: must be in [0, 1)")
    if not 0.001 <= chroma_epsilon <= 1.0:
        raise ValueError(f"chroma_epsilon = {chroma_epsilon} is invalid: must be in [0.001, 1]")
    if not (energy_floor >= 0.0 and energy_floor < float("inf")):
        raise ValueError(f"energy_floor = {energy_floor} is invalid: must be finite and >= 0")
    if levels not in (1, 2, 3):
        raise ValueError(f"levels = {levels} is invalid: must be 1, 2 or 3")


def _check_output(out):
    out = os.fspath(out)
    if not out.endswith(".btfz"):
        raise FileError(out, "the output must end in .btfz")
    folder = os.path.dirname(os.path.abspath(out))
    if not os.path.isdir(folder):
        raise FileError(out, "its folder does not exist")
    if not os.access(folder, os.W_OK):
        raise FileError(out, "its folder is not writable")
    return out


def _balanced_parts(costs, parts):
    """Consecutive runs of the materials (their order kept), `parts` of them, of about equal cost."""
    parts = max(1, min(parts, len(costs)))
    total = float(sum(costs))
    out, run, done = [], [], 0.0
    for i, cost in enumerate(costs):
        run.append(i)
        done += cost
        left_items, left_parts = len(costs) - i - 1, parts - len(out) - 1
        # Close the run at its share of the total, or when the rest is one material per part.
        if left_parts > 0 and (done >= total * (len(out) + 1) / parts or left_items == left_parts):
            out.append(run)
            run = []
    if run:
        out.append(run)
    return out


class _Progress:
    def __init__(self, enabled):
        self.enabled = enabled if enabled is not None else sys.stderr.isatty()

    def __call__(self, text, end="\n"):
        if self.enabled:
            sys.stderr.write(("\r" if end == "" else "") + text + end)
            sys.stderr.flush()


def _local_cluster(workers):
    from distributed import LocalCluster

    # Worker processes import this package: the folder it was imported from goes first on their path.
    package_parent = os.path.dirname(os.path.dirname(os.path.abspath(_core.__file__)))
    paths = [p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p]
    if package_parent not in paths:
        os.environ["PYTHONPATH"] = os.pathsep.join([package_parent] + paths)
    return LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, host="127.0.0.1",
                        dashboard_address=None)


def _wait_phase(futures, name, progress):
    """Waits for the futures in completion order (progress per part); their results, in order."""
    from distributed import as_completed

    done = 0
    for _ in as_completed(futures):
        done += 1
        progress(f"{name}: {done}/{len(futures)} parts", end="")
    progress("")
    return [f.result() for f in futures]


def compress_dataset(inputs, out, *, client=None, scheduler=None, local_workers=None, parts=None, tiles=None,
                     names=None, epsilon=0.02, chroma_epsilon=0.01, energy_floor=1.0, levels=3,
                     level3_exceptions=True, threads=0, retries=1, verify=True, progress=None):
    """compress_dataset(inputs, out, *, client=None, scheduler=None, local_workers=None, parts=None,
                        tiles=None, names=None, epsilon=0.02, chroma_epsilon=0.01, energy_floor=1.0,
                        levels=3, level3_exceptions=True, threads=0, retries=1, verify=True,
                        progress=None) -> dict

    Compresses `inputs` (paths or specs of BTFs and BRDFs, as btf.compress takes them) on a Dask
    cluster into the database `out` (.btfz).

    The cluster: `client` (a distributed.Client), else `scheduler` (an address,
    "tcp://host:8786"), else `local_workers` worker processes on this machine (loopback only).
      parts     materials per part: the inputs cut into this many consecutive runs of about equal
                size (default: one per worker thread, at most one per input)
      tiles     with one input: cut it into this many texel tiles, one part each, joined into one
                material again
      names     material names (default: each input's name)
      epsilon, chroma_epsilon, energy_floor, levels, level3_exceptions: as btf.compress
      threads   library threads per task (0: the host's cores shared among its worker threads);
                the output does not depend on it
      retries   extra attempts of a task that raised (the scheduler reruns tasks lost with a worker
                on its own)
      verify    read the written file back and measure every material against its input
      progress  print progress on stderr (default: when stderr is a terminal)

    Everything is checked before any work is sent out: each input is opened on the client (an
    error names the file), the names, the options and the output's folder. Returns a report: the
    output, materials, bytes, ratio_u8, shared_entries, parts, workers, seconds per phase and, with
    verify, per material rel_rmse, luminance_rel_rmse and the bound the library guarantees for it
    (luminance_bound). Raises btf.Error / btf.FileError for bad inputs (before any task), the
    library's errors from a task as they are, and ClusterError when the cluster fails; in every
    failure no output file is left.
    """
    start = time.perf_counter()
    seconds = {}
    say = _Progress(progress)
    # ---- validation, on the client, before anything is sent out
    if isinstance(inputs, (str, os.PathLike)):
        inputs = [inputs]
    inputs = [os.fspath(p) for p in inputs]
    if not inputs:
        raise ValueError("inputs: expected at least one BTF or BRDF")
    out = _check_output(out)
    _check_options(float(epsilon), float(chroma_epsilon), float(energy_floor), int(levels))
    if tiles is not None and (len(inputs) != 1 or int(tiles) < 1):
        raise ValueError("tiles: splits one input into texel tiles (give one input and tiles >= 1)")
    described = [_core._dataset_describe(p) for p in inputs]
    if names is None:
        names = [d["name"] for d in described]
    names = [str(n) for n in names]
    if len(names) != len(inputs):
        raise ValueError(f"names: {len(names)} names for {len(inputs)} inputs")
    for i, n in enumerate(names):
        if not n:
            raise Error(f"input {inputs[i]} has no name: give names=")
        if n in names[:i]:
            raise Error(f"inputs {inputs[names.index(n)]} and {inputs[i]} are both named '{n}': "
                        "a database needs distinct material names (give names=)")
    options = dict(epsilon=float(epsilon), chroma_epsilon=float(chroma_epsilon), energy_floor=float(energy_floor),
                   levels=int(levels), level3_exceptions=bool(level3_exceptions), threads=int(threads))
    seconds["validate"] = time.perf_counter() - start

    own_client = own_cluster = None
    try:
        try:
            if client is None:
                from distributed import Client

                if scheduler is not None:
                    client = own_client = Client(scheduler)
                elif local_workers:
                    own_cluster = _local_cluster(int(local_workers))
                    client = own_client = Client(own_cluster)
                else:
                    raise ValueError("give a client, a scheduler address or local_workers")
            workers = client.scheduler_info()["workers"]
        except (OSError, TimeoutError) as e:
            raise ClusterError(f"cannot reach the Dask scheduler ({e}); nothing was written to {out}") from e
        if not workers:
            raise ClusterError(f"the Dask cluster has no workers; nothing was written to {out}")
        host_threads = {}
        for address, info in workers.items():
            host = urllib.parse.urlparse(address).hostname
            host_threads[host] = host_threads.get(host, 0) + int(info.get("nthreads", 1))
        worker_threads = sum(host_threads.values())

        # ---- the partition
        tiled = None
        if tiles is not None:
            d = described[0]
            rects = _core._dataset_tiles(d["width"], d["height"], int(tiles))
            part_items = [[(inputs[0], f"{names[0]}@{r[0]},{r[1]}", tuple(r))] for r in rects]
            tiled = dict(name=names[0], width=d["width"], height=d["height"], rects=rects)
        else:
            count = int(parts) if parts else worker_threads
            runs = _balanced_parts([d["values"] for d in described], count)
            part_items = [[(inputs[i], names[i], None) for i in run] for run in runs]
        labels = [f"part {k + 1} ({', '.join(item[1] for item in items)})" for k, items in enumerate(part_items)]

        from distributed import KilledWorker

        try:
            t = time.perf_counter()
            mapped = [client.submit(_map_task, items, options, host_threads, pure=True, retries=retries,
                                    key=f"btf-map-{k}-{_token(items, options)}")
                      for k, items in enumerate(part_items)]
            _wait_phase(mapped, "map", say)
            seconds["map"] = time.perf_counter() - t
            t = time.perf_counter()
            seed = client.submit(_reduce_task, labels, *mapped, pure=True, retries=retries,
                                 key=f"btf-reduce-{_token(part_items, options)}")
            _wait_phase([seed], "reduce", say)
            seconds["reduce"] = time.perf_counter() - t
            t = time.perf_counter()
            recoded = [client.submit(_recode_task, items, options, host_threads, seed, pure=True, retries=retries,
                                     key=f"btf-recode-{k}-{_token(items, options, part_items)}")
                       for k, items in enumerate(part_items)]
            results = _wait_phase(recoded, "re-code", say)
            seconds["recode"] = time.perf_counter() - t
            del mapped, seed, recoded
        except KilledWorker as e:
            raise ClusterError(f"the Dask job lost its workers too often ({e}); nothing was written to {out}") from e
        except (OSError, TimeoutError) as e:
            if isinstance(e, FileError):
                raise
            raise ClusterError(f"the Dask job failed ({type(e).__name__}: {e}); nothing was written to {out}") from e
    finally:
        if own_client is not None:
            own_client.close()
        if own_cluster is not None:
            own_cluster.close()

    # ---- the join, on the client: the one write, atomic
    t = time.perf_counter()
    report = _core._dataset_join(results, labels, out, tiled)
    seconds["join"] = time.perf_counter() - t
    report["parts"] = len(part_items)
    report["workers"] = len(workers)
    report["worker_threads"] = worker_threads
    report.update(epsilon=options["epsilon"], chroma_epsilon=options["chroma_epsilon"],
                  energy_floor=options["energy_floor"], levels=options["levels"])
    if verify:
        t = time.perf_counter()
        pairs = [(names[0], inputs[0])] if tiled else list(zip(names, inputs))
        report["errors"] = _core._dataset_errors(out, pairs)
        seconds["verify"] = time.perf_counter() - t
    seconds["total"] = time.perf_counter() - start
    report["seconds"] = seconds
    return report


def _token(*values):
    from dask.base import tokenize

    return tokenize(*values)


# ---- the command line --------------------------------------------------------------------------

def main(argv=None):
    parser = argparse.ArgumentParser(
        prog="python3 -m btf.dask",
        description="Compress a material dataset on a Dask cluster into one .btfz database with shared "
                    "codebooks (the format of `btf compress A B C db.btfz`). See docs/dask.md.")
    parser.add_argument("inputs", nargs="+", help="BTFs and BRDFs (paths readable on every worker, or specs)")
    parser.add_argument("-o", "--output", required=True, help="the database to write (.btfz), written atomically")
    where = parser.add_mutually_exclusive_group(required=True)
    where.add_argument("--scheduler", metavar="ADDRESS", help="a running scheduler, e.g. tcp://head:8786")
    where.add_argument("--local-workers", metavar="N", type=int, help="N worker processes on this machine")
    parser.add_argument("--parts", type=int, help="parts the inputs are cut into (default: one per worker thread)")
    parser.add_argument("--tiles", type=int, help="one input: cut it into N texel tiles, joined into one material")
    parser.add_argument("--epsilon", type=float, default=0.02, help="relative L2 tolerance per level (0.02)")
    parser.add_argument("--chroma-epsilon", type=float, default=0.01, help="chromaticity tolerance (0.01)")
    parser.add_argument("--energy-floor", type=float, default=1.0, help="tolerance floor in batch RMS norms (1)")
    parser.add_argument("--levels", type=int, default=3, choices=(1, 2, 3), help="VQ levels (3)")
    parser.add_argument("--no-level3-exceptions", action="store_true", help="store every level-3 entry whole")
    parser.add_argument("--threads", type=int, default=0, help="library threads per task (0: the cores per worker thread)")
    parser.add_argument("--no-verify", action="store_true", help="skip measuring the written file against the inputs")
    parser.add_argument("--json", action="store_true", help="print the report as JSON")
    args = parser.parse_args(argv)
    # Through the package's module (not this __main__ copy), so that workers find the tasks by name.
    from btf import dask as this

    try:
        report = this.compress_dataset(
            args.inputs, args.output, scheduler=args.scheduler, local_workers=args.local_workers, parts=args.parts,
            tiles=args.tiles, epsilon=args.epsilon, chroma_epsilon=args.chroma_epsilon,
            energy_floor=args.energy_floor, levels=args.levels, level3_exceptions=not args.no_level3_exceptions,
            threads=args.threads, verify=not args.no_verify)
    except (Error, ValueError) as e:
        print(f"python3 -m btf.dask: {e}", file=sys.stderr)
        return 1
    if args.json:
        import json

        print(json.dumps(report, indent=2))
        return 0
    s = report["seconds"]
    print(f"{report['output']}: {len(report['materials'])} materials, {report['bytes']} bytes "
          f"(ratio_u8 {report['ratio_u8']:.1f}), {report['parts']} parts on {report['workers']} workers")
    print("seconds: " + ", ".join(f"{k} {v:.2f}" for k, v in s.items()))
    for e in report.get("errors", []):
        print(f"  {e['name']}: rel_rmse {e['rel_rmse']:.5f}, luminance {e['luminance_rel_rmse']:.5f} "
              f"(bound {e['luminance_bound']:.5f})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
