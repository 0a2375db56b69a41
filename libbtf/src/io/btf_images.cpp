#include "btf/io/btf_images.h"

#include <nlohmann/json.hpp>
#include <tbb/parallel_for.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>

#include "btf/core/error.h"
#include "btf/core/progress.h"
#include "btf/core/value_limits.h"
#include "btf/io/atomic_file.h"
#include "btf/io/image.h"
#include "image_backend.h"
#include "image_input.h"

namespace btf {
namespace fs = std::filesystem;
using image_backend::PixelType;
namespace {

// The smallest value_scale: a normal float, so that code * scale keeps its precision.
constexpr double kMinValueScale = double(std::numeric_limits<float>::min());

bool validValueScale(double scale) { return scale >= kMinValueScale && scale <= double(kMaxReflectance); }

std::string formatLimit(double v) {
  char text[40];
  std::snprintf(text, sizeof text, "%.9g", v);
  return text;
}

constexpr int kImagesPerBtf = kBtfDirectionCount * kBtfDirectionCount;

// What our writer stores in integer images: 8-bit PNGs sRGB-encoded, as cameras and viewers expect
// (and their 256 codes then spend their precision where the eye and the dark, grazing measurements
// need it); 16-bit PNGs linear (precision enough without a curve).
BtfTransfer btfWriterTransfer(BtfImageFormat format) {
  return format == BtfImageFormat::Png8 ? BtfTransfer::Srgb : BtfTransfer::Linear;
}

std::string lower(std::string_view text) {
  std::string out(text);
  std::transform(out.begin(), out.end(), out.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return out;
}

bool isImageExtension(const std::string& ext) {
  return ext == ".png" || ext == ".exr" || ext == ".tif" || ext == ".tiff" || ext == ".jpg" || ext == ".jpeg";
}

std::string describePair(int view, int light) {
  return "view (" + describeBtfDirection(view) + ") and light (" + describeBtfDirection(light) + ")";
}

std::string sizeText(int width, int height) { return std::to_string(width) + " x " + std::to_string(height); }

// Rethrows the error of the lowest index, so a failing parallel loop reports the same error
// whatever the thread count.
// An image of the folder, its header checked against the BTF's size (that of `first`) before any
// pixel is read.
std::unique_ptr<image_backend::Reader> openBtfImage(const fs::path& path, int width, int height, const fs::path& first) {
  auto in = openImageInput(path);
  const image_backend::ImageHeader& spec = in->header();
  if (spec.width != width || spec.height != height)
    throw FileError(path, "is " + sizeText(spec.width, spec.height) + " pixels, but the BTF's images are " +
                              sizeText(width, height) + " (" + first.filename().string() + ")");
  if (spec.channels < 3)
    throw FileError(path, "has " + std::to_string(spec.channels) + " channel(s), a BTF image needs RGB (3 or more)");
  return in;
}

void rethrowFirst(const std::vector<std::exception_ptr>& errors) {
  for (const std::exception_ptr& e : errors)
    if (e) std::rethrow_exception(e);
}

// The sidecar's settings (btf_images.h): value_scale and transfer, each optional.
struct Sidecar {
  float value_scale = 1.0f;
  std::optional<BtfTransfer> transfer;
  std::optional<BtfColorSpace> color_space;
  std::optional<fs::path> direction_list;   // relative to the folder
  std::optional<int> width, height, views;  // as recorded by the writer, if present
};

Sidecar readSidecar(const fs::path& folder) {
  const fs::path sidecar = folder / kBtfSidecarName;
  std::error_code ec;
  if (!fs::exists(sidecar, ec)) return {};
  std::ifstream in(sidecar);
  if (!in) throw FileError(sidecar, "cannot be opened for reading");
  nlohmann::json doc;
  try {
    doc = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw FileError(sidecar, std::string("is not valid JSON: ") + e.what());
  }
  if (!doc.is_object()) throw FileError(sidecar, "expected a JSON object like {\"value_scale\": 2.5, \"transfer\": \"srgb\"}");
  Sidecar result;
  if (doc.contains("value_scale")) {
    // Checked as the float it is stored in: 1e300 would become inf, 1e-320 zero.
    const nlohmann::json& s = doc["value_scale"];
    const double scale = s.is_number() ? s.get<double>() : 0.0;
    if (!s.is_number() || !validValueScale(scale))
      throw FileError(sidecar, "value_scale must be a number in [" + formatLimit(kMinValueScale) + ", " +
                                   formatLimit(kMaxReflectance) + "] (the largest value an image holds), not " + s.dump());
    result.value_scale = float(scale);
  }
  if (doc.contains("transfer")) {
    const nlohmann::json& t = doc["transfer"];
    const std::optional<BtfTransfer> transfer = t.is_string() ? parseBtfTransfer(t.get<std::string>()) : std::nullopt;
    if (!transfer) throw FileError(sidecar, "transfer must be \"srgb\" or \"linear\", not " + t.dump());
    result.transfer = transfer;
  }
  if (doc.contains("color_space")) {
    const nlohmann::json& c = doc["color_space"];
    const std::string name = c.is_string() ? lower(c.get<std::string>()) : std::string();
    if (name == "xyz") result.color_space = BtfColorSpace::Xyz;
    else if (name == "rec709" || name == "srgb") result.color_space = BtfColorSpace::Rec709;
    else throw FileError(sidecar, "color_space must be \"xyz\" or \"rec709\", not " + c.dump());
  }
  if (doc.contains("direction_list")) {
    const nlohmann::json& d = doc["direction_list"];
    if (!d.is_string() || d.get<std::string>().empty())
      throw FileError(sidecar, "direction_list must name a file in the folder, not " + d.dump());
    result.direction_list = fs::path(d.get<std::string>());
  }
  // The facts our writer records for people: not needed to read the images, but a sidecar that
  // holds them holds them right (a width of 2^63, true or "nan" is a damaged file, not a note).
  for (const char* key : {"width", "height", "views"}) {
    if (!doc.contains(key)) continue;
    const nlohmann::json& v = doc[key];
    const bool whole = v.is_number_integer() || v.is_number_unsigned();
    if (!whole || v.get<double>() < 1 || v.get<double>() > (std::string_view(key) == "views" ? 81.0 : 1e6))
      throw FileError(sidecar, std::string(key) + " must be a whole number from 1 to " +
                                   (std::string_view(key) == "views" ? "81" : "1000000") + ", not " + v.dump());
    const std::string_view name(key);
    (name == "width" ? result.width : name == "height" ? result.height : result.views) = v.get<int>();
  }
  for (const char* key : {"format", "source", "layout"})
    if (doc.contains(key) && !doc[key].is_string())
      throw FileError(sidecar, std::string(key) + " must be a string, not " + doc[key].dump());
  return result;
}

}  // namespace

std::string btfImageFormatName(BtfImageFormat format) {
  switch (format) {
    case BtfImageFormat::Png8: return "png8";
    case BtfImageFormat::Png16: return "png16";
    case BtfImageFormat::Exr: return "exr";
  }
  return "?";
}

std::string btfImageExtension(BtfImageFormat format) { return format == BtfImageFormat::Exr ? ".exr" : ".png"; }

std::string btfImageLayoutName(BtfImageLayout layout) { return layout == BtfImageLayout::Utia ? "UTIA" : "UBO2003"; }

std::string btfTransferName(BtfTransfer transfer) { return transfer == BtfTransfer::Srgb ? "srgb" : "linear"; }

std::optional<BtfTransfer> parseBtfTransfer(std::string_view name) {
  const std::string n = lower(name);
  if (n == "srgb") return BtfTransfer::Srgb;
  if (n == "linear") return BtfTransfer::Linear;
  return std::nullopt;
}

std::optional<BtfImagePair> parseBtfImageName(std::string_view file_name) {
  const std::string name = lower(fs::path(file_name).stem().string());
  // Tag order in `angles`: tv, pv, tl, pl.
  static constexpr std::array<std::string_view, 4> kTags{"tv", "pv", "tl", "pl"};
  std::array<std::optional<float>, 4> angles;
  bool any = false;
  for (std::size_t i = 0; i + 2 < name.size() + 1; ++i) {
    if (i > 0 && std::isalpha(static_cast<unsigned char>(name[i - 1]))) continue;  // inside a word
    for (std::size_t t = 0; t < kTags.size(); ++t) {
      if (name.compare(i, 2, kTags[t]) != 0) continue;
      std::size_t end = i + 2;
      while (end < name.size() && (std::isdigit(static_cast<unsigned char>(name[end])) || name[end] == '.')) ++end;
      while (end > i + 2 && name[end - 1] == '.') --end;  // a separator dot, not a decimal point
      if (end == i + 2) continue;                          // a tag needs its number
      if (angles[t]) throw Error(std::string(file_name) + ": the angle tag '" + std::string(kTags[t]) + "' appears twice");
      float angle = 0;
      if (std::from_chars(name.data() + i + 2, name.data() + end, angle).ec != std::errc())
        throw Error(std::string(file_name) + ": the angle of tag '" + std::string(kTags[t]) + "' (" +
                    name.substr(i + 2, end - i - 2) + ") is not a number of degrees");
      angles[t] = angle;
      any = true;
    }
  }
  if (!any) return std::nullopt;
  for (std::size_t t = 0; t < kTags.size(); ++t)
    if (!angles[t])
      throw Error(std::string(file_name) + ": the angle tag '" + std::string(kTags[t]) +
                  "' is missing (a BTF image is named by tv, pv, tl and pl, e.g. tv030_pv060_tl045_pl120.png)");
  const std::optional<int> view = findBtfDirection(*angles[0], *angles[1]);
  const std::optional<int> light = findBtfDirection(*angles[2], *angles[3]);
  auto notInSet = [&](const char* what, float theta, float phi) {
    char text[160];
    std::snprintf(text, sizeof text, ": the %s direction (theta %g, phi %g) is not one of the 81 measured directions",
                  what, double(theta), double(phi));
    return Error(std::string(file_name) + text);
  };
  if (!view) throw notInSet("view", *angles[0], *angles[1]);
  if (!light) throw notInSet("light", *angles[2], *angles[3]);
  return BtfImagePair{*view, *light};
}

std::string btfImageName(int view, int light, BtfImageFormat format) {
  const BtfDirection& v = btfDirections().at(std::size_t(view));
  const BtfDirection& l = btfDirections().at(std::size_t(light));
  char text[64];
  std::snprintf(text, sizeof text, "tv%03d_pv%03d_tl%03d_pl%03d", int(std::lround(v.theta_deg)),
                int(std::lround(v.phi_deg)), int(std::lround(l.theta_deg)), int(std::lround(l.phi_deg)));
  return text + btfImageExtension(format);
}

std::string btfImagePath(int view, int light, BtfImageFormat format, BtfImageLayout layout) {
  if (layout == BtfImageLayout::Ubo2003) return btfImageName(view, light, format);
  const BtfDirection& v = btfDirections().at(std::size_t(view));
  const BtfDirection& l = btfDirections().at(std::size_t(light));
  char text[96];
  const int tv = int(std::lround(v.theta_deg)), pv = int(std::lround(v.phi_deg));
  std::snprintf(text, sizeof text, "tv%03d_pv%03d/tl%03d_pl%03d_tv%03d_pv%03d", tv, pv, int(std::lround(l.theta_deg)),
                int(std::lround(l.phi_deg)), tv, pv);
  return text + btfImageExtension(format);
}

// ---------------------------------------------------------------------------------------------
// Reading

namespace {

// The view a UTIA subfolder stands for ("tv030_pv060", any case), or nothing for other names.
std::optional<int> parseViewFolderName(const std::string& name) {
  const std::string n = lower(name);
  const auto number = [&](std::size_t& at, int& out) {
    const auto [end, ec] = std::from_chars(n.data() + at, n.data() + n.size(), out);
    if (ec != std::errc() || end == n.data() + at) return false;
    at = std::size_t(end - n.data());
    return true;
  };
  std::size_t at = 2;
  int tv = 0, pv = 0;
  if (!n.starts_with("tv") || !number(at, tv) || n.compare(at, 3, "_pv") != 0) return std::nullopt;
  at += 3;
  if (!number(at, pv) || at != n.size()) return std::nullopt;
  return findBtfDirection(float(tv), float(pv));
}

std::vector<fs::path> imageFilesIn(const fs::path& folder) {
  std::error_code ec;
  std::vector<fs::path> files;
  for (const fs::directory_entry& entry : fs::directory_iterator(folder, ec)) {
    if (!entry.is_regular_file()) continue;
    if (isImageExtension(lower(entry.path().extension().string()))) files.push_back(entry.path());
  }
  if (ec) throw FileError(folder, "cannot be listed: " + ec.message());
  std::sort(files.begin(), files.end());  // directory order varies; messages must not
  return files;
}

// UTIA's list of directions (one line per direction: number, theta, phi, theta_lS, phi_lS) as the
// lights of each view: light v of view v (light and camera at the same place) moved to its
// shifted position. The result keeps the UBO2003 set as its nominal one.
BtfDirectionSetPtr shiftedLightSet(const fs::path& list) {
  std::ifstream in(list);
  if (!in) throw FileError(list, "cannot be opened (named by btf.json's direction_list)");
  std::vector<std::array<double, 5>> rows;
  std::string line;
  int line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    std::array<double, 5> row{};
    std::istringstream fields(line);
    int n = 0;
    while (n < 5 && fields >> row[std::size_t(n)]) ++n;
    if (n == 0 && line.find_first_not_of(" \t\r") == std::string::npos) continue;
    if (n < 5) {
      if (rows.empty() && n == 0) continue;  // a heading
      throw FileError(list, "line " + std::to_string(line_number) +
                                " does not hold five numbers (number, theta, phi, theta_lS, phi_lS)");
    }
    rows.push_back(row);
  }
  if (rows.size() != std::size_t(kBtfDirectionCount))
    throw FileError(list, "lists " + std::to_string(rows.size()) + " directions; the UTIA layout has " +
                              std::to_string(kBtfDirectionCount));
  const BtfDirectionSet& nominal = *BtfDirectionSet::ubo2003();
  std::vector<BtfAngles> views(nominal.lights(0).begin(), nominal.lights(0).end());
  std::vector<std::vector<BtfAngles>> lights(std::size_t(kBtfDirectionCount), views);
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const auto& r = rows[k];
    if (findBtfDirection(float(r[1]), float(r[2])) != int(k))
      throw FileError(list, "direction " + std::to_string(k + 1) + " is (theta " + formatLimit(r[1]) + ", phi " +
                                formatLimit(r[2]) + "), not the set's (" + describeBtfDirection(int(k)) + ")");
    if (!(r[3] >= 0 && r[3] < 90) || !std::isfinite(r[4]))
      throw FileError(list, "direction " + std::to_string(k + 1) + " has a shifted light at theta " + formatLimit(r[3]) +
                                ", phi " + formatLimit(r[4]) + " (theta must lie in [0, 90))");
    lights[k][k] = BtfAngles{float(r[3]), float(r[4])};
  }
  try {
    return std::make_shared<const BtfDirectionSet>("UTIA, shifted lights", views, lights, BtfDirectionSet::ubo2003());
  } catch (const FileError&) {
    throw;
  } catch (const Error& e) {
    throw FileError(list, e.what());
  }
}

}  // namespace

