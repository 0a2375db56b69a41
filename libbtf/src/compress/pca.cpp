// PcaBtf: decoding and the storage count (compression is in pca_compress.cpp).
#include "btf/compress/pca.h"

#include <Eigen/Core>

#include <algorithm>

#include "btf/core/error.h"

namespace btf {

namespace {

// The dimension (3 x lights) of the view with the fewest lights: the most components every view has.
int smallestDimension(const BtfViewSet& views) {
  int lights = views.directions().lightCount(views.view(0));
  for (const int v : views.views()) lights = std::min(lights, views.directions().lightCount(v));
  return 3 * lights;
}

// `views` views of the 81-direction set (which ones does not change a size).
BtfViewSet firstViews(int views) {
  if (views < 1 || views > kBtfDirectionCount) throw Error("PCA: " + std::to_string(views) + " views is outside 1..81");
  std::vector<int> held(static_cast<std::size_t>(views));
  for (int v = 0; v < views; ++v) held[std::size_t(v)] = v;
  return BtfViewSet(std::move(held));
}

}  // namespace

std::uint64_t PcaBtf::storedBytesFor(int width, int height, int components, PcaPrecision precision, int views) {
  return storedBytesFor(width, height, components, precision, firstViews(views));
}

std::uint64_t PcaBtf::storedBytesFor(int width, int height, int components, PcaPrecision precision,
                                     const BtfViewSet& views) {
  if (width < 1 || height < 1) throw Error("PCA: BTF size " + std::to_string(width) + " x " + std::to_string(height) + " is invalid");
  const int most = smallestDimension(views);
  if (components < 0 || components > most)
    throw Error("PCA: " + std::to_string(components) + " components is outside 0.." + std::to_string(most));
  const std::uint64_t value_bytes = precision == PcaPrecision::Half ? 2 : 4;
  const std::uint64_t texels = std::uint64_t(width) * std::uint64_t(height);
  const std::uint64_t k = std::uint64_t(components);
  std::uint64_t bytes = kPcaHeaderBytes;
  for (const int v : views.views()) {
    const std::uint64_t dims = 3 * std::uint64_t(views.directions().lightCount(v));
    bytes += dims * 4                   // mean, float32
             + k * dims * value_bytes   // basis
             + k * 4                    // component scales, float32
             + texels * k * value_bytes;  // coefficients
  }
  return bytes;
}

int pcaComponentsForBudget(int width, int height, std::uint64_t byte_budget, PcaPrecision precision,
                           const BtfViewSet& views) {
  const std::uint64_t base = PcaBtf::storedBytesFor(width, height, 0, precision, views);
  if (byte_budget < base) return -1;
  const std::uint64_t per_component = PcaBtf::storedBytesFor(width, height, 1, precision, views) - base;
  return int(std::min<std::uint64_t>(std::uint64_t(smallestDimension(views)), (byte_budget - base) / per_component));
}

int pcaComponentsForBudget(int width, int height, std::uint64_t byte_budget, PcaPrecision precision, int views) {
  return pcaComponentsForBudget(width, height, byte_budget, precision, firstViews(views));
}

PcaBtf compressPcaToBytes(const BtfSource& source, std::uint64_t byte_budget, PcaPrecision precision) {
  const BtfViewSet& views = source.views();
  const int k = pcaComponentsForBudget(source.width(), source.height(), byte_budget, precision, views);
  if (k < 0)
    throw Error("PCA of " + source.name() + ": a budget of " + std::to_string(byte_budget) +
                " bytes cannot hold even the per-view means (" +
                std::to_string(PcaBtf::storedBytesFor(source.width(), source.height(), 0, precision, views)) +
                " bytes)");
  return compressPca(source, k, precision);
}

void PcaBtf::loadView(int view, std::vector<Rgb>& out) const {
  view_set_.require(view, name_);
  using RowMajor = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  const View& v = views_[std::size_t(view_set_.slot(view))];
  const Eigen::Index texels = Eigen::Index(texelCount()), k = components_;
  const Eigen::Index dims = Eigen::Index(v.mean.size());
  const int lights = int(dims / 3);
  // decoded(t, d) = sum_j c_tj b_dj, column-major so that each (light, channel) column is contiguous.
  Eigen::MatrixXf decoded = Eigen::MatrixXf::Zero(texels, dims);
  if (k > 0) {
    const Eigen::Map<const RowMajor> coefficients(v.coefficients.data(), texels, k);
    const Eigen::Map<const RowMajor> basis(v.basis.data(), dims, k);
    decoded.noalias() = coefficients * basis.transpose();
  }
  out.resize(std::size_t(lights) * std::size_t(texels));
  for (int light = 0; light < lights; ++light) {
    const int d = 3 * light;
    const float mr = v.mean[std::size_t(d)], mg = v.mean[std::size_t(d) + 1], mb = v.mean[std::size_t(d) + 2];
    Rgb* row = out.data() + std::size_t(light) * std::size_t(texels);
    for (Eigen::Index t = 0; t < texels; ++t)
      row[t] = Rgb(mr + decoded(t, d), mg + decoded(t, d + 1), mb + decoded(t, d + 2));
  }
}

Rgb PcaBtf::value(int x, int y, int view, int light) const {
  const View& v = views_[std::size_t(view_set_.slot(view))];
  const std::size_t k = std::size_t(components_);
  const std::size_t t = std::size_t(y) * std::size_t(width_) + std::size_t(x);
  const std::size_t d = 3 * std::size_t(light);
  const float* c = v.coefficients.data() + t * k;
  const float* b = v.basis.data() + d * k;
  float r = v.mean[d], g = v.mean[d + 1], bl = v.mean[d + 2];
  for (std::size_t j = 0; j < k; ++j) {
    r += c[j] * b[j];
    g += c[j] * b[k + j];
    bl += c[j] * b[2 * k + j];
  }
  return {r, g, bl};
}

}  // namespace btf
