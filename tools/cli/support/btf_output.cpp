#include "btf_output.h"

#include <cstdio>
#include <filesystem>

#include "btf/core/error.h"

namespace btf::cli {

void addBtfOutputOptions(CLI::App& cmd, BtfOutputOptions& o) {
  cmd.add_option("--layout", o.layout,
                 "A folder output's layout: ubo2003 (every image in the folder; default) or utia (a subfolder per "
                 "view, EXR in CIE XYZ); a .btf output's: dfmf (decorrelated full matrix factorisation, as UBO2014 "
                 "ships; default), fmf (one factorisation of all channels) or pvf (a PCA per view)")
      ->check(CLI::IsMember({"ubo2003", "utia", "dfmf", "fmf", "pvf"}));
  cmd.add_option("--format", o.image_format, "An image-folder output's images: exr (float), png8 or png16")
      ->capture_default_str();
  cmd.add_option("--components", o.components,
                 "A .btf output: components kept per factorisation (the rank of the truncated SVD; at most)")
      ->capture_default_str()
      ->check(CLI::Range(1, 4096));
  cmd.add_option_function<double>(
         "--relative-error", [&o](double e) { o.relative_error = e; },
         "A .btf output: keep the fewest components (up to --components) whose truncation error, relative to the "
         "data's norm in the stored values, is at most this (default 0.001, about the half scalars' precision; "
         "a tiny value keeps all --components)")
      ->check(CLI::Range(1e-9, 0.999999));
  cmd.add_option("--scalar", o.scalar_bytes, "A .btf output's factor scalars: 2 (half, as the database ships), 4 or 8 bytes")
      ->capture_default_str()
      ->check(CLI::IsMember({2, 4, 8}));
  cmd.add_option("--color-model", o.color_model,
                 "A DFMF output's colour model: 11 (log-Y, U/Y, V/Y; UBO2014's), 0 (RGB), or 1-4, 9, 10, 12")
      ->capture_default_str()
      ->check(CLI::IsMember({0, 1, 2, 3, 4, 9, 10, 11, 12}));
  cmd.add_flag("--log", o.log_values, "An FMF output: store log(x + 1e-5) (the format's dynamic-range reduction)");
}

namespace {

BtfImageFormat imageFormatOf(const std::string& name) {
  if (name == "exr") return BtfImageFormat::Exr;
  if (name == "png8" || name == "png") return BtfImageFormat::Png8;
  if (name == "png16") return BtfImageFormat::Png16;
  throw Error("unknown --format '" + name + "' (expected exr, png8 or png16)");
}

}  // namespace

void writeBtfOutput(const BtfSource& source, const std::string& out, const BtfOutputOptions& o) {
  const std::filesystem::path path(out);
  if (path.extension() != ".btf") {
    if (!o.layout.empty() && o.layout != "ubo2003" && o.layout != "utia")
      throw Error("--layout " + o.layout + " is a layout of .btf files; the folder " + out + " takes ubo2003 or utia");
    BtfImageWriteOptions options;
    options.format = imageFormatOf(o.image_format);
    options.layout = o.layout == "utia" ? BtfImageLayout::Utia : BtfImageLayout::Ubo2003;
    writeBtfImageFolder(source, path, options);
    std::printf("wrote %s: image folder (%s layout), %d x %d texels, %s, %zu %s images\n", out.c_str(),
                btfImageLayoutName(options.layout).c_str(), source.width(), source.height(),
                source.views().describe().c_str(), std::size_t(source.entryCount() / source.texelCount()),
                btfImageFormatName(options.format).c_str());
    return;
  }
  if (o.layout == "ubo2003" || o.layout == "utia")
    throw Error("--layout " + o.layout + " is a folder layout; " + out + " is a .btf file (dfmf, fmf or pvf)");
  if (o.layout == "pvf") {
    writeBonnBtfPvf(source, path, o.components, o.scalar_bytes);
    std::printf("wrote %s: Bonn BTF (PVF, %d components per view, %d-byte scalars), %llu bytes\n", out.c_str(),
                o.components, o.scalar_bytes, static_cast<unsigned long long>(std::filesystem::file_size(path)));
    return;
  }
  BonnBtfWriteOptions options;
  options.layout = o.layout == "fmf" ? BonnBtfLayout::Fmf : BonnBtfLayout::Dfmf;
  options.max_components = o.components;
  options.relative_error = o.relative_error;
  options.scalar_bytes = o.scalar_bytes;
  options.color_model = o.color_model;
  options.dynamic_range_reduction = o.log_values ? 1 : 0;
  const BonnBtfWriteReport report = writeBonnBtf(source, path, options);
  std::printf("wrote %s: Bonn BTF (%s, %d-byte scalars), %s, %d x %d texels, %llu bytes\n", out.c_str(),
              bonnBtfLayoutName(options.layout).c_str(), o.scalar_bytes, source.directions().describe().c_str(),
              source.width(), source.height(), static_cast<unsigned long long>(report.bytes));
  const char* names[] = {"Y (log)", "U/Y", "V/Y"};
  for (std::size_t i = 0; i < report.components.size(); ++i) {
    const std::string label = options.layout == BonnBtfLayout::Fmf ? std::string("all channels")
                              : options.color_model == 11       ? std::string(names[i])
                                                                : "channel " + std::to_string(i);
    std::printf("  %-14s %4u components, truncation error %.3g (relative, stored values)\n", label.c_str(),
                report.components[i], report.relative_error[i]);
  }
}

}  // namespace btf::cli
