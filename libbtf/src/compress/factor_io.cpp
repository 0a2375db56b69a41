// FactorBtf in .btfz (io/container.h): sections "header" (JSON: format "libbtf-factor", size, name,
// direction set and views held (btfz_directions.h), the colour transform, components per channel,
// the colour model (and its transform or log offset), the coefficient step, the basis scales, the options and the estimate), "coefficients" (the
// k_total coefficient planes over the texels) and "basis" (the k_total basis planes over the pairs),
// each plane as factor_impl.h encodes it, zstd-compressed. docs/formats.md describes it.
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "btf/core/error.h"
#include "btf/io/container.h"
#include "btfz_directions.h"
#include "factor_impl.h"

namespace btf {
namespace {

constexpr const char* kFactorFormat = "libbtf-factor";
constexpr int kFactorFormatVersion = 1;

const nlohmann::json& field(const nlohmann::json& h, const char* key, const std::filesystem::path& path) {
  const auto it = h.find(key);
  if (it == h.end()) throw FileError(path, std::string("factor header has no \"") + key + "\"");
  return *it;
}

int intField(const nlohmann::json& h, const char* key, const std::filesystem::path& path, int lo, int hi) {
  const nlohmann::json& v = field(h, key, path);
  if (!v.is_number_integer() || v.get<long long>() < lo || v.get<long long>() > hi)
    throw FileError(path, std::string("factor header's \"") + key + "\" is " + v.dump() + ", not an integer in " +
                              std::to_string(lo) + ".." + std::to_string(hi));
  return v.get<int>();
}

double positiveField(const nlohmann::json& v, const std::string& what, const std::filesystem::path& path) {
  if (!v.is_number() || !std::isfinite(v.get<double>()) || !(v.get<double>() > 0))
    throw FileError(path, "factor header's " + what + " is " + v.dump() + ", not a positive number");
  return v.get<double>();
}

}  // namespace

void FactorBtf::write(const std::filesystem::path& path) const {
  const Impl& m = *impl_;
  nlohmann::json header;
  header["format"] = kFactorFormat;
  header["format_version"] = kFactorFormatVersion;
  header["width"] = m.width;
  header["height"] = m.height;
  header["name"] = m.name;
  addDirectionSetHeader(m.views, header);
  header["color_model"] = factorColorModelName(m.color_model);
  if (m.color_model == FactorColorModel::LogLuminance) header["log_offset"] = m.log_offset;
  else header["color_transform"] = m.color;
  header["components"] = m.k;
  header["coefficient_step"] = m.coefficient_step;
  header["basis_scales"] = m.basis_scale;
  header["epsilon"] = m.options.epsilon;
  header["estimated_rel_rmse"] = m.stats.estimated_rel_rmse;
  header["truncation_rel_rmse"] = m.stats.truncation_rel_rmse;
  if (m.stats.measured_rel_rmse >= 0) header["measured_rel_rmse"] = m.stats.measured_rel_rmse;

  std::vector<ContainerSection> sections(3);
  const std::string text = header.dump();
  sections[0].type = SectionType::Header;
  sections[0].name = "header";
  sections[0].data.resize(text.size());
  std::memcpy(sections[0].data.data(), text.data(), text.size());
  const std::size_t K = std::size_t(m.k_total), T = m.texels();
  sections[1].type = SectionType::IndexStream;
  sections[1].name = "coefficients";
  sections[1].compress = true;
  for (std::size_t j = 0; j < K; ++j) encodeFactorPlane(&m.coefficient_codes[j * T], T, sections[1].data);
  sections[2].type = SectionType::Codebook;
  sections[2].name = "basis";
  sections[2].compress = true;
  for (std::size_t j = 0; j < K; ++j) encodeFactorPlane(&m.basis_codes[j * m.pairs], m.pairs, sections[2].data);
  if (!m.pair_offset.empty()) {
    ContainerSection offsets;
    offsets.type = SectionType::Other;
    offsets.name = "pair_offset";
    offsets.compress = true;
    offsets.data.resize(m.pair_offset.size() * sizeof(float));
    std::memcpy(offsets.data.data(), m.pair_offset.data(), offsets.data.size());
    sections.push_back(std::move(offsets));
  }
  const std::uint64_t bytes = writeContainer(path, sections, 19);
  const_cast<Impl&>(m).stats.compressed_bytes = bytes;
}

FactorBtf FactorBtf::read(const std::filesystem::path& path) {
  const std::vector<ContainerSection> sections = readContainer(path);
  const ContainerSection& hs = requireSection(sections, "header", path);
  nlohmann::json h;
  try {
    h = nlohmann::json::parse(std::string(reinterpret_cast<const char*>(hs.data.data()), hs.data.size()));
  } catch (const nlohmann::json::exception& e) {
    throw FileError(path, std::string("factor header is invalid: ") + e.what());
  }
  if (!h.is_object() || h.value("format", std::string()) != kFactorFormat)
    throw FileError(path, "is not a factor-compressed BTF (its header's format is not \"libbtf-factor\")");
  const int version = intField(h, "format_version", path, 1, 1 << 20);
  if (version > kFactorFormatVersion)
    throw FileError(path, "is a factor file of format version " + std::to_string(version) + ", newer than this reader's " +
                              std::to_string(kFactorFormatVersion));
  auto impl = std::make_shared<Impl>();
  Impl& m = *impl;
  m.width = intField(h, "width", path, 1, 1 << 16);
  m.height = intField(h, "height", path, 1, 1 << 16);
  if (std::uint64_t(m.width) * std::uint64_t(m.height) > (std::uint64_t(1) << 28))
    throw FileError(path, "factor header's size " + std::to_string(m.width) + " x " + std::to_string(m.height) + " is too large");
  const nlohmann::json& name = field(h, "name", path);
  if (!name.is_string()) throw FileError(path, "factor header's name is not a string");
  m.name = name.get<std::string>();
  m.views = readDirectionSetHeader(h, path, "factor header");

  const nlohmann::json& model = field(h, "color_model", path);
  if (model == "log-luminance") {
    m.color_model = FactorColorModel::LogLuminance;
    m.log_offset = float(positiveField(field(h, "log_offset", path), "log_offset", path));
  } else if (model == "linear") {
    m.color_model = FactorColorModel::Linear;
    const nlohmann::json& color = field(h, "color_transform", path);
    if (!color.is_array() || color.size() != 9) throw FileError(path, "factor header's color_transform is not 9 numbers");
    for (std::size_t i = 0; i < 9; ++i) {
      if (!color[i].is_number() || !std::isfinite(color[i].get<double>()) || std::abs(color[i].get<double>()) > 1.0 + 1e-6)
        throw FileError(path, "factor header's color_transform holds " + color[i].dump() + ", not an entry of a rotation");
      m.color[i] = color[i].get<float>();
    }
  } else {
    throw FileError(path, "factor header's color_model " + model.dump() + " is not \"linear\" or \"log-luminance\"");
  }
  const nlohmann::json& components = field(h, "components", path);
  if (!components.is_array() || components.size() != 3)
    throw FileError(path, "factor header's components are not 3 counts (one per colour channel)");
  for (std::size_t c = 0; c < 3; ++c) {
    if (!components[c].is_number_integer() || components[c].get<long long>() < 0 || components[c].get<long long>() > 4096)
      throw FileError(path, "factor header's components hold " + components[c].dump() + ", not a count in 0..4096");
    m.k[c] = components[c].get<int>();
  }
  m.coefficient_step = positiveField(field(h, "coefficient_step", path), "coefficient_step", path);
  const nlohmann::json& scales = field(h, "basis_scales", path);
  const std::size_t K = std::size_t(m.k[0] + m.k[1] + m.k[2]);
  if (!scales.is_array() || scales.size() != K)
    throw FileError(path, "factor header's basis_scales are not " + std::to_string(K) + " numbers (one per component)");
  for (const auto& s : scales) m.basis_scale.push_back(positiveField(s, "basis scale", path));
  if (h.contains("epsilon")) m.options.epsilon = float(positiveField(h.at("epsilon"), "epsilon", path));
  if (h.contains("estimated_rel_rmse") && h.at("estimated_rel_rmse").is_number())
    m.stats.estimated_rel_rmse = h.at("estimated_rel_rmse").get<double>();
  if (h.contains("truncation_rel_rmse") && h.at("truncation_rel_rmse").is_number())
    m.stats.truncation_rel_rmse = h.at("truncation_rel_rmse").get<double>();
  if (h.contains("measured_rel_rmse") && h.at("measured_rel_rmse").is_number())
    m.stats.measured_rel_rmse = h.at("measured_rel_rmse").get<double>();
  m.options.color_model = m.color_model;
  m.stats.components = m.k;
  m.stats.coefficient_step = m.coefficient_step;

  std::size_t pairs = 0;
  for (const int v : m.views.views()) pairs += std::size_t(m.views.directions().lightCount(v));
  const std::size_t T = m.texels();
  const auto planes = [&](const char* section, std::size_t count, std::vector<std::int32_t>& codes) {
    const ContainerSection& s = requireSection(sections, section, path);
    // Every value takes at least one byte: a section shorter than that cannot hold the planes, and
    // is refused before the codes are allocated.
    if (s.data.size() < K * (count + 1))
      throw FileError(path, std::string("section '") + section + "' is too short for " + std::to_string(K) + " planes of " +
                                std::to_string(count) + " values");
    codes.resize(K * count);
    const std::byte* in = s.data.data();
    const std::byte* end = in + s.data.size();
    for (std::size_t j = 0; j < K; ++j)
      decodeFactorPlane(in, end, &codes[j * count], count, path, std::string("section '") + section + "' plane " + std::to_string(j));
    if (in != end) throw FileError(path, std::string("section '") + section + "' has bytes after its last plane");
  };
  if (const auto it = std::find_if(sections.begin(), sections.end(), [](const ContainerSection& s) { return s.name == "pair_offset"; });
      it != sections.end()) {
    if (m.color_model != FactorColorModel::LogLuminance)
      throw FileError(path, "section 'pair_offset' belongs to the log-luminance model, not to " + factorColorModelName(m.color_model));
    if (it->data.size() != pairs * sizeof(float))
      throw FileError(path, "section 'pair_offset' holds " + std::to_string(it->data.size()) + " bytes, not " +
                                std::to_string(pairs) + " floats (one per pair)");
    m.pair_offset.resize(pairs);
    std::memcpy(m.pair_offset.data(), it->data.data(), it->data.size());
    for (const float v : m.pair_offset)
      if (!std::isfinite(v)) throw FileError(path, "section 'pair_offset' holds a value that is not finite");
  }
  planes("coefficients", T, m.coefficient_codes);
  planes("basis", pairs, m.basis_codes);
  m.prepare();
  for (const float v : m.coefficients)
    if (!std::isfinite(v)) throw FileError(path, "a coefficient decodes to a value that is not finite");
  m.stats.compressed_bytes = std::filesystem::file_size(path);
  return FactorBtf(std::move(impl));
}

}  // namespace btf