BtfImageFolder BtfImageFolder::open(const fs::path& folder) {
  std::error_code ec;
  if (!fs::exists(folder, ec)) throw FileError(folder, "no such folder");
  if (!fs::is_directory(folder, ec)) throw FileError(folder, "is not a folder (a BTF is read from a folder of images)");

  BtfImageFolder result;
  result.folder_ = folder;
  result.paths_.assign(kImagesPerBtf, fs::path());
  // The UBO2003 layout: tagged images in the folder. Else the UTIA layout: a subfolder per view.
  std::vector<std::pair<fs::path, std::optional<int>>> files;  // with the view its folder names
  for (const fs::path& file : imageFilesIn(folder)) files.emplace_back(file, std::nullopt);
  const bool tagged = std::any_of(files.begin(), files.end(), [](const auto& f) {
    try {
      return parseBtfImageName(f.first.filename().string()).has_value();
    } catch (const Error&) {
      return true;  // reported below
    }
  });
  if (!tagged) {
    std::vector<std::pair<fs::path, int>> view_folders;
    for (const fs::directory_entry& entry : fs::directory_iterator(folder, ec))
      if (entry.is_directory())
        if (const std::optional<int> view = parseViewFolderName(entry.path().filename().string()))
          view_folders.emplace_back(entry.path(), *view);
    std::sort(view_folders.begin(), view_folders.end());
    if (!view_folders.empty()) {
      result.layout_ = BtfImageLayout::Utia;
      files.clear();
      for (const auto& [sub, view] : view_folders)
        for (const fs::path& file : imageFilesIn(sub)) files.emplace_back(file, view);
    }
  }

  int found = 0;
  for (const auto& [file, folder_view] : files) {
    std::optional<BtfImagePair> pair;
    try {
      pair = parseBtfImageName(file.filename().string());
    } catch (const Error& e) {
      throw FileError(file.parent_path(), e.what());
    }
    if (!pair) continue;
    if (folder_view && *folder_view != pair->view)
      throw FileError(file, "names view (" + describeBtfDirection(pair->view) + "), but it lies in the folder of view (" +
                                describeBtfDirection(*folder_view) + ")");
    fs::path& slot = result.paths_[std::size_t(pair->view * kBtfDirectionCount + pair->light)];
    if (!slot.empty())
      throw FileError(folder, "two images for " + describePair(pair->view, pair->light) + ": " +
                                  slot.lexically_relative(folder).string() + " and " +
                                  file.lexically_relative(folder).string());
    slot = file;
    ++found;
  }
  if (found == 0)
    throw FileError(folder, "holds no BTF images (expected images named like tv030_pv060_tl045_pl120.png, 81 lights "
                            "for each view held, in the folder or, in the UTIA layout, in subfolders like tv030_pv060/)");
  // A view is held when any of its images is there, and then needs all 81 (a gantry records every
  // light per camera position; the codecs group a texel's data by view).
  std::vector<int> held;
  for (int view = 0; view < kBtfDirectionCount; ++view) {
    int missing = 0, first_missing = -1;
    for (int light = 0; light < kBtfDirectionCount; ++light)
      if (result.paths_[std::size_t(view * kBtfDirectionCount + light)].empty()) {
        if (first_missing < 0) first_missing = light;
        ++missing;
      }
    if (missing == kBtfDirectionCount) continue;
    if (missing > 0) {
      // The name to suggest, with the extension the view's other images have (.exr, .jpg, ...).
      fs::path suggestion = btfImagePath(view, first_missing, BtfImageFormat::Png8, result.layout_);
      for (int light = 0; light < kBtfDirectionCount; ++light)
        if (const fs::path& held_path = result.paths_[std::size_t(view * kBtfDirectionCount + light)]; !held_path.empty()) {
          suggestion.replace_extension(held_path.extension());
          break;
        }
      throw FileError(folder, "the image of " + describePair(view, first_missing) + " is missing (e.g. " +
                                  suggestion.string() + "); " +
                                  std::to_string(missing) + " of the view's " + std::to_string(kBtfDirectionCount) +
                                  " light images are missing (a view held needs every light)");
    }
    held.push_back(view);
  }
  const Sidecar sidecar = readSidecar(folder);
  result.value_scale_ = sidecar.value_scale;
  result.transfer_override_ = sidecar.transfer;
  result.color_space_ = sidecar.color_space.value_or(result.layout_ == BtfImageLayout::Utia ? BtfColorSpace::Xyz
                                                                                             : BtfColorSpace::Rec709);
  BtfDirectionSetPtr directions = BtfDirectionSet::ubo2003();
  if (sidecar.direction_list) {
    result.direction_list_ = folder / *sidecar.direction_list;
    directions = shiftedLightSet(*result.direction_list_);
  }
  result.views_ = BtfViewSet(std::move(held), directions);
  const fs::path& first = result.imagePath(result.views_.view(0), 0);
  auto in = openImageInput(first);
  result.width_ = in->header().width;
  result.height_ = in->header().height;
  result.first_type_ = {in->header().floating_point, in->header().stored == PixelType::UInt8};
  if ((sidecar.width && *sidecar.width != result.width_) || (sidecar.height && *sidecar.height != result.height_))
    throw FileError(folder / kBtfSidecarName,
                    "records " + std::to_string(sidecar.width.value_or(result.width_)) + " x " +
                        std::to_string(sidecar.height.value_or(result.height_)) + " texels, but the images are " +
                        sizeText(result.width_, result.height_) + " (" + first.filename().string() + ")");
  return result;
}

