"""What the Python binding costs per sample: Material.eval and Material.sample through btf (numpy
in, numpy out, the GIL released) against the library's own C++ calls on the same arrays, timed in
C++ by btf._bench (Material::evalMany, the stream call; a C++ loop of Material::sample, which has
no stream form). Prints seconds per call and the ratio Python / C++ for each material and N;
"eval out" passes a preallocated result (out=), as the C++ timing does.
The goal: a ratio of at most 1.2 for N >= 1e5.

    /usr/bin/python3 tools/bench/python_overhead.py [--build build-py] [--repeats 5] [--csv out.csv]

--csv writes the same rows as a CSV (material, call, n, python_s_per_sample, cpp_s_per_sample,
ratio), the file tools/results/run_benches.sh puts on docs/results.md.

Materials: a GGX, a MERL-layout table made by btf-datagen (preset plastic-red; BTF_DATAGEN names
the program, default the build folder's bin/btf-datagen), and the shared RGL file
paper_white_rgb.bsdf when the shared data is beside the checkout.
"""

import argparse
import csv
import os
import pathlib
import subprocess
import sys
import tempfile
import time

repo = pathlib.Path(__file__).resolve().parents[2]
parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
parser.add_argument("--build", default=None, help="build folder whose python/ and bin/ to use (default: build-py, then build)")
parser.add_argument("--repeats", type=int, default=5, help="runs per timing; the fastest counts")
parser.add_argument("--sizes", default="100000,1000000", help="comma-separated N")
parser.add_argument("--csv", default=None, metavar="PATH", help="also write the rows as a CSV (written atomically)")
args = parser.parse_args()
build = pathlib.Path(args.build) if args.build else next(
    (repo / b for b in ("build-py", "build") if (repo / b / "python" / "btf").exists()), repo / "build")
sys.path.insert(0, str(build / "python"))

import numpy as np  # noqa: E402

import btf  # noqa: E402


def fastest(repeats, call):
    best = float("inf")
    for _ in range(repeats):
        start = time.perf_counter()
        call()
        best = min(best, time.perf_counter() - start)
    return best


def materials(folder):
    yield "ggx", btf.create({"type": "ggx", "diffuse": [0.5, 0.1, 0.1], "f0": 0.04, "alpha": 0.2})
    table = folder / "plastic-red.binary"
    datagen = os.environ.get("BTF_DATAGEN") or str(build / "bin" / "btf-datagen")
    subprocess.run([datagen, "--preset", "plastic-red", "--seed", "1", "-o", str(table)],
                   check=True, stdout=subprocess.DEVNULL)
    yield "merl table (plastic-red)", btf.open(table)
    rgl = pathlib.Path(os.environ.get("BTF_SHARED_DATA_DIR", repo.parent / "shared" / "data" / "real")) / "rgl_bsdf" / "paper_white_rgb.bsdf"
    if rgl.exists():
        yield "rgl paper_white_rgb", btf.open(rgl)
    else:
        print(f"(no {rgl}: the RGL material is left out)")


def write_csv(path, rows):
    """The rows as a CSV, written to PATH.tmp and renamed, so that PATH is whole or absent."""
    tmp = f"{path}.tmp"
    with open(tmp, "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(["material", "call", "n", "python_s_per_sample", "cpp_s_per_sample", "ratio"])
        writer.writerows(rows)
    os.replace(tmp, path)


def main():
    rows = []
    sizes = [int(float(s)) for s in args.sizes.split(",")]
    wo = btf.direction(35, 10)
    print(f"package: {btf.__file__}; fastest of {args.repeats} alternating runs; ratio = Python / C++ per call")
    print(f"{'material':28s} {'call':8s} {'N':>8s} {'python s':>10s} {'c++ s':>10s} {'ns/sample':>10s} {'ratio':>6s}")
    with tempfile.TemporaryDirectory() as tmp:
        for name, material in materials(pathlib.Path(tmp)):
            for n in sizes:
                rng = np.random.default_rng(1)
                v = rng.normal(size=(n, 3))
                wi = (v / np.linalg.norm(v, axis=1, keepdims=True)).astype(np.float32)
                wi[:, 2] = np.abs(wi[:, 2])
                u = rng.random((n, 2)).astype(np.float32)
                material.eval(wi[:1000], wo)  # first-call set-up out of the timing
                buffer = np.empty((n, 3), np.float32)
                # Python and C++ runs alternate, the fastest of each counting, so that a change of
                # the machine's load during the run weighs on both alike.
                best = {}
                for _ in range(args.repeats):
                    for key, call in (("py_eval", lambda: material.eval(wi, wo)),
                                      ("py_eval_out", lambda: material.eval(wi, wo, out=buffer)),
                                      ("py_sample", lambda: material.sample(wo, u))):
                        best[key] = min(best.get(key, float("inf")), fastest(1, call))
                    best["cpp_eval"] = min(best.get("cpp_eval", float("inf")),
                                           btf._bench.eval_stream_seconds(material, wo, wi, 1))
                    best["cpp_sample"] = min(best.get("cpp_sample", float("inf")),
                                             btf._bench.sample_loop_seconds(material, wo, u, 1))
                py_eval, py_eval_out, py_sample = best["py_eval"], best["py_eval_out"], best["py_sample"]
                cpp_eval, cpp_sample = best["cpp_eval"], best["cpp_sample"]
                for call, p, c in (("eval", py_eval, cpp_eval), ("eval out", py_eval_out, cpp_eval),
                                   ("sample", py_sample, cpp_sample)):
                    print(f"{name:28s} {call:8s} {n:8d} {p:10.5f} {c:10.5f} {p / n * 1e9:10.1f} {p / c:6.3f}")
                    rows.append([name, call, n, f"{p / n:.6g}", f"{c / n:.6g}", f"{p / c:.4f}"])
    if args.csv:
        write_csv(args.csv, rows)


main()
