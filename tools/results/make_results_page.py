#!/usr/bin/python3
"""Write docs/results.md from the output folders of `btf bench` runs.

Usage:
    /usr/bin/python3 tools/results/make_results_page.py RUN_DIR [RUN_DIR...] [-o docs/results.md]

Each RUN_DIR is searched recursively for the files the benches write:

    sampling.csv                    btf bench sampling -o DIR
    warp_comparison.csv             btf bench sampling -o DIR (with the dj-warp sampler)
    rgl_writer.csv                  btf bench rgl-writer -o DIR
    compression.csv                 btf bench compression -o DIR
    compression_scaling.csv         btf bench compression --scaling -o DIR
    bonn.csv                        btf bench bonn -o DIR
    brdf_compression.csv            btf bench compression -o DIR (unless --no-brdfs)
    compressibility.csv             btf bench compressibility -o DIR
    fits.csv                        btf bench fits -o DIR
    samplers.csv, summary.txt       btf bench render -o DIR
    decode*.json                    btf bench decode FILE --json > DIR/decode.json
    python_overhead.csv             tools/bench/python_overhead.py --csv DIR/python_overhead.csv
    dask_scaling.csv                tools/bench/dask_scaling.py --csv DIR/dask_scaling.csv

and, when tools/results/run_benches.sh made the folder, commands.txt (the commands it ran) and
meta.json (date and commit of the run). Any other CSV found is tabulated whole. With several
folders (e.g. a full run, then a run of a few benches with BTF_BENCHES), a file of a later folder
replaces the file at the same place in an earlier one, and each section names the run it is from. Nothing on the
page is typed by hand: every figure comes from those files, and the page says which commands
wrote them, on which commit and machine. Standard library only (Debian's /usr/bin/python3).
"""

import argparse
import csv
import datetime
import json
import os
import platform
import subprocess
import sys
from pathlib import Path

# Per known file: title, the command that writes it, and the columns worth a table (those present
# are shown, in this order; a file without any of them is shown whole).
KNOWN = {
    "sampling.csv": (
        "Sampling: samplers × materials",
        "btf bench sampling",
        ["material", "theta_o_deg", "sampler", "parameterization", "parameter", "bytes", "full_cdf_bytes",
         "samples_per_s", "stream_samples_per_s", "chi2_p", "fcos_rel_variance", "efficiency_vs_own",
         "stream_efficiency_vs_own", "acceptance_rate"],
    ),
    "warp_comparison.csv": (
        "Sampling: DP-CDF against the Dupuy–Jakob warp at equal memory",
        "btf bench sampling --as-tables (with dj-warp)",
        ["material", "theta_o_deg", "warp_bytes", "dp_cdf_bytes", "dp_cdf_parameterization", "dp_cdf_epsilon",
         "efficiency_vs_warp", "stream_efficiency_vs_warp", "warp_variance_over_dp_cdf"],
    ),
    "rgl_writer.csv": (
        "RGL writer: what a .bsdf written by virtual acquisition loses",
        "btf bench rgl-writer",
        ["material", "bytes", "seconds", "fcos_rel_rmse", "max_albedo_rel_error", "spectral_albedo_rel_error",
         "grazing_albedo_rel_error", "albedo_0", "reference_albedo_0",
         "albedo_60", "reference_albedo_60", "albedo_75", "reference_albedo_75", "chi2_p_0", "chi2_p_30", "chi2_p_60",
         "chi2_p_80"],
    ),
    "compression.csv": (
        "Compression: VQ against PCA",
        "btf bench compression",
        ["method", "material", "texels", "epsilon", "levels", "components", "bytes", "ratio_u8", "rel_rmse",
         "psnr_db", "mean_ssim", "rel_rmse_display", "noise_rel_rmse", "compression_s", "evals_per_s"],
    ),
    "compression_scaling.csv": (
        "Compression: time against texels and directions",
        "btf bench compression --scaling",
        ["study", "set", "side", "texels", "pairs", "seconds", "texel_directions_per_s_per_core", "level1_entries",
         "level2_entries", "level3_entries", "bytes"],
    ),
    "bonn.csv": (
        "Compression against the downloaded file: Bonn dome DFMF inputs, the .btfz and the DFMF at equal bytes",
        "btf bench bonn",
        ["side", "texels", "input_bytes", "method", "epsilon", "form", "components", "bytes", "ratio_input", "rel_rmse",
         "mean_ssim", "seconds", "peak_memory_mib", "generate_s"],
    ),
    "brdf_compression.csv": (
        "Compression: BRDFs as one-texel .btfz",
        "btf bench compression",
        ["material", "btfz_bytes", "source_bytes", "rel_rmse"],
    ),
    "compressibility.csv": (
        "Compressibility: how far the data compresses at all",
        "btf bench compressibility",
        ["pattern", "size", "texels", "directions", "epsilon", "nn_p10", "nn_p50", "nn_p90", "greedy_entries",
         "reuse_factor", "rank", "ratio_u8_bound", "seconds"],
    ),
    "fits.csv": (
        "Fits: ours beside the published MERL fits",
        "btf bench fits",
        ["material", "reference", "model", "ours", "rel_rmse", "albedo_error", "converged", "seconds"],
    ),
    "samplers.csv": (
        "Rendering: samplers at equal time",
        "btf bench render",
        ["sampler", "spp", "seconds", "relmse", "rel_rmse", "efficiency"],
    ),
    "python_overhead.csv": (
        "Python: a vectorised call against the C++ stream call",
        "tools/bench/python_overhead.py",
        ["material", "call", "n", "python_s_per_sample", "cpp_s_per_sample", "ratio"],
    ),
    "dask_scaling.csv": (
        "Dask: a dataset compressed on 1 and 2 workers against one machine",
        "tools/bench/dask_scaling.py",
        ["run", "workers", "threads", "parts", "wall_s", "bytes", "bytes_vs_one_machine", "mean_rel_rmse",
         "rel_rmse_vs_one_machine", "max_luminance_over_bound", "map_s", "reduce_s", "recode_s", "join_s",
         "speedup_vs_1_worker", "same_file_as_1_worker"],
    ),
}
ORDER = ["sampling.csv", "warp_comparison.csv", "rgl_writer.csv", "compression.csv", "compression_scaling.csv", "bonn.csv",
         "brdf_compression.csv", "compressibility.csv", "fits.csv", "samplers.csv", "python_overhead.csv",
         "dask_scaling.csv"]