BtfTransfer BtfImageFolder::transferOf(StoredType stored) const {
  if (stored.floating_point) return BtfTransfer::Linear;
  if (transfer_override_) return *transfer_override_;
  return stored.eight_bit ? BtfTransfer::Srgb : BtfTransfer::Linear;
}

std::optional<BtfTransfer> BtfImageFolder::transfer() const {
  if (first_type_.floating_point) return std::nullopt;
  return transferOf(first_type_);
}

std::optional<float> BtfImageFolder::white() const {
  if (first_type_.floating_point) return std::nullopt;
  return value_scale_;
}

std::string BtfImageFolder::name() const {
  const fs::path trimmed = folder_.has_filename() ? folder_ : folder_.parent_path();
  return trimmed.filename().string();
}

const fs::path& BtfImageFolder::imagePath(int view, int light) const {
  if (view < 0 || view >= kBtfDirectionCount || light < 0 || light >= kBtfDirectionCount)
    throw Error("BTF image index (" + std::to_string(view) + ", " + std::to_string(light) + ") is out of range");
  return paths_[std::size_t(view * kBtfDirectionCount + light)];  // empty for a view not held
}

void BtfImageFolder::checkImageHeaders() const {
  std::vector<std::exception_ptr> errors(paths_.size());
  tbb::parallel_for(std::size_t(0), paths_.size(), [&](std::size_t k) {
    if (paths_[k].empty()) return;  // a view not held
    try {
      (void)openBtfImage(paths_[k], width_, height_, imagePath(views_.view(0), 0));
    } catch (...) {
      errors[k] = std::current_exception();
    }
  });
  rethrowFirst(errors);
}

