#!/usr/bin/python3
"""Dataset compression on a Dask LocalCluster (btf.dask, docs/dask.md) against one machine.

Generates --materials BTFs with btf-datagen (patterns in turn, seeds apart), then compresses them
  - on one machine into one database with shared codebooks (btf.compress, all cores),
  - with btf.dask on a LocalCluster of 1 and of N worker processes (one thread each, loopback),
    the same partition (--parts, default N) in both, so both write the same database,
and prints wall times (cluster start-up not included), bytes and the mean rel_rmse of the
materials against their inputs. Run with Debian's python3 and the package on its path:

    PYTHONPATH=build/python /usr/bin/python3 tools/bench/dask_scaling.py --materials 8 --size 32

--csv PATH also writes the rows as a CSV (written to PATH.tmp, then renamed; --append adds them to
an existing file, so that runs at several --threads share one table), the file
tools/results/run_benches.sh puts on docs/results.md. Its columns: run (one-machine, 1-worker,
2-workers), workers, threads (library threads per task; the cores for one-machine), parts,
wall_s, bytes, bytes_vs_one_machine, mean_rel_rmse, rel_rmse_vs_one_machine,
max_luminance_over_bound, map_s, reduce_s, recode_s, join_s (the phases of btf.dask), speedup_vs_1_worker
(wall time of 1 worker over this run's) and same_file_as_1_worker.
"""

import argparse
import csv
import os
import shutil
import subprocess
import sys
import tempfile
import time

PATTERNS = ("fabric", "stones", "leather", "print", "paint")


def generate(datagen, folder, count, size, components):
    paths = []
    for i in range(count):
        pattern = PATTERNS[i % len(PATTERNS)]
        path = os.path.join(folder, f"{pattern}{i}.btf")
        subprocess.run([datagen, "btf", "--pattern", pattern, "--size", str(size), "--seed", str(1 + i), "--layout",
                        "fmf", "--components", str(components), "-o", path], check=True, stdout=subprocess.DEVNULL)
        paths.append(path)
    return paths


def mean_error(btf, path, names, inputs):
    errors = btf._core._dataset_errors(path, list(zip(names, inputs)))
    return sum(e["rel_rmse"] for e in errors) / len(errors), max(e["luminance_rel_rmse"] / e["luminance_bound"]
                                                                    for e in errors)


CSV_COLUMNS = ["run", "workers", "threads", "parts", "wall_s", "bytes", "bytes_vs_one_machine", "mean_rel_rmse",
               "rel_rmse_vs_one_machine", "max_luminance_over_bound", "map_s", "reduce_s", "recode_s", "join_s",
               "speedup_vs_1_worker", "same_file_as_1_worker"]