MAX_ROWS = 60


def fmt(value):
    """A CSV cell for a table: numbers to 4 significant digits, text as it is."""
    text = value.strip()
    if text == "":
        return ""
    try:
        number = float(text)
    except ValueError:
        return text.replace("|", "\\|")
    if number != number:  # NaN
        return "nan"
    if number.is_integer() and abs(number) < 1e15 and "e" not in text.lower() and "." not in text:
        return f"{int(number):,}"
    if number == 0:
        return "0"
    if 1e-3 <= abs(number) < 1e6:
        return f"{number:.4g}"
    return f"{number:.3g}"


def table(header, rows):
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    for row in rows:
        lines.append("| " + " | ".join(row) + " |")
    return "\n".join(lines)


def csv_section(path, root, columns):
    with open(path, newline="") as f:
        reader = csv.DictReader(f)
        fields = reader.fieldnames or []
        records = list(reader)
    shown = [c for c in columns if c in fields] if columns else []
    if not shown:
        shown = fields
    rows = [[fmt(r.get(c) or "") for c in shown] for r in records[:MAX_ROWS]]
    out = [f"`{path.relative_to(root)}`, {len(records)} rows"
           + (f" (the first {MAX_ROWS} shown)" if len(records) > MAX_ROWS else "")
           + (f"; columns shown: {len(shown)} of {len(fields)}" if len(shown) < len(fields) else "") + ":", ""]
    out.append(table(shown, rows) if rows else "(no rows)")
    return "\n".join(out)