void BtfImageFolder::readImageInto(int view, int light, std::vector<Rgb>& out) const {
  const fs::path& path = imagePath(view, light);
  auto in = openBtfImage(path, width_, height_, imagePath(views_.view(0), 0));
  const image_backend::ImageHeader& spec = in->header();
  const std::size_t texels = std::size_t(width_) * std::size_t(height_);
  Rgb* dst = out.data() + std::size_t(light) * texels;
  const bool eight_bit = spec.stored == PixelType::UInt8;
  const BtfTransfer transfer = transferOf({spec.floating_point, eight_bit});
  if (eight_bit) {
    // 8-bit codes through a table of their 256 values (the sRGB curve's pow per pixel would cost
    // more than the decoding of the JPEG).
    std::array<float, 256> table;
    for (int code = 0; code < 256; ++code)
      table[std::size_t(code)] =
          (transfer == BtfTransfer::Srgb ? Srgb8::instance().decode(std::uint8_t(code)) : float(code) / 255.0f) *
          value_scale_;
    std::vector<std::uint8_t> codes;
    auto allocate = [&]() -> void* {
      codes.resize(texels * 3);
      return codes.data();
    };
    if (!in->readPixels(0, 3, PixelType::UInt8, allocate))
      throw FileError(path, "pixel data cannot be read (truncated or corrupt?): " + in->error());
    for (std::size_t i = 0; i < texels; ++i)
      dst[i] = Rgb(table[codes[3 * i]], table[codes[3 * i + 1]], table[codes[3 * i + 2]]);
    return;
  }
  std::vector<float> pixels;
  auto allocate = [&]() -> void* {
    pixels.resize(texels * 3);
    return pixels.data();
  };
  // Channels 0..2 only; integer data arrives as code / max_code.
  if (!in->readPixels(0, 3, PixelType::Float, allocate))
    throw FileError(path, "pixel data cannot be read (truncated or corrupt?): " + in->error());
  const bool is_float = spec.floating_point;
  const float scale = is_float ? 1.0f : value_scale_;
  if (transfer == BtfTransfer::Srgb)
    for (float& p : pixels) p = srgbDecode(p);  // 16-bit codes: rarely sRGB, not worth a table
  const bool xyz = is_float && color_space_ == BtfColorSpace::Xyz;
  for (std::size_t i = 0; i < texels; ++i) {
    Rgb v(pixels[3 * i] * scale, pixels[3 * i + 1] * scale, pixels[3 * i + 2] * scale);
    if (xyz && v.isFinite() && v.minComponent() >= 0.0f) {
      // Colours outside the Rec.709 gamut come out slightly negative: 0, as a reflectance is.
      const Rgb rgb = xyzToLinearRec709(v);
      v = Rgb(std::max(rgb.r, 0.0f), std::max(rgb.g, 0.0f), std::max(rgb.b, 0.0f));
    }
    if (is_float && (!v.isFinite() || v.minComponent() < 0.0f || v.maxComponent() > kMaxReflectance))
      throw FileError(path, "pixel (" + std::to_string(i % std::size_t(width_)) + ", " +
                                std::to_string(i / std::size_t(width_)) + ") holds " +
                                (!v.isFinite()               ? std::string("NaN or infinity")
                                 : v.minComponent() < 0.0f ? "a negative value"
                                                           : "the value " + formatLimit(v.maxComponent())) +
                                "; BTF values are finite, >= 0 and <= " + formatLimit(kMaxReflectance));
    dst[i] = v;
  }
}

