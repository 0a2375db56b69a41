#include "btf_input.h"

#include "btf/compress/vq_btf.h"
#include "btf/core/error.h"
#include "btf/io/btf_images.h"
#include "btf/fit/merl_fits.h"
#include "merl_fit_report.h"
#include "measured_file.h"

namespace btf::cli {

BtfData brdfAsBtf(const Material& material, const std::string& name) {
  BtfData data(1, 1, name);
  const auto& directions = btfDirections();
  for (int view = 0; view < kBtfDirectionCount; ++view)
    for (int light = 0; light < kBtfDirectionCount; ++light) {
      const Rgb f = material.eval(directions[std::size_t(light)].w, directions[std::size_t(view)].w);
      if (!f.isFinite() || f.minComponent() < 0.0f)
        throw Error(name + ": the material gives an invalid value at view " + std::to_string(view) + ", light " +
                    std::to_string(light));
      data.at(0, 0, view, light) = f;
    }
  return data;
}

namespace {
// "merl-fit:MODEL:NAME" (e.g. merl-fit:sgd:alum-bronze): a published fit of a MERL material, from
// the fits folder the other verbs use (data-gen/materials/merl_fit_report.h).
BtfInput openMerlFit(const std::string& spec) {
  const std::string rest = spec.substr(std::string(kMerlFitPrefix).size());
  const std::size_t colon = rest.find(':');
  if (colon == std::string::npos || colon == 0 || colon + 1 == rest.size())
    throw Error("'" + spec + "': expected merl-fit:MODEL:NAME, e.g. merl-fit:sgd:alum-bronze");
  const FitModel model = parseFitModel(rest.substr(0, colon));
  const std::string name = rest.substr(colon + 1);
  const MerlFits fits = MerlFits::load(findMerlFitsFolder(datagen::defaultFitsFolders()));
  const auto material = makeMerlFitMaterial(fits, name, model);
  auto data = std::make_shared<BtfData>(brdfAsBtf(*material, name + "-" + fitModelName(model)));
  return {BtfInputKind::Brdf, data, std::string(fitModelName(model)) + " fit of a MERL material as a one-texel BTF at 81 x 81 directions"};
}
}  // namespace

BtfInput openBtfInput(const std::filesystem::path& path, const std::string& material) {
  std::error_code ec;
  const bool database = path.extension() == ".btfz" && !std::filesystem::is_directory(path, ec);
  if (!material.empty() && !database)
    throw FileError(path, "a material name ('" + material + "') selects a material of a .btfz database; this is not one");
  if (path.string().starts_with(kMerlFitPrefix)) return openMerlFit(path.string());
  if (std::filesystem::is_directory(path, ec)) {
    auto folder = std::make_shared<BtfImageFolder>(BtfImageFolder::open(path));
    return {BtfInputKind::ImageFolder, folder, "image-folder BTF"};
  }
  if (!std::filesystem::exists(path, ec)) throw FileError(path, "no such file or folder");
  if (path.extension() == ".btfz") {
    auto vq = std::make_shared<VqBtf>(VqBtf::read(path, material));
    return {BtfInputKind::Compressed, vq, "VQ-compressed BTF (.btfz)"};
  }
  const std::string ext = path.extension().string();
  if (ext != ".binary" && ext != ".bsdf" && ext != ".exr")
    throw FileError(path, "is not a BTF (expected an image folder, a .btfz file, or a BRDF as .binary, .exr or .bsdf)");
  const MeasuredFormat format = measuredFormatOf(path);
  const auto brdf = loadMeasuredMaterial(path, TableLookup::Interpolated);
  auto data = std::make_shared<BtfData>(brdfAsBtf(*brdf, path.stem().string()));
  return {BtfInputKind::Brdf, data, describe(format) + " as a one-texel BTF at 81 x 81 directions"};
}

}  // namespace btf::cli
