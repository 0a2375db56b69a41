// Where the BTF verbs write a BTF, decided in one place by the output path: a name ending in .btf is
// a Bonn file (DFMF by default, FMF or PVF with --layout; factorised by a truncated SVD), anything
// else an image folder (the UBO2003 layout, or UTIA's with --layout utia). `btf convert` and `btf decompress` share it.
#pragma once

#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "btf/io/bonn_btf.h"
#include "btf/io/btf_images.h"

namespace btf::cli {

struct BtfOutputOptions {
  std::string layout;  // "ubo2003", "utia" for a folder; "dfmf", "fmf", "pvf" for .btf; empty: the default
  std::string image_format = "exr";
  int components = 64;
  // The default: the precision of the half scalars the database ships (2^-11 relative), so that a
  // file read and written back keeps the components its data needs, not --components of them.
  std::optional<double> relative_error = 1e-3;
  int scalar_bytes = 2;
  int color_model = 11;
  bool log_values = false;  // FMF: store log(x + 1e-5)
  bool operator==(const BtfOutputOptions&) const = default;
};

// The options above on a verb (--layout, --format, --components, --relative-error, --scalar,
// --color-model, --log).
void addBtfOutputOptions(CLI::App& cmd, BtfOutputOptions& options);

// Writes `source` to `out` (atomically) and prints what was written: the layout, and for a
// factorised file the components kept and the truncation error per factor.
void writeBtfOutput(const BtfSource& source, const std::string& out, const BtfOutputOptions& options);

}  // namespace btf::cli
