// The steps of a dataset compressed in parts (compress/vq_dataset.h): shared codebooks on their
// own and as bytes, their merge within the tolerance, databases as bytes, texel tiles and their
// join. The re-code (compressVqDatabase from a seed) is in vq_compress.cpp, beside the compressor.
#include "btf/compress/vq_dataset.h"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <random>

#include <tbb/parallel_for.h>

#include "btf/compress/codebook.h"
#include "btf/core/error.h"
#include "vq_codebooks.h"
#include "vq_sections.h"

namespace btf {

namespace vq_dataset_detail {

constexpr const char* kVqCodebooksFormat = "libbtf-vq-codebooks";
constexpr int kVqCodebooksVersion = 1;
// The zstd level of bytes between processes: they are read once, soon after; the level of files
// (vqZstdLevelFor) would cost more time than the bytes it saves on the way. The final file is
// written by VqDatabase::write at its own level.
constexpr int kVqTransportZstdLevel = 1;
// The merge's searches, as the compressor's below level 3: at most this many kd-tree node visits per
// segment (codebook.h), so that a search costs about the same whatever the codebook's size; a missed
// entry within the tolerance costs a merged entry, never accuracy (the re-code checks every reuse).
constexpr int kMergeMaxVisits = 16;
// Entries added between two index() calls (the compressor's chunk): the rest of a codebook is
// searched in its kd-trees, the entries not yet indexed by a linear scan.
constexpr std::size_t kMergeIndexEvery = 128;
const Codebook::SearchOptions kMergeSearch{0, kMergeMaxVisits};
// Adds an entry to `book`, indexing every kMergeIndexEvery entries.
std::uint32_t addIndexed(Codebook& book, std::span<const float> values) {
  const std::uint32_t e = book.add(values);
  if (book.size() % kMergeIndexEvery == 0) book.index();
  return e;
}

std::string codebookGroupPrefix(std::size_t g) { return "group" + std::to_string(g) + "/"; }

bool sameDatasetOptions(const VqOptions& a, const VqOptions& b) {
  return a.levels == b.levels && a.epsilon == b.epsilon && a.chroma_epsilon == b.chroma_epsilon &&
         a.energy_floor == b.energy_floor;
}

// A file of its own in the system's temporary folder, removed when the guard goes: the .btfz
// container is read and written as files, and this process's bytes pass through one.
class ScratchFile {
 public:
  ScratchFile() {
    static std::atomic<unsigned> counter{0};
    std::random_device random;
    path_ = std::filesystem::temp_directory_path() /
            ("libbtf-bytes-" + std::to_string(::getpid()) + "-" + std::to_string(counter++) + "-" +
             std::to_string(random()) + ".btfz");
  }
  ~ScratchFile() {
    std::error_code ignored;
    std::filesystem::remove(path_, ignored);
  }
  ScratchFile(const ScratchFile&) = delete;
  ScratchFile& operator=(const ScratchFile&) = delete;
  const std::filesystem::path& path() const { return path_; }
  std::vector<std::byte> bytes() const {
    std::ifstream in(path_, std::ios::binary);
    std::vector<char> data((std::istreambuf_iterator<char>(in)), {});
    if (!in.good() && !in.eof()) throw FileError(path_, "cannot be read back");
    std::vector<std::byte> out(data.size());
    std::memcpy(out.data(), data.data(), data.size());
    return out;
  }
  void put(std::span<const std::byte> bytes) const {
    std::ofstream out(path_, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
    out.close();
    if (!out) throw FileError(path_, "cannot be written (the temporary folder is full or not writable?)");
  }

 private:
  std::filesystem::path path_;
};

// A group of codebooks: layout, views and options of `m`, no entries.
VqBtf::Impl emptyGroupLike(const VqBtf::Impl& m) {
  VqBtf::Impl g;
  g.options = m.options;
  g.views = m.views;
  g.setLayout(m.layout);
  return g;
}
void copySharedCodebooks(const VqBtf::Impl& from, VqBtf::Impl& to) {
  to.l1 = from.l1;
  to.chroma = from.chroma;
  to.l2_index = from.l2_index;
  to.l2_scale = from.l2_scale;
  to.l2_chroma = from.l2_chroma;
}

std::vector<std::size_t> groupEntries(const VqBtf::Impl& g) {
  std::vector<std::size_t> entries = vqCodebookEntries(g);
  if (g.options.levels == 3) entries.pop_back();
  return entries;
}

// The reduce of one ring layout: the merged codebooks and the search trees over their decoded
// entries, which the parts' entries are inserted into one by one.
class CodebookMerger {
 public:
  explicit CodebookMerger(const VqBtf::Impl& like)
      : out_(emptyGroupLike(like)),
        R_(out_.ringCount()),
        L_(std::size_t(out_.layout.lightCount())),
        step_(vqChromaStep(out_.options.chroma_epsilon)),
        scale_shift_(vqPrecisionFor(out_.options.epsilon, out_.layout.maxSize()).scale_shift) {
    for (std::size_t r = 0; r < R_; ++r) {
      l1_.emplace_back(out_.ringSize(int(r)));
      chroma_.emplace_back(2 * out_.ringSize(int(r)));
    }
    if (out_.options.levels >= 2) l2_.emplace_back(int(L_));
  }

