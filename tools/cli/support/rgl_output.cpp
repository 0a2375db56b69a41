#include "rgl_output.h"

#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>

#include "btf/core/error.h"
#include "btf/fit/btf_texel.h"
#include "btf/io/rgl_tensor.h"
#include "btf/material/azimuthal_average.h"
#include "btf/material/btf_material.h"
#include "btf/material/material_difference.h"
#include "btf/material/rgl_acquisition.h"
#include "btf/material/rgl_brdf.h"
#include "material_input.h"

namespace btf::cli {
namespace {

// The source as an isotropic material, with what the description says of it.
struct RglSource {
  std::shared_ptr<const Material> material;
  std::string description;
  bool slow = false;  // a BTF texel: each eval interpolates and averages over phi_h
};

RglSource btfTexelSource(const IdentifiedMaterial& from, const std::string& in, const std::string& texel_option) {
  if (texel_option.empty())
    throw FileError(in, "is a BTF (it varies over the surface) and an RGL file holds one BRDF: choose a texel with "
                        "--texel X,Y, or the mean over the texels with --texel mean");
  const BtfInput input = openBtfInput(from);
  std::optional<glm::ivec2> texel;
  if (texel_option != "mean") {
    int x = 0, y = 0;
    char rest = 0;
    if (std::sscanf(texel_option.c_str(), "%d,%d%c", &x, &y, &rest) != 2)
      throw Error("--texel takes X,Y (two integers) or mean, not '" + texel_option + "'");
    texel = glm::ivec2(x, y);
    if (const auto problem = texelOutside(*input.source, *texel)) throw FileError(in, *problem);
  }
  auto one = std::make_shared<BtfData>(btfTexel(*input.source, texel));
  const std::string which = texel ? "texel (" + std::to_string(texel->x) + ", " + std::to_string(texel->y) + ")"
                                  : "mean over its " + std::to_string(input.source->texelCount()) + " texels";
  // A texel is anisotropic in general; the file is isotropic, so it holds the average over the
  // azimuth of the half vector (azimuthal_average.h).
  auto material = std::make_shared<AzimuthalAverage>(std::make_shared<BtfMaterial>(std::move(one)));
  return {material, std::filesystem::path(in).filename().string() + ", " + which + ", averaged over phi_h", true};
}

RglAcquisitionOptions acquisitionOptions(const RglOutputOptions& o, const Material& source, const std::string& description) {
  RglAcquisitionOptions a;
  if (const auto* rgl = dynamic_cast<const RglBrdf*>(&source)) {
    a.theta_i_count = int(rgl->thetaSamples().size());
    a.resolution = rgl->resolution();
    a.vndf_resolution = rgl->vndfResolution();
  }
  a.theta_i_count = o.theta_i_count.value_or(a.theta_i_count);
  a.resolution = o.resolution.value_or(a.resolution);
  a.vndf_resolution = o.vndf_resolution.value_or(a.vndf_resolution);
  a.ndf_resolution = o.ndf_resolution.value_or(a.ndf_resolution);
  a.spectral = !o.rgb_only;
  a.description = o.description.empty() ? "virtual acquisition (libbtf) of " + description : o.description;
  return a;
}

void printWritten(const std::string& out, const RglAcquisitionOptions& a, const std::vector<float>& theta_i,
                  std::uintmax_t bytes, const MaterialDifference& d, std::uint32_t pairs) {
  std::printf("wrote %s (RGL measured material, tensor_file 1.0, isotropic, %s)\n", out.c_str(),
              a.spectral ? "RGB and spectra 360-830 nm: pbrt-v4, Mitsuba 3 spectral variants"
                         : "RGB only: Mitsuba 3 RGB variants");
  std::printf("  description %s\n", a.description.c_str());
  std::printf("  theta_i     %d values (deg):", a.theta_i_count);
  for (const float t : theta_i) std::printf(" %.1f", double(t) * 180.0 / 3.14159265358979);
  std::printf("\n  resolution  %d x %d luminance/RGB per incidence, %d x %d VNDF, %d NDF nodes\n", a.resolution,
              a.resolution, a.vndf_resolution, a.vndf_resolution, a.ndf_resolution);
  std::printf("  bytes       %ju\n", bytes);
  std::printf("  rel_rmse    %.3g of f cos against the source (%u random direction pairs within 80 deg, read back)\n",
              d.fcos_rel_rmse, pairs);
  std::printf("  albedo      theta_o   written (RGB)              source (RGB)\n");
  for (std::size_t k = 0; k < d.theta_o_deg.size(); ++k)
    std::printf("              %3.0f deg   %.4f %.4f %.4f   %.4f %.4f %.4f\n", double(d.theta_o_deg[k]),
                double(d.albedo[k].r), double(d.albedo[k].g), double(d.albedo[k].b), double(d.reference_albedo[k].r),
                double(d.reference_albedo[k].g), double(d.reference_albedo[k].b));
  std::printf("  largest albedo error %.2f%% (of channels reflecting at least 0.001)\n", 100.0 * d.max_albedo_rel_error);
}

}  // namespace

void addRglOutputOptions(CLI::App& cmd, RglOutputOptions& o) {
  const std::string group = "RGL output (OUT ending in .bsdf)";
  cmd.add_option("--theta-i", o.theta_i_count, "Incidence angles (default 8, as the RGL database; an RGL input: its own)")
      ->group(group);
  cmd.add_option("--resolution", o.resolution,
                 "Luminance and RGB nodes per side per incidence (default 32; an RGL input: its own)")
      ->group(group);
  cmd.add_option("--vndf-resolution", o.vndf_resolution, "VNDF warp nodes per side (default 128; an RGL input: its own)")
      ->group(group);
  cmd.add_option("--ndf-resolution", o.ndf_resolution, "NDF and projected-area nodes over theta (default 128)")->group(group);
  cmd.add_option("--description", o.description, "The file's description (default: names the source)")->group(group);
  cmd.add_option("--texel", o.texel, "A BTF input: the texel X,Y, or mean (the mean over all texels)")->group(group);
  cmd.add_flag("--rgb-only", o.rgb_only,
               "Write no 'wavelengths'/'spectra': the file for Mitsuba 3's RGB variants, which refuse a file with "
               "'wavelengths' (default: RGB and spectra, for pbrt-v4 and Mitsuba 3's spectral variants)")
      ->group(group);
}

void writeRglOutput(const IdentifiedMaterial& from, const std::string& in, const std::string& out,
                    const RglOutputOptions& o) {
  RglSource source;
  std::optional<TensorFile> rgl_file;  // an RGL input, read once: the source and its parameterization
  if (isBtf(from)) {
    source = btfTexelSource(from, in, o.texel);
  } else {
    if (!o.texel.empty()) throw FileError(in, "--texel is for BTFs (an image folder, a Bonn .btf, a .btfz); this is a BRDF");
    const std::string label = std::filesystem::path(in).filename().string();
    if (from.type->name == "rgl") {
      rgl_file = readTensorFile(from.params.existingPath("file"));
      source = {std::make_shared<RglBrdf>(*rgl_file), label};
    } else {
      source = {createMaterial(from.params), label};
    }
  }
  RglAcquisitionOptions a = acquisitionOptions(o, *source.material, source.description);
  // An RGL input is re-measured on its own parameterization unless other resolutions are asked for.
  if (rgl_file && !o.theta_i_count && !o.vndf_resolution && !o.ndf_resolution) a.parameterization = &*rgl_file;
  std::vector<TensorField> fields;
  try {
    fields = acquireRglFields(*source.material, a);
  } catch (const FileError&) {
    throw;
  } catch (const Error& e) {
    throw FileError(in, e.what());
  }
  writeTensorFile(out, fields);
  // What the conversion lost, measured on the file as written.
  const RglBrdf written(out);
  MaterialDifferenceOptions compare;
  if (source.slow) {
    compare.pair_count = 20'000;
    compare.albedo_theta_h_steps = 64;
    compare.albedo_phi_h_steps = 128;
  }
  const MaterialDifference d = compareMaterials(written, *source.material, compare);
  printWritten(out, a, written.thetaSamples(), std::filesystem::file_size(out), d, d.pairs);
}

}  // namespace btf::cli