def write_csv(path, rows, append):
    """The rows as a CSV, written to PATH.tmp and renamed, so that PATH is whole or absent; with
    append, after the rows PATH already holds (of the same columns)."""
    old = []
    if append and os.path.exists(path):
        with open(path, newline="") as f:
            reader = csv.DictReader(f)
            if reader.fieldnames != CSV_COLUMNS:
                sys.exit(f"{path}: its columns are not this script's; cannot append")
            old = list(reader)
    tmp = f"{path}.tmp"
    with open(tmp, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=CSV_COLUMNS)
        writer.writeheader()
        writer.writerows(old + rows)
    os.replace(tmp, path)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--materials", type=int, default=8)
    parser.add_argument("--size", type=int, default=32)
    parser.add_argument("--components", type=int, default=32, help="FMF components of the generated .btf files")
    parser.add_argument("--epsilon", type=float, default=0.05)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--parts", type=int, help="parts of the partition (default: --workers)")
    parser.add_argument("--threads", type=int, default=0,
                        help="library threads per task (0: the host's cores shared among its worker threads, so one "
                             "worker uses every core; 1: one core per worker, the scaling of workers alone)")
    parser.add_argument("--inputs", nargs="*", help="use these inputs instead of generated ones")
    parser.add_argument("--datagen", default=os.environ.get("BTF_DATAGEN") or shutil.which("btf-datagen"))
    parser.add_argument("--csv", metavar="PATH", help="also write the rows as a CSV (written atomically)")
    parser.add_argument("--append", action="store_true", help="with --csv: add the rows to PATH if it exists")
    args = parser.parse_args()

    import btf
    import btf.dask
    import distributed

    folder = tempfile.mkdtemp(prefix="btf-dask-bench-")
    try:
        if args.inputs:
            inputs = args.inputs
        else:
            if not args.datagen:
                sys.exit("btf-datagen not found: give --datagen or --inputs")
            t = time.perf_counter()
            inputs = generate(args.datagen, folder, args.materials, args.size, args.components)
            print(f"generated {len(inputs)} BTFs of {args.size} x {args.size} texels in {time.perf_counter() - t:.1f} s")
        names = [btf._core._dataset_describe(p)["name"] for p in inputs]
        parts = args.parts or args.workers

        single_path = os.path.join(folder, "single.btfz")
        t = time.perf_counter()
        single = btf.compress(inputs, single_path, epsilon=args.epsilon, verify=False)
        single_s = time.perf_counter() - t
        single_err, single_bound = mean_error(btf, single_path, names, inputs)
        cores = len(os.sched_getaffinity(0))
        rows = [("one machine (btf.compress)", single_s, single["bytes"], single_err, single_bound, None)]
        csv_rows = [dict(run="one-machine", workers=0, threads=cores, parts=1, wall_s=single_s, bytes=single["bytes"],
                         mean_rel_rmse=single_err, max_luminance_over_bound=single_bound)]

        files = {}
        for workers in sorted({1, args.workers}):
            os.environ["PYTHONPATH"] = os.pathsep.join(
                [os.path.dirname(os.path.dirname(btf.__file__))] + os.environ.get("PYTHONPATH", "").split(os.pathsep))
            with distributed.LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, host="127.0.0.1",
                                          dashboard_address=None) as cluster, distributed.Client(cluster) as client:
                path = os.path.join(folder, f"dask{workers}.btfz")
                t = time.perf_counter()
                report = btf.dask.compress_dataset(inputs, path, client=client, parts=parts, epsilon=args.epsilon,
                                                   threads=args.threads, verify=False, progress=False)
                seconds = time.perf_counter() - t
            err, bound = mean_error(btf, path, names, inputs)
            files[workers] = open(path, "rb").read()
            rows.append((f"btf.dask, {workers} worker{'s' if workers > 1 else ''}, {report['parts']} parts", seconds,
                         report["bytes"], err, bound, report["seconds"]))
            csv_rows.append(dict(run=f"{workers}-worker{'s' if workers > 1 else ''}", workers=workers,
                                 threads=args.threads or max(1, cores // workers), parts=report["parts"],
                                 wall_s=seconds, bytes=report["bytes"], mean_rel_rmse=err,
                                 max_luminance_over_bound=bound,
                                 **{f"{k}_s": report["seconds"][k] for k in ("map", "reduce", "recode", "join")
                                    if k in report["seconds"]}))

        print(f"{len(inputs)} materials, epsilon {args.epsilon}, {len(os.sched_getaffinity(0))} cores, "
              f"threads per task {args.threads or 'cores / worker threads'}")
        print(f"{'run':<36} {'wall_s':>8} {'bytes':>9} {'bytes/1m':>9} {'rel_rmse':>9} {'err/1m':>7} "
              f"{'max lum/bound':>13}  phases (s)")
        for name, seconds, nbytes, err, bound, phases in rows:
            phase_text = "" if phases is None else ", ".join(
                f"{k} {v:.1f}" for k, v in phases.items() if k in ("map", "reduce", "recode", "join"))
            print(f"{name:<36} {seconds:>8.2f} {nbytes:>9d} {nbytes / single['bytes']:>9.3f} {err:>9.5f} "
                  f"{err / single_err:>7.3f} {bound:>13.3f}  {phase_text}")
        if len(rows) == 3:
            print(f"speed-up of {args.workers} workers over 1: {rows[1][1] / rows[2][1]:.2f}x; "
                  f"same file: {files[1] == files[args.workers]}")
        if args.csv:
            one_worker_s = csv_rows[1]["wall_s"]
            for row in csv_rows:
                row["bytes_vs_one_machine"] = row["bytes"] / single["bytes"]
                row["rel_rmse_vs_one_machine"] = row["mean_rel_rmse"] / single_err
                if row["workers"]:
                    row["speedup_vs_1_worker"] = one_worker_s / row["wall_s"]
                    row["same_file_as_1_worker"] = int(files[row["workers"]] == files[1])
                for key, value in row.items():
                    if isinstance(value, float):
                        row[key] = f"{value:.6g}"
            write_csv(args.csv, csv_rows, args.append)
    finally:
        shutil.rmtree(folder, ignore_errors=True)


if __name__ == "__main__":
    main()