  void insert(const VqBtf::Impl& part) {
    std::vector<std::vector<std::uint32_t>> l1_map(R_), chroma_map(R_);
    // Each ring's level-1 and chromaticity codebooks are merged on their own (parallel jobs, each
    // sequential in entry order: the result does not depend on the threads).
    tbb::parallel_for(std::size_t(0), 2 * R_, [&](std::size_t job) {
      const std::size_t r = job / 2, n = std::size_t(out_.ringSize(int(r)));
      std::vector<Codebook::Match> found;
      if (job % 2 == 0) {
        for (std::size_t e = 0; e < part.l1Count(int(r)); ++e) l1_map[r].push_back(insertLevel1(r, &part.l1[r][e * n], e == 0, found));
        l1_[r].index();
      } else {
        for (std::size_t c = 0; c < part.chromaCount(int(r)); ++c)
          chroma_map[r].push_back(insertChroma(r, &part.chroma[r][c * 2 * n], c == 0, found));
        chroma_[r].index();
      }
    });
    if (out_.options.levels >= 2) {
      for (std::size_t e = 0; e < part.l2Count(); ++e) insertLevel2(part, e, l1_map, chroma_map);
      l2_.front().index();
    }
  }
  VqBtf::Impl result() && { return std::move(out_); }

 private:
  // The relative least-squares rule of level 1 (codebook.h) at epsilon. Entry 0 (the constant seed,
  // the same in every part) stays entry 0.
  std::uint32_t insertLevel1(std::size_t r, const std::uint16_t* codes, bool seed, std::vector<Codebook::Match>& found) {
    const std::size_t n = std::size_t(out_.ringSize(int(r)));
    std::vector<float> v(n);
    for (std::size_t a = 0; a < n; ++a) v[a] = decodeVqEntryValue(codes[a]);
    if (seed && l1_[r].size() > 0) return 0;
    const double len = std::sqrt(dotOf(v.data(), v.data(), n));
    if (len > 0 && l1_[r].size() > 0) {
      std::vector<float> unit(n);
      for (std::size_t a = 0; a < n; ++a) unit[a] = float(v[a] / len);
      l1_[r].search(unit, Codebook::chordRadius(out_.options.epsilon), 1, found, kMergeSearch);
      if (!found.empty()) return found.front().index;
    }
    out_.l1[r].insert(out_.l1[r].end(), codes, codes + n);
    return addIndexed(l1_[r], v);
  }
  // Chromaticity: an absolute L2 distance <= chroma_epsilon between the functions, which bounds
  // the compressor's luminance-weighted error (weights of a unit luminance function) for any
  // luminance. Candidates by direction within a chord radius that such a distance cannot exceed.
  std::uint32_t insertChroma(std::size_t r, const std::int32_t* grid, bool seed, std::vector<Codebook::Match>& found) {
    const std::size_t n2 = 2 * std::size_t(out_.ringSize(int(r)));
    std::vector<float> c(n2);
    for (std::size_t i = 0; i < n2; ++i) c[i] = float(grid[i]) * step_;
    if (seed && chroma_[r].size() > 0) return 0;
    const double len = std::sqrt(dotOf(c.data(), c.data(), n2));
    const double tolerance = out_.options.chroma_epsilon;
    if (len > 0 && chroma_[r].size() > 0) {
      std::vector<float> unit(n2);
      for (std::size_t i = 0; i < n2; ++i) unit[i] = float(c[i] / len);
      const float radius = float(std::min(2.0 * tolerance / len, 1.415));
      chroma_[r].search(unit, radius, 8, found, kMergeSearch);
      for (const Codebook::Match& m : found) {
        const float* e = chroma_[r].entry(m.index);
        double d2 = 0;
        for (std::size_t i = 0; i < n2; ++i) d2 += (double(e[i]) - c[i]) * (double(e[i]) - c[i]);
        if (d2 <= tolerance * tolerance) return m.index;
      }
    }
    out_.chroma[r].insert(out_.chroma[r].end(), grid, grid + n2);
    return addIndexed(chroma_[r], c);
  }
  // Level 2: the part's entry on the merged level-1 entries (each ring's scale refitted by least
  // squares to the merged entry), then the relative rule at epsilon on that reconstruction among
  // merged entries of the same chromaticities.
  void insertLevel2(const VqBtf::Impl& part, std::size_t e, const std::vector<std::vector<std::uint32_t>>& l1_map,
                    const std::vector<std::vector<std::uint32_t>>& chroma_map) {
    std::vector<std::uint32_t> index(R_), chroma(R_);
    std::vector<std::uint16_t> scale(R_);
    std::vector<float> recon(L_, 0.0f);
    for (std::size_t r = 0; r < R_; ++r) {
      const std::size_t n = std::size_t(out_.ringSize(int(r))), start = std::size_t(out_.layout.start(int(r)));
      const std::size_t k = e * R_ + r;
      index[r] = l1_map[r].at(part.l2_index[k]);
      chroma[r] = chroma_map[r].at(part.l2_chroma[k]);
      const float* merged = l1_[r].entry(index[r]);
      std::vector<float> own(n);
      for (std::size_t a = 0; a < n; ++a) own[a] = decodeVqEntryValue(part.l1[r][std::size_t(part.l2_index[k]) * n + a]);
      const double mm = dotOf(merged, merged, n);
      const double s = double(decodeVqScale(part.l2_scale[k])) * (mm > 0 ? dotOf(own.data(), merged, n) / mm : 0.0);
      scale[r] = encodeVqScale(float(s), scale_shift_);
      const float decoded = decodeVqScale(scale[r]);
      for (std::size_t a = 0; a < n; ++a) recon[start + a] = decoded * merged[a];
    }
    std::uint32_t to = 0;
    const double len = std::sqrt(dotOf(recon.data(), recon.data(), L_));
    bool found = e == 0 && l2_.front().size() > 0;  // the uniform slice, entry 0 in every part
    if (!found && len > 0 && l2_.front().size() > 0) {
      std::vector<float> unit(L_);
      for (std::size_t l = 0; l < L_; ++l) unit[l] = float(recon[l] / len);
      l2_.front().search(unit, Codebook::chordRadius(out_.options.epsilon), 8, found_, kMergeSearch);
      for (const Codebook::Match& m : found_) {
        bool same = true;
        for (std::size_t r = 0; r < R_ && same; ++r)
          same = out_.l2_chroma[std::size_t(m.index) * R_ + r] == chroma[r] || out_.l2_scale[std::size_t(m.index) * R_ + r] == 0 ||
                 scale[r] == 0;
        if (same) {
          to = m.index;
          found = true;
          break;
        }
      }
    }
    if (!found) {
      out_.l2_index.insert(out_.l2_index.end(), index.begin(), index.end());
      out_.l2_scale.insert(out_.l2_scale.end(), scale.begin(), scale.end());
      out_.l2_chroma.insert(out_.l2_chroma.end(), chroma.begin(), chroma.end());
      to = addIndexed(l2_.front(), recon);
    }
    (void)to;  // level 3 is re-coded: the part's level-2 indices are not needed
  }