def fit_tables_summary(path):
    """Per model, from a `btf bench fits --tables` CSV: how many tables keep the albedo within 10%
    at theta_o 0/30/60, the median rel_rmse, how often rel_rmse is at most the best published
    fit's (SGD or ABC) on the same table, and the fit times."""
    with open(path, newline="") as f:
        records = list(csv.DictReader(f))
    if not any((r.get("albedo_error") or "").strip() for r in records):
        return None
    published = {}
    for r in records:
        if r["ours"] == "0" and r["model"] in ("sgd", "abc"):
            value = float(r["rel_rmse"])
            published[r["material"]] = min(published.get(r["material"], value), value)
    rows = []
    for model in sorted({r["model"] for r in records}):
        mine = [r for r in records if r["model"] == model]
        errors = sorted(float(r["rel_rmse"]) for r in mine)
        albedo = [float(r["albedo_error"]) for r in mine if (r.get("albedo_error") or "").strip()]
        compared = [r for r in mine if r["material"] in published]
        beats = sum(float(r["rel_rmse"]) <= published[r["material"]] for r in compared)
        seconds = sorted(float(r["seconds"]) for r in mine)
        ours = mine[0]["ours"] == "1"
        rows.append([model, str(len(mine)), f"{sum(a <= 0.1 for a in albedo)} of {len(albedo)}",
                     fmt(str(errors[len(errors) // 2])),
                     f"{beats} of {len(compared)}" if ours and compared else "",
                     fmt(str(seconds[len(seconds) // 2])) if ours else "", fmt(str(seconds[-1])) if ours else ""])
    header = ["model", "tables", "albedo within 10% at 0/30/60°", "median rel_rmse", "rel_rmse ≤ best published",
              "median s", "max s"]
    text = ("Per model (computed from the CSV; \"best published\" is the lower of the SGD and ABC fits' rel_rmse "
            "on the same table):\n\n" + table(header, rows))
    default = [r for r in records if r["model"] == "ours:default"]
    if default:  # the time goal is per table: each table's default fit, its figures and seconds
        per_table = [[r["material"], fmt(r["rel_rmse"]), fmt(r.get("albedo_error") or ""),
                      fmt(str(published[r["material"]])) if r["material"] in published else "", fmt(r["seconds"])]
                     for r in sorted(default, key=lambda r: r["material"])]
        text += ("\n\nThe default fit (`btf fit` without `--model`) per table, seconds as the run's `--threads` "
                 "allowed (the command above):\n\n"
                 + table(["table", "rel_rmse", "albedo error", "best published rel_rmse", "seconds"], per_table))
    return text


def decode_section(path, root):
    with open(path) as f:
        data = json.load(f)
    keys = ["file", "texels", "views", "samples", "repeats", "table_MB", "value_per_s", "values_per_s",
            "lafortune_per_s", "value_vs_lafortune", "values_vs_lafortune"]
    rows = []
    for k in keys:
        if k in data:
            v = data[k]
            if isinstance(v, list):
                v = " × ".join(str(x) for x in v)
            elif isinstance(v, str) and k == "file":
                v = os.path.basename(v)
            rows.append([k, fmt(str(v)) if not isinstance(v, str) else v])
    return f"`{path.relative_to(root)}`:\n\n" + table(["measure", "value"], rows)


def machine():
    model, cores_per_socket, sockets = "unknown CPU", None, set()
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                key, _, value = line.partition(":")
                key, value = key.strip(), value.strip()
                if key == "model name" and model == "unknown CPU":
                    model = value
                elif key == "cpu cores" and cores_per_socket is None:
                    cores_per_socket = value
                elif key == "physical id":
                    sockets.add(value)
    except OSError:
        pass
    logical = os.cpu_count() or 0
    memory = "unknown"
    try:
        with open("/proc/meminfo") as f:
            for line in f:
                if line.startswith("MemTotal:"):
                    memory = f"{int(line.split()[1]) / 1024 / 1024:.1f} GiB"
                    break
    except OSError:
        pass
    cores = f"{logical} logical CPUs"
    if cores_per_socket:
        cores += f" ({cores_per_socket} cores per socket, {max(len(sockets), 1)} socket(s))"
    return model, cores, memory


def git(repo, *args):
    try:
        return subprocess.run(["git", "-C", str(repo), *args], capture_output=True, text=True, check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return ""


def run_facts(root, repo, files, here):
    """The table rows of one run folder: its date, commit and machine (meta.json, else guessed)."""
    meta = {}
    if (root / "meta.json").is_file():
        with open(root / "meta.json") as f:
            meta = json.load(f)
    commit = meta.get("commit") or git(repo, "rev-parse", "HEAD") or "unknown"
    dirty = meta.get("dirty")
    if dirty is None:
        dirty = bool(git(repo, "status", "--porcelain", "--untracked-files=no"))
    newest = max((p.stat().st_mtime for p in files), default=None)
    measured = meta.get("date") or (
        datetime.datetime.fromtimestamp(newest, datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC") if newest else "unknown")
    model, cores, memory = meta.get("cpu") or here[0], meta.get("cores") or here[1], meta.get("memory") or here[2]
    return [
        ["measured", measured],
        ["commit", f"`{commit}`" + (" (with uncommitted changes)" if dirty else "")],
        ["CPU", model],
        ["cores", cores],
        ["memory", memory],
        ["system", meta.get("system") or f"{platform.system()} {platform.release()}"],
        ["outputs", f"`{root}`"],
    ]


def blocks_of(lines):
    """The page's lines before its first "## " heading, and its sections as (heading, lines)."""
    head, blocks = [], []
    for line in lines:
        if line.startswith("## "):
            blocks.append((line, [line]))
        elif blocks:
            blocks[-1][1].append(line)
        else:
            head.append(line)
    return head, blocks


def updated_page(old_lines, new_lines):
    """The old page with the new page's runs after its runs and the new sections in place of those of
    the same title (appended when new); the runs are renumbered after the old page's."""
    _, old = blocks_of(old_lines)
    head, new = blocks_of(new_lines)
    is_run = lambda heading: heading == "## The run" or heading.startswith("## Run ")
    old_runs = [b for b in old if is_run(b[0])]
    new_runs = [b for b in new if is_run(b[0])]
    sections = [b for b in new if not is_run(b[0])]
    first = len(old_runs) + 1
    if old_runs and old_runs[0][0] == "## The run":
        old_runs[0] = ("## Run 1", ["## Run 1"] + old_runs[0][1][1:])
    stamp = [l for b in new_runs for l in b[1] if l.startswith("| page generated |")]
    if old_runs and stamp:
        old_runs[0] = (old_runs[0][0], [stamp[0] if l.startswith("| page generated |") else l for l in old_runs[0][1]])
    renumbered = []
    for i, (heading, lines) in enumerate(new_runs):
        title = f"## Run {first + i} (updates the sections it reran)"
        renumbered.append((title, [title] + [l for l in lines[1:] if not l.startswith("| page generated |")]))
    # The new sections name their run "(run k)" among the new folders alone: shift k past the old runs.
    def relabel(line):
        if line.startswith("Written by ") and "(run " in line:
            k = int(line.rsplit("(run ", 1)[1].split(")")[0])
            return line.rsplit("(run ", 1)[0] + f"(run {first + k - 1})."
        if line.startswith("Written by ") and line.endswith("`."):
            return line[:-1] + f" (run {first})."
        return line
    sections = [(h, [relabel(l) for l in lines]) for h, lines in sections]
    replaced = {h for h, _ in sections}
    out, placed = [], set()
    for heading, lines in old:
        if is_run(heading):
            continue
        if heading in replaced:
            if heading not in placed:
                out += [b for b in sections if b[0] == heading]
                placed.add(heading)
            continue
        out.append((heading, lines))
    out += [b for b in sections if b[0] not in placed]
    page = list(head)
    for _, lines in old_runs + renumbered + out:
        page += lines
    return page


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("run_dirs", type=Path, nargs="+", metavar="RUN_DIR",
                        help="folders holding the benches' outputs (searched recursively; later ones update earlier ones)")
    parser.add_argument("-o", "--output", type=Path, default=None, help="page to write (default: docs/results.md)")
    parser.add_argument("--update", action="store_true",
                        help="keep the page's other sections: the folders' sections replace those of the same title, "
                             "the rest are added, and the folders are listed as the page's next runs")
    args = parser.parse_args()

    repo = Path(__file__).resolve().parents[2]
    out_path = args.output or repo / "docs" / "results.md"
    roots = [d.resolve() for d in args.run_dirs]
    for root in roots:
        if not root.is_dir():
            sys.exit(f"make_results_page: {root}: no such folder")
    here = machine()
    generated = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")

    # Every file by its place in its run; a later run's file replaces an earlier one's.
    chosen = {}
    all_files = {}
    for index, root in enumerate(roots):
        all_files[root] = sorted(p for p in root.rglob("*") if p.is_file())
        for p in all_files[root]:
            if p.name not in ("commands.txt", "meta.json"):
                chosen[p.relative_to(root)] = (index, root, p)
    run_of = {p: (index, root) for index, root, p in chosen.values()}
    files = sorted(run_of, key=lambda p: p.relative_to(run_of[p][1]))
    label = (lambda p: f" (run {run_of[p][0] + 1})") if len(roots) > 1 else (lambda p: "")

    page = [
        "# Results",
        "",
        "[README](../README.md) · [sampling](sampling.md) · [compress](compress.md) · [validate](validate.md) · [fit](fit.md)",
        "",
        "<!-- Generated by tools/results/make_results_page.py; do not edit by hand. -->",
        "",
        "Measured figures of libbtf, as its benchmarks wrote them. This page is generated: every figure below "
        "comes from the files of benchmark runs, none is typed by hand. To regenerate it on your machine:",
        "",
        "```sh",
        "bash tools/results/run_benches.sh            # quick sizes; writes build/results/ and this page",
        "/usr/bin/python3 tools/results/make_results_page.py RUN_DIR   # the page from any folder of bench outputs",
        "```",
        "",
        "Timings depend on the machine and on what else runs on it; compare ratios taken within one run "
        "rather than absolute rates across runs. The quick sizes check that everything runs and show the "
        "shape of the results; the full benchmarks (the commands without `--quick`, see `btf bench <name> "
        "--help`) take minutes to hours.",
        "",
    ]
    for index, root in enumerate(roots):
        title = "The run" if len(roots) == 1 else f"Run {index + 1}" + (
            " (updates the sections it reran)" if index > 0 else "")
        rows = run_facts(root, repo, all_files[root], here)
        if index == 0:
            rows.insert(1, ["page generated", generated])
        page += [f"## {title}", "", table(["", ""], rows), ""]
        commands = root / "commands.txt"
        if commands.is_file():
            page += ["Commands that produced its figures:", "", "```sh", commands.read_text().rstrip(), "```", ""]
        else:
            page += ["The folder records no commands (it was not made by `run_benches.sh`); each section names "
                     "the benchmark that writes its file.", ""]

    found = {name: [p for p in files if p.name == name] for name in ORDER}
    sections = 0
    for name in ORDER:
        title, command, columns = KNOWN[name]
        for path in found[name]:
            root = run_of[path][1]
            summary = fit_tables_summary(path) if name == "fits.csv" else None
            if summary:
                page += ["## Fits on measured-style tables", "", f"Written by `btf bench fits --tables`{label(path)}.", "",
                         summary, "", csv_section(path, root, columns), ""]
                sections += 1
                continue
            page += [f"## {title}", "", f"Written by `{command}`{label(path)}.", "", csv_section(path, root, columns), ""]
            sections += 1
            if name == "samplers.csv" and (path.parent / "summary.txt").is_file():
                page += [f"The report of `{command}` (`{(path.parent / 'summary.txt').relative_to(root)}`):", "",
                         "```", (path.parent / "summary.txt").read_text().rstrip(), "```", ""]
    for path in [p for p in files if p.name.startswith("decode") and p.suffix == ".json"]:
        page += ["## Decoding: random lookups from a .btfz", "", f"Written by `btf bench decode FILE --json`{label(path)}.", "",
                 decode_section(path, run_of[path][1]), ""]
        sections += 1
    known_names = set(ORDER)
    for path in files:
        if path.suffix == ".csv" and path.name not in known_names:
            page += [f"## {path.name}", "", csv_section(path, run_of[path][1], []), ""]
            sections += 1
    if sections == 0:
        page += ["No benchmark output was found in the folders.", ""]

    if args.update and out_path.is_file():
        page = updated_page(out_path.read_text().split("\n"), "\n".join(page).split("\n"))
    text = "\n".join(page).rstrip() + "\n"
    tmp = out_path.with_name(out_path.name + ".tmp")
    tmp.write_text(text)
    os.replace(tmp, out_path)
    print(f"wrote {out_path} ({sections} sections from {', '.join(str(r) for r in roots)})")


if __name__ == "__main__":
    main()