void BtfImageFolder::loadView(int view, std::vector<Rgb>& out) const {
  views_.require(view, name());
  out.resize(std::size_t(kBtfDirectionCount) * texelCount());
  std::vector<std::exception_ptr> errors(kBtfDirectionCount);
  tbb::parallel_for(0, kBtfDirectionCount, [&](int light) {
    try {
      readImageInto(view, light, out);
    } catch (...) {
      errors[std::size_t(light)] = std::current_exception();
    }
  });
  rethrowFirst(errors);
}

// ---------------------------------------------------------------------------------------------
// Writing

namespace {

// Hidden sibling of the destination, unique per process and call.
fs::path siblingPath(const fs::path& folder, const std::string& kind) {
  static std::atomic<unsigned> counter{0};
  std::string name(".");
  name.append(folder.filename().string())
      .append(".")
      .append(kind)
      .append(std::to_string(::getpid()))
      .append("-")
      .append(std::to_string(counter++));
  return folder.parent_path() / name;
}

void requireValidValue(const BtfSource& source, int view, std::size_t index, const Rgb& v) {
  if (v.isFinite() && v.minComponent() >= 0.0f) return;
  const std::size_t texels = source.texelCount();
  const std::size_t light = index / texels, texel = index % texels;
  throw Error(source.name() + ": entry (x " + std::to_string(texel % std::size_t(source.width())) + ", y " +
              std::to_string(texel / std::size_t(source.width())) + ", view " + std::to_string(view) + ", light " +
              std::to_string(light) + ") is " + (v.isFinite() ? "negative" : "NaN or infinite") +
              "; cannot be written as a BTF image");
}

float findLargestValue(const BtfSource& source) {
  Progress progress("scanning " + source.name() + " for its largest value", source.views().count());
  std::vector<Rgb> values;
  float largest = 0.0f;
  for (const int view : source.views().views()) {
    source.loadView(view, values);
    for (std::size_t i = 0; i < values.size(); ++i) {
      requireValidValue(source, view, i, values[i]);
      largest = std::max(largest, values[i].maxComponent());
    }
    progress.advance();
  }
  return largest;
}

template <typename Code>
std::vector<Code> quantize(const Rgb* values, std::size_t count, float value_scale, BtfTransfer transfer) {
  constexpr float kMaxCode = float(std::numeric_limits<Code>::max());
  const bool srgb8 = transfer == BtfTransfer::Srgb && sizeof(Code) == 1;
  const Srgb8& srgb = Srgb8::instance();
  std::vector<Code> codes(count * 3);
  for (std::size_t i = 0; i < count; ++i)
    for (int c = 0; c < 3; ++c) {
      float e = std::clamp(values[i][c] / value_scale, 0.0f, 1.0f);
      if (srgb8) {
        codes[3 * i + std::size_t(c)] = Code(srgb.encode(e));
        continue;
      }
      if (transfer == BtfTransfer::Srgb) e = srgbEncode(e);
      codes[3 * i + std::size_t(c)] = Code(std::lround(e * kMaxCode));
    }
  return codes;
}

void writeOneImage(const fs::path& path, int width, int height, BtfImageFormat format, const Rgb* values,
                   float value_scale) {
  std::string error;
  auto out = imageBackend().createWriter(path.string(), error);
  if (!out) throw FileError(path, "no image writer for this extension: " + error);
  const std::size_t count = std::size_t(width) * std::size_t(height);
  PixelType type = PixelType::Float;
  std::vector<std::uint8_t> codes8;
  std::vector<std::uint16_t> codes16;
  const void* data = values;
  static_assert(sizeof(Rgb) == 3 * sizeof(float), "Rgb is read as three packed floats");
  if (format == BtfImageFormat::Png8) {
    codes8 = quantize<std::uint8_t>(values, count, value_scale, btfWriterTransfer(format));
    type = PixelType::UInt8;
    data = codes8.data();
  } else if (format == BtfImageFormat::Png16) {
    codes16 = quantize<std::uint16_t>(values, count, value_scale, btfWriterTransfer(format));
    type = PixelType::UInt16;
    data = codes16.data();
  }
  image_backend::WriteSpec spec{width, height, 3, type, {}};
  if (format == BtfImageFormat::Exr) spec.attributes.emplace_back("compression", std::string("zip"));
  if (!out->open(path.string(), spec) || !out->write(type, data) || !out->close())
    throw FileError(path, "cannot be written: " + out->error());
}

// A destination we may replace: absent, an empty folder, or a BTF folder this writer made.
void requireReplaceable(const fs::path& folder, bool overwrite) {
  std::error_code ec;
  const fs::path parent = folder.parent_path().empty() ? fs::path(".") : folder.parent_path();
  if (!fs::is_directory(parent, ec)) throw FileError(folder, "folder " + parent.string() + " does not exist");
  if (!fs::exists(folder, ec)) return;
  if (!fs::is_directory(folder, ec)) throw FileError(folder, "exists and is not a folder");
  if (fs::is_empty(folder, ec)) return;
  if (!overwrite) throw FileError(folder, "exists already (remove it first)");
  if (!fs::exists(folder / kBtfSidecarName, ec))
    throw FileError(folder, "exists and is not a BTF image folder written by libbtf (no " +
                                std::string(kBtfSidecarName) + "); refusing to replace it");
}

void writeSidecar(const fs::path& path, const BtfSource& source, const BtfImageWriteOptions& options, float value_scale) {
  const BtfImageFormat format = options.format;
  nlohmann::json doc{{"value_scale", value_scale},
                     {"layout", btfImageLayoutName(options.layout)},
                     {"width", source.width()},
                     {"height", source.height()},
                     {"views", source.views().count()},
                     {"format", btfImageFormatName(format)},
                     {"source", source.name()},
                     {"value", "apparent BRDF (1/sr); integer images hold transfer(code / max_code) * value_scale"}};
  if (format != BtfImageFormat::Exr) doc["transfer"] = btfTransferName(btfWriterTransfer(format));
  else doc["color_space"] = options.layout == BtfImageLayout::Utia ? "xyz" : "rec709";
  std::ofstream out(path);
  out << doc.dump(2) << "\n";
  out.flush();
  if (!out) throw FileError(path, "cannot be written (disk full?)");
}

}  // namespace