  static double dotOf(const float* a, const float* b, std::size_t n) {
    double s = 0;
    for (std::size_t i = 0; i < n; ++i) s += double(a[i]) * b[i];
    return s;
  }

  VqBtf::Impl out_;
  std::size_t R_, L_;
  float step_;
  int scale_shift_;
  std::vector<Codebook> l1_, chroma_, l2_;
  std::vector<Codebook::Match> found_;
};

void checkTilesCover(std::span<const BtfRect> rects, int width, int height) {
  if (width < 1 || height < 1) throw Error("joinVqTiles: the material needs a positive size");
  std::vector<unsigned char> covered(std::size_t(width) * std::size_t(height), 0);
  for (const BtfRect& r : rects) {
    if (r.width < 1 || r.height < 1 || r.x < 0 || r.y < 0 || r.x + r.width > width || r.y + r.height > height)
      throw Error("joinVqTiles: tile (" + std::to_string(r.x) + ", " + std::to_string(r.y) + ", " + std::to_string(r.width) +
                  " x " + std::to_string(r.height) + ") is not inside the " + std::to_string(width) + " x " +
                  std::to_string(height) + " texels");
    for (int y = r.y; y < r.y + r.height; ++y)
      for (int x = r.x; x < r.x + r.width; ++x)
        if (covered[std::size_t(y) * std::size_t(width) + std::size_t(x)]++)
          throw Error("joinVqTiles: texel (" + std::to_string(x) + ", " + std::to_string(y) + ") is in two tiles");
  }
  for (std::size_t i = 0; i < covered.size(); ++i)
    if (!covered[i])
      throw Error("joinVqTiles: texel (" + std::to_string(i % std::size_t(width)) + ", " + std::to_string(i / std::size_t(width)) +
                  ") is in no tile");
}

// The tiles (materials of one database, so sharing its codebooks) joined into one material.
std::shared_ptr<VqBtf::Impl> joinTiles(const std::vector<const VqBtf::Impl*>& tiles, std::span<const BtfRect> rects, int width,
                                       int height, const std::string& name) {
  checkTilesCover(rects, width, height);
  const VqBtf::Impl& first = *tiles.front();
  auto m = std::make_shared<VqBtf::Impl>();
  m->options = first.options;
  m->views = first.views;
  m->setLayout(first.layout);
  copySharedCodebooks(first, *m);
  m->width = width;
  m->height = height;
  m->name = name;
  const std::size_t R = m->ringCount(), V = m->viewCount(), T = std::size_t(width) * std::size_t(height);
  const int levels = m->options.levels;
  // Per texel: the top stream's values of one texel (levels 1: views x rings, 2: views, 3: one).
  const std::size_t per = levels == 1 ? V * R : levels == 2 ? V : 1;
  m->top_index.assign(T * per, 0);
  m->top_scale.assign(T * per, 0);
  if (levels == 1) m->top_chroma.assign(T * per, 0);
  bool derived = false;
  for (const VqBtf::Impl* t : tiles) derived = derived || !t->l3_parent.empty();
  for (std::size_t i = 0; i < tiles.size(); ++i) {
    const VqBtf::Impl& t = *tiles[i];
    const BtfRect& r = rects[i];
    if (t.width != r.width || t.height != r.height)
      throw Error("joinVqTiles: tile '" + t.name + "' has " + std::to_string(t.width) + " x " + std::to_string(t.height) +
                  " texels, its rectangle " + std::to_string(r.width) + " x " + std::to_string(r.height));
    if (!(t.views == first.views) || !(t.layout == first.layout))
      throw Error("joinVqTiles: tile '" + t.name + "' holds other views or directions than tile '" + first.name + "'");
    const std::uint32_t offset = std::uint32_t(m->l3Count());
    if (levels == 3) {
      m->l3_index.insert(m->l3_index.end(), t.l3_index.begin(), t.l3_index.end());
      m->l3_scale.insert(m->l3_scale.end(), t.l3_scale.begin(), t.l3_scale.end());
      if (derived) {
        if (t.l3_parent.empty())
          m->l3_parent.insert(m->l3_parent.end(), t.l3Count(), 0u);
        else
          for (const std::uint32_t p : t.l3_parent) m->l3_parent.push_back(p == 0 ? 0u : p + offset);
      }
    }
    for (int y = 0; y < r.height; ++y)
      for (int x = 0; x < r.width; ++x) {
        const std::size_t from = (std::size_t(y) * std::size_t(r.width) + std::size_t(x)) * per;
        const std::size_t to = ((std::size_t(r.y + y)) * std::size_t(width) + std::size_t(r.x + x)) * per;
        for (std::size_t k = 0; k < per; ++k) {
          m->top_index[to + k] = t.top_index[from + k] + (levels == 3 ? offset : 0u);
          m->top_scale[to + k] = t.top_scale[from + k];
          if (levels == 1) m->top_chroma[to + k] = t.top_chroma[from + k];
        }
      }
  }
  m->prepare("joinVqTiles");
  m->stats.codebook_entries = vqCodebookEntries(*m);
  return m;
}

}  // namespace vq_dataset_detail

using namespace vq_dataset_detail;

VqCodebooks::VqCodebooks(std::shared_ptr<const Impl> impl) : impl_(std::move(impl)) {}

const VqOptions& VqCodebooks::options() const { return impl_->options; }
std::size_t VqCodebooks::groupCount() const { return impl_->groups.size(); }

std::vector<std::size_t> VqCodebooks::entries() const {
  std::vector<std::size_t> sum;
  for (const VqBtf::Impl& g : impl_->groups) {
    const std::vector<std::size_t> e = groupEntries(g);
    sum.resize(e.size(), 0);
    for (std::size_t l = 0; l < e.size(); ++l) sum[l] += e[l];
  }
  return sum;
}

VqCodebooks VqCodebooks::of(const VqDatabase& database) {
  auto impl = std::make_shared<Impl>();
  impl->options = database.options();
  for (const VqBtf& material : database.materials()) {
    const VqBtf::Impl& m = material.impl();
    if (impl->groupOf(m.layout)) continue;
    for (const VqRingBasis& basis : m.l1_basis)
      if (!basis.empty())
        throw Error("material '" + m.name + "' codes level 1 in learned bases (level1_cut): its codebooks cannot be merged with "
                    "another part's");
    VqBtf::Impl g = emptyGroupLike(m);
    copySharedCodebooks(m, g);
    impl->groups.push_back(std::move(g));
  }
  return VqCodebooks(std::move(impl));
}

std::vector<std::byte> VqCodebooks::toBytes() const {
  nlohmann::json header = vqOptionsHeader(impl_->groups.front());
  header["format"] = kVqCodebooksFormat;
  header["format_version"] = kVqCodebooksVersion;
  nlohmann::json groups = nlohmann::json::array();
  std::vector<ContainerSection> sections;
  for (std::size_t g = 0; g < impl_->groups.size(); ++g) {
    nlohmann::json entry{{"codebook_entries", groupEntries(impl_->groups[g])}};
    addVqDirectionsHeader(impl_->groups[g], entry);
    groups.push_back(std::move(entry));
  }
  header["groups"] = std::move(groups);
  addVqHeaderSection(header, sections);
  for (std::size_t g = 0; g < impl_->groups.size(); ++g) addVqSharedSections(impl_->groups[g], sections, codebookGroupPrefix(g));
  ScratchFile file;
  writeContainer(file.path(), sections, kVqTransportZstdLevel);
  return file.bytes();
}

VqCodebooks VqCodebooks::fromBytes(std::span<const std::byte> bytes, const std::string& label) {
  ScratchFile file;
  file.put(bytes);
  try {
    const std::vector<ContainerSection> sections = readContainer(file.path());
    const nlohmann::json header = parseVqHeader(sections, file.path());
    if (header.value("format", std::string()) != kVqCodebooksFormat)
      throw FileError(file.path(), "is not a set of VQ codebooks (format " + header.value("format", std::string("none")) + ")");
    auto impl = std::make_shared<Impl>();
    readVqOptions(header, file.path(), impl->options);
    const auto groups = header.find("groups");
    if (groups == header.end() || !groups->is_array() || groups->empty() || groups->size() > sections.size())
      throw FileError(file.path(), "VQ codebooks header lists no groups, or more than its sections can hold");
    for (std::size_t g = 0; g < groups->size(); ++g) {
      VqBtf::Impl group;
      group.options = impl->options;
      readVqDirectionsHeader(groups->at(g), file.path(), group);
      readVqSharedSections(sections, file.path(), group, codebookGroupPrefix(g));
      if (groupEntries(group) != vqHeaderCounts(groups->at(g), "codebook_entries", file.path()))
        throw FileError(file.path(), "VQ codebooks header's entry counts disagree with group " + std::to_string(g) + "'s sections");
      for (const VqRingBasis& basis : group.l1_basis)
        if (!basis.empty()) throw FileError(file.path(), "VQ codebooks hold a basis-coded ring, which seeds cannot take");
      // Every index within its codebook: a seed's entries are decoded by the compressor as they are.
      for (std::size_t k = 0; k < group.l2_index.size(); ++k) {
        const int r = int(k % group.ringCount());
        if (group.l2_index[k] >= group.l1Count(r) || group.l2_chroma[k] >= group.chromaCount(r))
          throw FileError(file.path(), "VQ codebooks' level-2 entry " + std::to_string(k / group.ringCount()) +
                                           " points outside its level-1 or chromaticity codebook");
      }
      for (int r = 0; r < int(group.ringCount()); ++r)
        if (group.l1Count(r) == 0 || group.chromaCount(r) == 0)
          throw FileError(file.path(), "VQ codebooks' ring " + std::to_string(r) + " has no seed entry");
      if (impl->options.levels >= 2 && group.l2Count() == 0) throw FileError(file.path(), "VQ codebooks' level 2 has no seed entry");
      if (impl->groupOf(group.layout)) throw FileError(file.path(), "VQ codebooks hold two groups of one ring layout");
      impl->groups.push_back(std::move(group));
    }
    return VqCodebooks(std::move(impl));
  } catch (const FileError& e) {
    std::string what = e.what();
    const std::string scratch = file.path().string();
    if (const auto at = what.find(scratch); at != std::string::npos) what.replace(at, scratch.size(), label);
    throw FileError(label, what);
  }
}

VqCodebooks mergeVqCodebooks(std::span<const VqCodebooks> parts, std::span<const std::string> labels) {
  if (parts.empty()) throw Error("merging VQ codebooks needs at least one part");
  auto label = [&](std::size_t p) { return p < labels.size() ? labels[p] : "part " + std::to_string(p + 1); };
  const VqOptions& options = parts.front().options();
  for (std::size_t p = 0; p < parts.size(); ++p)
    if (!sameDatasetOptions(parts[p].options(), options))
      throw Error("cannot merge the codebooks of " + label(p) + " and " + label(0) +
                  ": they were made with other options (the same levels, epsilon, chroma_epsilon and energy_floor in every part)");
  // Per ring layout, in order of first appearance; each part's groups inserted in part order.
  std::vector<CodebookMerger> mergers;
  std::vector<BtfRingLayout> layouts;
  for (const VqCodebooks& part : parts)
    for (const VqBtf::Impl& g : part.impl().groups) {
      std::size_t i = 0;
      while (i < layouts.size() && !(layouts[i] == g.layout)) ++i;
      if (i == layouts.size()) {
        layouts.push_back(g.layout);
        mergers.emplace_back(g);
      }
      mergers[i].insert(g);
    }
  auto impl = std::make_shared<VqCodebooks::Impl>();
  impl->options = options;
  for (CodebookMerger& m : mergers) impl->groups.push_back(std::move(m).result());
  return VqCodebooks(std::move(impl));
}

std::vector<std::byte> vqDatabaseBytes(const VqDatabase& database) {
  std::vector<ContainerSection> sections = vqDatabaseSections(database);
  ScratchFile file;
  writeContainer(file.path(), sections, kVqTransportZstdLevel);
  return file.bytes();
}

VqDatabase vqDatabaseFromBytes(std::span<const std::byte> bytes, const std::string& label) {
  ScratchFile file;
  file.put(bytes);
  try {
    return VqDatabase::read(file.path());
  } catch (const FileError& e) {
    std::string what = e.what();
    const std::string scratch = file.path().string();
    if (const auto at = what.find(scratch); at != std::string::npos) what.replace(at, scratch.size(), label);
    throw FileError(label, what);
  }
}

std::vector<BtfRect> vqTiles(int width, int height, int parts) {
  if (width < 1 || height < 1 || parts < 1) throw Error("vqTiles: the size and the number of parts must be positive");
  parts = int(std::min<long long>(parts, (long long)width * height));
  // rows x columns = parts, rows the largest divisor <= sqrt(parts); along the longer side the more.
  int rows = int(std::sqrt(double(parts)));
  while (parts % rows != 0) --rows;
  int cols = parts / rows;
  if ((width >= height) != (cols >= rows)) std::swap(rows, cols);
  if (cols > width || rows > height) {  // a thin BTF: strips along its long side
    cols = width >= height ? parts : 1;
    rows = parts / cols;
  }
  std::vector<BtfRect> out;
  for (int j = 0; j < rows; ++j)
    for (int i = 0; i < cols; ++i) {
      const int x0 = int((long long)width * i / cols), x1 = int((long long)width * (i + 1) / cols);
      const int y0 = int((long long)height * j / rows), y1 = int((long long)height * (j + 1) / rows);
      out.push_back({x0, y0, x1 - x0, y1 - y0});
    }
  return out;
}

VqDatabase joinVqTiles(const VqDatabase& tiles, std::span<const BtfRect> rects, int width, int height, const std::string& name) {
  if (tiles.size() != rects.size())
    throw Error("joinVqTiles: " + std::to_string(tiles.size()) + " tiles but " + std::to_string(rects.size()) + " rectangles");
  std::vector<const VqBtf::Impl*> impls;
  for (const VqBtf& m : tiles.materials()) impls.push_back(&m.impl());
  std::vector<VqBtf> one;
  one.emplace_back(joinTiles(impls, rects, width, height, name));
  VqDatabase out(std::move(one));
  out.setSeconds(tiles.seconds());
  return out;
}

}  // namespace btf
