// Measured BTF data: RGB reflectance over texels (x, y) x the (view, light) pairs of a direction
// set (core/btf_direction_set.h; the 81 x 81 UBO2003 set unless the data says otherwise). The value is what image-based BTF measurements store: the
// reflected radiance towards the view over the irradiance a flat sample would receive from the
// light, i.e. an "apparent BRDF" (1/sr) that includes the microgeometry's masking, shadowing and
// interreflection; a flat sample of a BRDF f gives f itself.
//
// BtfSource is the streaming interface: a consumer asks for one view at a time (all of the view's
// lights for every texel: on the 81 set 81 * width * height RGB values, 64 MiB for 256 x 256
// texels), so a 256 x 256 BTF (5 GiB as float) never has to sit in memory whole. A source may hold
// only some of its set's views (core/btf_view_set.h): consumers loop over views() and ask for no
// other; views().directions() is the set. Readers (btf_images.h), the compressed forms
// (compress/) and the in-memory BtfData all implement it, so comparisons and converters work on
// any pair of them.
#pragma once

#include <cassert>
#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "btf/core/btf_directions.h"
#include "btf/core/btf_view_set.h"
#include "btf/core/rgb.h"

namespace btf {

class BtfSource {
 public:
  virtual ~BtfSource() = default;
  virtual int width() const = 0;
  virtual int height() const = 0;
  // The views the source holds, and through them its direction set (all 81 UBO2003 views unless
  // it says otherwise).
  virtual const BtfViewSet& views() const;
  // Fills out (resized to viewValueCount(view)) with the view's values, light-major:
  // out[(light * height + y) * width + x], lights in the set's order for that view.
  // Throws btf::Error / FileError (naming the file) on unreadable data or a view not held.
  virtual void loadView(int view, std::vector<Rgb>& out) const = 0;
  // Short description for reports, e.g. the folder name.
  virtual std::string name() const = 0;
  // The value the source's encoding saturates at, if it has one: an 8-bit or 16-bit image folder's
  // largest code (value_scale). Perceptual measures clip to it as the camera did.
  virtual std::optional<float> white() const { return std::nullopt; }

  const BtfDirectionSet& directions() const { return views().directions(); }
  std::size_t texelCount() const { return std::size_t(width()) * std::size_t(height()); }
  // Values of one view: its lights x texels.
  std::size_t viewValueCount(int view) const { return std::size_t(directions().lightCount(view)) * texelCount(); }
  // Entries of the whole BTF: texels x the held views' (view, light) pairs (each an RGB triple).
  std::size_t entryCount() const;
};

// Random access to single entries, for evaluation (material/btf_material.h). Implemented by the
// in-memory BtfData and by the compressed forms, which decode one entry without decoding more.
// One measured sample of a BTF: texel (x, y), view and light indices (btf_directions.h).
struct BtfSampleIndex {
  int x, y, view, light;
};

class BtfLookup {
 public:
  virtual ~BtfLookup() = default;
  virtual int lookupWidth() const = 0;
  virtual int lookupHeight() const = 0;
  // The views value() answers for (all 81 unless it says otherwise), and so the direction set.
  virtual const BtfViewSet& lookupViews() const;
  virtual Rgb value(int x, int y, int view, int light) const = 0;
  // A stream of lookups (after Embree's stream calls): out[i] = value(samples[i]), bit for bit.
  // Throws btf::Error for spans of different sizes, an index outside the BTF or a view it does not
  // hold (naming it). The default loops; a three-level VqBtf walks groups of samples one level at
  // a time, so that their table loads overlap (vq_stream.cpp).
  virtual void values(std::span<const BtfSampleIndex> samples, std::span<Rgb> out) const;

 protected:
  // The checks of values(): equal sizes, every index inside the BTF (btf::Error otherwise).
  void checkSampleIndices(std::span<const BtfSampleIndex> samples, std::size_t out_size) const;
};

// A BTF held in memory, view-major: at(x, y, view, light). For tests, small generated data and
// one-texel BTFs made from BRDFs. Only the held views take memory, on any direction set (that of
// `views`); at() and view() of a view not held is a programming error (checked in debug builds
// only: they are the hot accessors).
class BtfData final : public BtfSource, public BtfLookup {
 public:
  // Zero-filled; throws for sizes < 1.
  BtfData(int width, int height, std::string name = "btf", BtfViewSet views = {});
  int width() const override { return width_; }
  int height() const override { return height_; }
  std::string name() const override { return name_; }
  const BtfViewSet& views() const override { return views_; }
  std::optional<float> white() const override { return white_; }
  void setWhite(std::optional<float> white) { white_ = white; }
  void loadView(int view, std::vector<Rgb>& out) const override;
  int lookupWidth() const override { return width_; }
  int lookupHeight() const override { return height_; }
  const BtfViewSet& lookupViews() const override { return views_; }
  Rgb value(int x, int y, int view, int light) const override { return at(x, y, view, light); }

  Rgb& at(int x, int y, int view, int light) { return values_[index(x, y, view, light)]; }
  const Rgb& at(int x, int y, int view, int light) const { return values_[index(x, y, view, light)]; }
  // The view's block, light-major as loadView writes it (viewValueCount(view) values).
  Rgb* view(int view) { return values_.data() + view_offsets_[slotOf(view)]; }
  const Rgb* view(int view) const { return values_.data() + view_offsets_[slotOf(view)]; }

  // Reads a whole source into memory, the views it holds (progress reported per view).
  static BtfData copyOf(const BtfSource& source);

 private:
  std::size_t slotOf(int view) const;
  std::size_t index(int x, int y, int view, int light) const {
    return view_offsets_[slotOf(view)] + (std::size_t(light) * std::size_t(height_) + std::size_t(y)) * std::size_t(width_) +
           std::size_t(x);
  }
  int width_, height_;
  std::string name_;
  BtfViewSet views_;
  std::vector<std::size_t> view_offsets_;  // per slot, into values_
  std::optional<float> white_;
  std::vector<Rgb> values_;
};

inline std::size_t BtfData::slotOf(int view) const {
  assert(views_.contains(view));
  return std::size_t(views_.slot(view));
}

// Errors of one BTF against a reference over all entries and channels (docs/design-notes.md#measures):
// rel_rmse = RMSE / RMS of the reference; psnr_db = 20 log10(max of the reference / RMSE);
// luminance_rel_rmse the same of the luminance alone (what the VQ tolerances bound, vq_btf.h).
// Over the reference's views; throws btf::Error if the sizes differ, the test lacks one of those
// views, or the reference is all zero.
struct BtfErrorStats {
  double rel_rmse = 0, psnr_db = 0, rmse = 0, reference_rms = 0, reference_max = 0;
  double luminance_rel_rmse = 0;
  std::size_t entries = 0;
};
BtfErrorStats compareBtf(const BtfSource& reference, const BtfSource& test);

}  // namespace btf