void writeBtfImageFolder(const BtfSource& source, const fs::path& folder_in, const BtfImageWriteOptions& options) {
  // A trailing slash would make the temporary folder a child instead of a sibling.
  const fs::path folder = folder_in.has_filename() ? folder_in : folder_in.parent_path();
  if (folder.empty()) throw FileError(folder_in, "is not a folder name to write");
  source.views().requireUbo2003("the image-folder layout (" + folder.filename().string() +
                                 ": files are named by the 81 directions' whole-degree angles)");
  requireReplaceable(folder, options.overwrite);
  const bool is_png = options.format != BtfImageFormat::Exr;
  float value_scale = 1.0f;
  if (is_png) {
    if (options.value_scale) {
      value_scale = *options.value_scale;
      if (!validValueScale(value_scale))
        throw Error("value_scale must be in [" + formatLimit(kMinValueScale) + ", " + formatLimit(kMaxReflectance) +
                    "], not " + formatLimit(value_scale));
    } else {
      const float largest = findLargestValue(source);
      value_scale = largest > 0.0f ? largest : 1.0f;
    }
  }

  removeStaleTemporaries(folder);
  const fs::path temporary = siblingPath(folder, "tmp");
  const TemporaryGuard guard(temporary, true);
  std::error_code ec;
  if (!fs::create_directory(temporary, ec)) throw FileError(temporary, "cannot be created: " + ec.message());
  try {
    Progress progress("writing " + folder.filename().string(), std::size_t(source.views().count()) * kBtfDirectionCount);
    const int width = source.width(), height = source.height();
    const std::size_t texels = source.texelCount();
    std::vector<Rgb> values;
    for (const int view : source.views().views()) {
      source.loadView(view, values);
      if (values.size() != texels * kBtfDirectionCount)
        throw Error(source.name() + ": view " + std::to_string(view) + " has " + std::to_string(values.size()) +
                    " values, expected " + std::to_string(texels * kBtfDirectionCount));
      for (std::size_t i = 0; i < values.size(); ++i) requireValidValue(source, view, i, values[i]);
      // The UTIA layout: a folder per view, and float images in CIE XYZ as that database keeps them.
      if (options.layout == BtfImageLayout::Utia) {
        const fs::path sub = temporary / fs::path(btfImagePath(view, 0, options.format, options.layout)).parent_path();
        if (!fs::create_directory(sub, ec)) throw FileError(sub, "cannot be created: " + ec.message());
        if (options.format == BtfImageFormat::Exr)
          for (Rgb& v : values) v = linearRec709ToXyz(v);
      }
      std::vector<std::exception_ptr> errors(kBtfDirectionCount);
      tbb::parallel_for(0, kBtfDirectionCount, [&](int light) {
        try {
          const fs::path path = temporary / btfImagePath(view, light, options.format, options.layout);
          writeOneImage(path, width, height, options.format, values.data() + std::size_t(light) * texels, value_scale);
          progress.advance();
        } catch (...) {
          errors[std::size_t(light)] = std::current_exception();
        }
      });
      rethrowFirst(errors);
    }
    writeSidecar(temporary / kBtfSidecarName, source, options, value_scale);

    // Swap in: move an old folder aside first, so the destination name always holds a whole BTF.
    fs::path old;
    if (fs::exists(folder, ec)) {
      old = siblingPath(folder, "old");
      fs::rename(folder, old, ec);
      if (ec) throw FileError(folder, "cannot be replaced: " + ec.message());
    }
    fs::rename(temporary, folder, ec);
    if (ec) {
      std::error_code ignored;
      if (!old.empty()) fs::rename(old, folder, ignored);
      throw FileError(folder, "cannot be written: " + ec.message());
    }
    if (!old.empty()) fs::remove_all(old, ec);
  } catch (...) {
    std::error_code ignored;
    fs::remove_all(temporary, ignored);
    throw;
  }
}

}  // namespace btf
