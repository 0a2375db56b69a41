// compressVq: the multi-level VQ compressor (compress/vq_btf.h states the tolerances and bounds).
//
// Order of work. Views are compressed one at a time (the source streams by view; the next view
// loads meanwhile). Inside a view, the chromaticity of each ring and level 1 of each ring of more
// than one light run as independent jobs (each has its own codebook; eleven on the 81-direction
// set's six rings), then level 2 over all texels' light slices; level 3 runs at the end over the
// texels (their level-2 codes per view are kept, ~6 bytes each plus 4 per ring).
//
// Determinism with parallel search. Each batch (one ring of one view, the slices of one view, the
// texels at level 3) is cut into chunks of kChunk vectors in texel order. A chunk is first searched
// in parallel against the codebook as it stood before the chunk (a frozen snapshot: searches are
// const), then walked sequentially in texel order: a vector without a reusable snapshot entry is
// compared with the entries the chunk has added so far (a linear scan of at most kChunk entries)
// and, failing that, becomes a new entry; then the chunk's new entries are indexed (codebook.h).
// Scales and errors are then computed in parallel. Every decision depends only on the data and the
// chunk order, never on the threads or on how the jobs interleave.
// Cost. Snapshot searches below level 3 are approximate (at most kMaxVisits kd-tree nodes per
// segment, codebook.h), so a search costs about the same whatever the codebook size, and compression time
// grows about linearly with the texel count (exact searches grow linearly with the codebook, which
// keeps a large share of a synthetic BTF's vectors: quadratic in all). An
// approximate search may miss a reusable entry, which costs an extra entry, never accuracy: every
// entry it returns is verified by the rules below.
//
// Reuse rules (least-squares error <= the tolerance of vq_btf.h at each level, Codebook's radius
// search with the radius of that vector's relative tolerance):
// - level 1: the nearest entry the search finds within the chord radius on unit directions
//   (exactly the tolerance, codebook.h);
// - chromaticity (per ring, alongside level 1): the key is the ring's chroma function (R/Y, B/Y
//   per azimuth), normalized; candidates are the 8 nearest within a generous chord radius
//   (4 chroma_epsilon sqrt(n) / |c|), verified exactly by the luminance-weighted error of vq_btf.h;
// - level 2: the key is the level-1 reconstruction of the slice, normalized; the first of the 8
//   nearest entries within the radius whose chromaticities pass (vq_btf.h) is reused;
// - level 3: the key is the texel's view scales (normalized). Since |a e - b e'| >= |a - b| for
//   unit e, e', an entry whose full reconstruction is within epsilon has a key within about the
//   same radius; candidates (8 nearest within 1.5x the radius) are verified on the full
//   views x lights reconstruction through the level-2 entries' dot products, and on the texel's
//   chromaticity as a whole (vq_btf.h). (The texel's mean chromaticity appended to the key, so
//   that the 8 candidates are not texels of another ink, saved few level-3 entries on the printed
//   BTF: left out, docs/design-notes.md#vq-level-3-search.)
// Rings without light (all zero) skip the chromaticity check: their colour is never seen.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>
#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>

#include "btf/compress/codebook.h"
#include "btf/compress/vq_database.h"
#include "btf/core/error.h"
#include "btf/core/progress.h"
#include "vq_codebooks.h"
#include "vq_impl.h"
#include "vq_prune.h"
#include "vq_sections.h"

namespace btf {

std::uint64_t vqCompressedBytes(const VqBtf::Impl& impl);  // vq_io.cpp

namespace {

constexpr std::uint32_t kNoChroma = std::numeric_limits<std::uint32_t>::max();
constexpr std::size_t kCandidates = 8;
// Level 3's derived entries (Compressor::nearestWithExceptions): the candidates examined. More
// candidates in a wider radius did not pay for their cost on the calibrated print
// (docs/design-notes.md#vq-derived-level-3-entries).
constexpr std::size_t kExceptionCandidates = 32;

// The first of up to max_matches codebook entries within radius of query (nearest first) that
// passes(entry index) accepts, or -1. The candidate list is per thread: searches run in parallel.
template <class Passes>
std::int64_t firstPassing(const Codebook& book, std::span<const float> query, float radius, std::size_t max_matches,
                          const Codebook::SearchOptions& options, Passes passes) {
  thread_local std::vector<Codebook::Match> found;
  book.search(query, radius, max_matches, found, options);
  for (const auto& m : found)
    if (passes(m.index)) return m.index;
  return -1;
}

// Per vector of a batch: 0 (entry 0, any entry will do) where it is dark, -1 (to be quantized) elsewhere.
template <class Lit>
std::vector<std::int64_t> initialMatches(std::size_t count, Lit lit) {
  std::vector<std::int64_t> match(count, -1);
  for (std::size_t t = 0; t < count; ++t)
    if (!lit(t)) match[t] = 0;
  return match;
}
// Vectors per chunk: the sequential part scans up to this many new entries per unmatched vector,
// the parallel part wants enough work per chunk to keep the threads busy.
constexpr std::size_t kChunk = 128;
// Node visits per kd-tree segment in snapshot searches (codebook.h). A bound trades a few extra
// entries (a missed reuse costs an entry, never accuracy) for searches whose cost does not grow with
// the codebook; a tighter one saves little more search time for more entries. `btf bench
// compression` measures entries and time.
constexpr int kMaxVisits = 16;

template <class F>
void parallelFor(std::size_t n, F&& f) {
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 256), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i) f(i);
  });
}

// The chunked snapshot-then-sequential quantization of one batch (see the top). match[t] >= 0 on
// entry marks vectors already decided (e.g. zero ones). find(t, options) returns the reusable entry
// the codebook search with `options` finds for vector t, or -1; create(t) adds vector t's entry to
// `book` and returns its index. Snapshot searches visit at most max_visits kd-tree nodes per
// segment (0: exact).
template <class Find, class Create>
void quantizeBatch(Codebook& book, std::vector<std::int64_t>& match, Find&& find, Create&& create,
                   int max_visits = kMaxVisits) {
  const std::size_t n = match.size();
  for (std::size_t begin = 0; begin < n; begin += kChunk) {
    const std::size_t end = std::min(n, begin + kChunk);
    const std::uint32_t chunk_first = std::uint32_t(book.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(begin, end, 16), [&](const tbb::blocked_range<std::size_t>& r) {
      for (std::size_t t = r.begin(); t != r.end(); ++t)
        if (match[t] < 0) match[t] = find(t, Codebook::SearchOptions{0, max_visits});
    });
    for (std::size_t t = begin; t < end; ++t) {
      if (match[t] >= 0) continue;
      if (book.size() > chunk_first) match[t] = find(t, Codebook::SearchOptions{chunk_first, 0});
      if (match[t] < 0) match[t] = create(t);
    }
    book.index();
  }
}

float norm(const float* v, int n) {
  double s = 0;
  for (int k = 0; k < n; ++k) s += double(v[k]) * v[k];
  return float(std::sqrt(s));
}
double dot(const float* a, const float* b, int n) {
  double s = 0;
  for (int k = 0; k < n; ++k) s += double(a[k]) * b[k];
  return s;
}

// RMS of norms, summed in index order (deterministic).
template <class F>
double rmsOf(std::size_t n, F&& norm_of) {
  double s = 0;
  for (std::size_t i = 0; i < n; ++i) s += double(norm_of(i)) * norm_of(i);
  return n ? std::sqrt(s / double(n)) : 0.0;
}

// Compresses materials one after another into shared level-1, chromaticity and level-2 codebooks
// (`books`), each material's level-3 codebook and top stream into its own Impl. One material alone
// is a plain VqBtf (books and material are then the same Impl: they write disjoint fields).
class Compressor {
 public:
  // `bases`: the level-1 ring bases (vqRingBasesFor), empty for value-by-value rings.
  // `books.layout` is the materials' ring layout (all the same: the codebooks are per ring).
  // `seed`: shared codebooks to start from (compress/vq_dataset.h), of books.layout and these
  // options, value-by-value rings; their entries are reused under the same rules as any other and
  // their entry 0 of each codebook is the seed below. Null: the codebooks start from the seeds alone.
  Compressor(const VqOptions& options, VqBtf::Impl& books, std::vector<VqRingBasis> bases,
             const VqBtf::Impl* seed = nullptr)
      : options_(options),
        precision_(vqPrecisionFor(options.epsilon, books.layout.maxSize())),
        books_(books),
        layout_(books.layout),
        R_(std::size_t(layout_.ringCount())),
        L_(std::size_t(layout_.lightCount())) {
    level1_entry_.resize(R_);
    ring_rms_.resize(R_);
    for (int r = 0; r < int(R_); ++r) {
      jobs_.push_back({r, true});
      if (layout_.size(r) > 1) jobs_.push_back({r, false});
    }
    std::stable_sort(jobs_.begin(), jobs_.end(),
                     [&](const RingJob& a, const RingJob& b) { return layout_.size(a.ring) > layout_.size(b.ring); });
    for (int r = 0; r < int(R_); ++r) {
      l1_.emplace_back(layout_.size(r));
      if (std::size_t(r) < bases.size()) books_.l1_basis[std::size_t(r)] = std::move(bases[std::size_t(r)]);
    }
    if (seed) {
      startFrom(*seed);
      return;
    }
    // Seeds, so that zero data always has an entry: the constant function of each ring, grey, the
    // uniform light slice (level 2) and, per material, the uniform texel (level 3).
    for (int r = 0; r < int(R_); ++r) {
      const std::vector<float> constant(std::size_t(layout_.size(r)), 1.0f / std::sqrt(float(layout_.size(r))));
      l1_[std::size_t(r)].add(storeLevel1Entry(r, constant, 0.0, 0));
    }
    const float step = vqChromaStep(options.chroma_epsilon);
    const std::int32_t grey = std::int32_t(std::lround(1.0 / double(step)));
    for (int r = 0; r < int(R_); ++r) {
      const std::size_t n2 = 2 * std::size_t(layout_.size(r));
      chroma_books_.emplace_back(int(n2));
      books_.chroma[std::size_t(r)].assign(n2, grey);
      chroma_books_.back().add(std::vector<float>(n2, float(grey) * step));
    }
    if (options.levels >= 2) {
      std::vector<std::uint32_t> e1(R_, 0), ch(R_, 0);
      std::vector<std::uint16_t> sc(R_);
      for (int r = 0; r < int(R_); ++r)
        sc[std::size_t(r)] = encodeVqScale(std::sqrt(float(layout_.size(r)) / float(L_)));
      l2_.emplace(int(L_));
      addLevel2Entry(e1.data(), sc.data(), ch.data());
    }
  }

  // The codebooks hold `seed`'s entries, in its order, as if they had been made here: stored codes
  // copied, the search trees over their decoded values (level 2 over its reconstructions).
  void startFrom(const VqBtf::Impl& seed) {
    books_.l1 = seed.l1;
    books_.chroma = seed.chroma;
    books_.l2_index = seed.l2_index;
    books_.l2_scale = seed.l2_scale;
    books_.l2_chroma = seed.l2_chroma;
    const float step = vqChromaStep(options_.chroma_epsilon);
    for (int r = 0; r < int(R_); ++r) {
      const std::size_t n = std::size_t(layout_.size(r));
      std::vector<float> values(n), chroma(2 * n);
      for (std::size_t e = 0; e < seed.l1Count(r); ++e) {
        for (std::size_t a = 0; a < n; ++a) values[a] = decodeVqEntryValue(seed.l1[std::size_t(r)][e * n + a]);
        l1_[std::size_t(r)].add(values);
      }
      chroma_books_.emplace_back(int(2 * n));
      for (std::size_t c = 0; c < seed.chromaCount(r); ++c) {
        for (std::size_t i = 0; i < 2 * n; ++i) chroma[i] = float(seed.chroma[std::size_t(r)][c * 2 * n + i]) * step;
        chroma_books_.back().add(chroma);
      }
      l1_[std::size_t(r)].index();
      chroma_books_.back().index();
    }
    if (options_.levels >= 2) {
      l2_.emplace(int(L_));
      std::vector<float> recon(L_);
      for (std::size_t e = 0; e < seed.l2Count(); ++e) {
        reconstructSlice(&seed.l2_index[e * R_], &seed.l2_scale[e * R_], recon.data());
        l2_norm2_.push_back(float(dot(recon.data(), recon.data(), int(L_))));
        l2_->add(recon);
      }
      l2_->index();
    }
  }

  // Adds one material: its vectors reuse (and extend) the codebooks of the materials before it.
  void run(const BtfSource& source, VqBtf::Impl& out) {
    source_ = &source;
    out_ = &out;
    texels_ = source.texelCount();
    views_ = std::size_t(source.views().count());
    if (options_.levels == 3) {
      l3_.emplace(int(views_));
      l3_norm2_.clear();
      std::vector<std::uint32_t> e(views_, 0);
      // At the stored precision: derived entries (vq_impl.h) may copy its codes.
      std::vector<std::uint16_t> sc(views_, encodeVqScale(1.0f / std::sqrt(float(views_)), precision_.scale_shift));
      addLevel3Entry(e.data(), sc.data());
    }
    const std::size_t T = texels_, V = views_;
    if (options_.levels == 1) {
      out_->top_index.resize(T * V * R_);
      out_->top_scale.resize(out_->top_index.size());
      out_->top_chroma.resize(out_->top_index.size());
    } else if (options_.levels == 2) {
      out_->top_index.resize(T * V);
      out_->top_scale.resize(T * V);
    } else {
      view_index_.resize(T * V);
      view_scale_.resize(T * V);
      view_chroma_.resize(T * V * R_);
    }
    Progress progress("vq compress " + source_->name(), int(V) + (options_.levels == 3 ? 1 : 0));
    // The next view loads (a synthetic source renders it) while this one is compressed; one
    // loadView at a time, so sources need not be thread-safe beyond running on a worker thread.
    // Per-view streams are indexed by the view's slot in the source's view set.
    const BtfViewSet& views = source_->views();
    std::vector<Rgb> buffer, next;
    source_->loadView(views.view(0), buffer);
    tbb::task_group loader;
    for (int slot = 0; slot < int(V); ++slot) {
      const int v = views.view(slot);
      if (buffer.size() != T * L_)
        throw Error(source_->name() + ": view " + std::to_string(v) + " has the wrong number of values");
      checkValues(buffer, v);
      if (slot + 1 < int(V)) loader.run([this, &views, slot, &next] { source_->loadView(views.view(slot + 1), next); });
      level1(buffer, slot);
      if (options_.levels >= 2) level2(slot);
      loader.wait();
      std::swap(buffer, next);
      progress.advance();
    }
    if (options_.levels == 3) {
      level3();
      progress.advance();
    }
  }

 private:
  // ---- input checks and colour -------------------------------------------------------------
  void checkValues(const std::vector<Rgb>& buffer, int v) const {
    std::size_t first_bad = buffer.size();
    for (std::size_t i = 0; i < buffer.size(); ++i) {
      const Rgb& c = buffer[i];
      if (!c.isFinite() || c.minComponent() < 0.0f) {
        first_bad = i;
        break;
      }
    }
    if (first_bad == buffer.size()) return;
    const std::size_t light = first_bad / texels_, t = first_bad % texels_;
    throw Error(source_->name() + ": view " + std::to_string(v) + ", light " + std::to_string(light) + ", texel (" +
                std::to_string(t % std::size_t(source_->width())) + ", " + std::to_string(t / std::size_t(source_->width())) +
                ") holds a negative, infinite or NaN value");
  }
  // Luminance-weighted squared chroma error of ring r's chroma entry `entry` against texel t's own
  // chroma function (current view): sum over azimuths of u_a^2 |c_entry,a - c_a|^2 with u the
  // ring's unit luminance function (vq_btf.h).
  bool chromaPasses(std::uint32_t entry, std::size_t t, int r) const {
    const int n = layout_.size(r), start = layout_.start(r);
    const float* e = chroma_books_[std::size_t(r)].entry(entry);
    const float* c = &cfun_[(t * L_ + std::size_t(start)) * 2];
    const float* u = &units_[t * L_ + std::size_t(start)];
    double err = 0;
    for (int a = 0; a < 2 * n; ++a) {
      const double d = double(e[a]) - c[a], w = u[a / 2];
      err += w * w * d * d;
    }
    const double ce = chromaTolerance(t, r);
    return err <= ce * ce;
  }
  // The chroma tolerance of texel t's ring r in the current view: chroma_epsilon, widened for
  // dark rings by the same energy floor as the luminance (vq_btf.h): a ring far below the view's
  // RMS ring norm adds little to the RGB error whatever its chromaticity.
  double chromaTolerance(std::size_t t, int r) const {
    const double len = norms_[t * R_ + std::size_t(r)];
    const double floor = double(options_.energy_floor) * ring_rms_[std::size_t(r)];
    return double(options_.chroma_epsilon) * (len >= floor || !(len > 0) ? 1.0 : floor / len);
  }
  // Chroma entries of ring r for all texels of the view (lit rings; unlit ones take entry 0), in
  // the same snapshot-then-sequential order as level 1.
  void quantizeChroma(int r) {
    const std::size_t T = texels_;
    const int n = layout_.size(r), start = layout_.start(r);
    const std::size_t n2 = 2 * std::size_t(n);
    Codebook& book = chroma_books_[std::size_t(r)];
    const float step = vqChromaStep(options_.chroma_epsilon);
    std::vector<float> keys(T * n2);
    std::vector<float> radius(T);
    parallelFor(T, [&](std::size_t t) {
      const float* c = &cfun_[(t * L_ + std::size_t(start)) * 2];
      const float len = norm(c, int(n2));
      for (std::size_t i = 0; i < n2; ++i) keys[t * n2 + i] = len > 0 ? c[i] / len : 0.0f;
      radius[t] = Codebook::chordRadius(len > 0 ? float(std::min(1.0, 4.0 * chromaTolerance(t, r) * std::sqrt(double(n)) / len)) : 1.0f);
    });
    auto key = [&](std::size_t t) { return std::span<const float>(&keys[t * n2], n2); };
    auto lit = [&](std::size_t t) { return norms_[t * R_ + std::size_t(r)] > 0; };
    std::vector<std::int64_t> match = initialMatches(T, lit);
    std::vector<float> entry(n2);
    quantizeBatch(
        book, match,
        [&](std::size_t t, const Codebook::SearchOptions& options) {
          return firstPassing(book, key(t), radius[t], kCandidates, options,
                              [&](std::uint32_t e) { return chromaPasses(e, t, r); });
        },
        [&](std::size_t t) -> std::int64_t {
          const float* c = &cfun_[(t * L_ + std::size_t(start)) * 2];
          for (std::size_t i = 0; i < n2; ++i) {
            const std::int32_t q = std::int32_t(std::lround(double(c[i]) / step));
            books_.chroma[std::size_t(r)].push_back(q);
            entry[i] = float(q) * step;
          }
          return book.add(entry);
        });
    for (std::size_t t = 0; t < T; ++t) chroma_[t * R_ + std::size_t(r)] = std::uint32_t(match[t]);
  }

  // Relative tolerance for a vector of norm `len` in a batch of RMS norm `rms` (vq_btf.h).
  float tolerance(double len, double rms) const {
    const double floor = double(options_.energy_floor) * rms;
    return float(std::min(1.0, double(options_.epsilon) * (len >= floor ? 1.0 : floor / len)));
  }
  float radiusFor(double len, double rms) const { return Codebook::chordRadius(tolerance(len, rms)); }

  // ---- level 1 -------------------------------------------------------------------------------
  void level1(const std::vector<Rgb>& buffer, int slot) {
    const std::size_t T = texels_;
    // Luminance functions (unit directions and norms) and chroma functions, in parallel.
    units_.resize(T * L_);
    norms_.resize(T * R_);
    cfun_.resize(T * L_ * 2);
    parallelFor(T, [&](std::size_t t) {
      for (int r = 0; r < int(R_); ++r) {
        const int n = layout_.size(r), start = layout_.start(r);
        float* f = &units_[t * L_ + std::size_t(start)];
        double sr = 0, sb = 0, sy = 0;
        for (int a = 0; a < n; ++a) {
          const Rgb& c = buffer[std::size_t(layout_.light(r, a)) * T + t];
          f[a] = c.luminance();
          sr += c.r;
          sb += c.b;
          sy += f[a];
        }
        const float len = norm(f, n);
        norms_[t * R_ + std::size_t(r)] = len;
        for (int a = 0; a < n; ++a) f[a] = len > 0 ? f[a] / len : 0.0f;
        // Chroma per azimuth; where the luminance is zero (weight zero) the ring's mean.
        const bool lit = sy > 0;
        const float mr = lit ? float(sr / sy) : 1.0f, mb = lit ? float(sb / sy) : 1.0f;
        float* c = &cfun_[(t * L_ + std::size_t(start)) * 2];
        for (int a = 0; a < n; ++a) {
          const Rgb& rgb = buffer[std::size_t(layout_.light(r, a)) * T + t];
          const float y = rgb.luminance();
          c[2 * a] = y > 0 ? rgb.r / y : mr;
          c[2 * a + 1] = y > 0 ? rgb.b / y : mb;
        }
      }
    });
    for (int r = 0; r < int(R_); ++r)
      ring_rms_[std::size_t(r)] = rmsOf(T, [&](std::size_t t) { return norms_[t * R_ + std::size_t(r)]; });
    chroma_.resize(T * R_);
    entries_.assign(T * R_, 0);
    scales_.assign(T * R_, 0);
    // A ring of one light has one unit function, the seed {1}: its code is its norm.
    for (int r = 0; r < int(R_); ++r)
      if (layout_.size(r) == 1)
        for (std::size_t t = 0; t < T; ++t)
          scales_[t * R_ + std::size_t(r)] = encodeVqScale(norms_[t * R_ + std::size_t(r)], precision_.scale_shift);
    // The chroma codebooks of the rings and the level-1 codebooks of the rings of more than one
    // light are independent (each job reads the view and writes only its own codebook and ring
    // slots): they run as parallel jobs, each deterministic on its own, so their sequential parts
    // overlap. Largest rings first.
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, jobs_.size(), 1),
        [&](const tbb::blocked_range<std::size_t>& range) {
          for (std::size_t j = range.begin(); j != range.end(); ++j) {
            if (jobs_[j].chroma)
              quantizeChroma(jobs_[j].ring);
            else
              quantizeLevel1(jobs_[j].ring);
          }
        },
        tbb::simple_partitioner());
    if (options_.levels == 1) {
      const std::size_t base = std::size_t(slot) * R_;
      parallelFor(T, [&](std::size_t t) {
        for (int r = 0; r < int(R_); ++r) {
          const std::size_t k = t * R_ + std::size_t(r);
          const std::size_t o = t * views_ * R_ + base + std::size_t(r);
          out_->top_index[o] = entries_[k];
          out_->top_scale[o] = scales_[k];
          out_->top_chroma[o] = chroma_[k];
        }
      });
    }
  }

  // Appends a level-1 entry for the unit function u of ring r to the stored codebook and returns
  // the values the file will decode: u itself rounded to multiples of 2^value_shift, or, in a
  // basis-coded ring, the reconstruction of its leading coefficients (dropping a tail of energy
  // <= budget^2; the basis's step stands for the shift). The values live in ring r's buffer, which
  // the ring's next call reuses: a ring's entries are created one at a time (quantizeBatch's
  // sequential pass), while the rings run as parallel jobs.
  std::span<const float> storeLevel1Entry(int r, std::span<const float> u, double budget, int value_shift) {
    const std::size_t n = u.size();
    const VqRingBasis& basis = books_.l1_basis[std::size_t(r)];
    std::vector<std::uint16_t>& codes = books_.l1[std::size_t(r)];
    const std::size_t first = codes.size();
    codes.resize(first + n);
    if (basis.empty()) {
      for (std::size_t a = 0; a < n; ++a) codes[first + a] = encodeVqEntryValue(u[a], value_shift);
    } else {
      std::vector<std::int32_t>& coefficients = books_.l1_coef[std::size_t(r)];
      coefficients.resize(first + n);
      vqBasisCoefficients(basis, u, budget, &coefficients[first]);
      vqBasisCodes(basis, &coefficients[first], &codes[first]);
    }
    std::vector<float>& entry = level1_entry_[std::size_t(r)];
    entry.resize(n);
    for (std::size_t a = 0; a < n; ++a) entry[a] = decodeVqEntryValue(codes[first + a]);
    return entry;
  }

  // Level-1 codes of ring r >= 1 for all texels of the view.
  void quantizeLevel1(int r) {
    const std::size_t T = texels_;
    const int n = layout_.size(r), start = layout_.start(r);
    Codebook& book = l1_[std::size_t(r)];
    auto unit = [&](std::size_t t) { return std::span<const float>(&units_[t * L_ + std::size_t(start)], std::size_t(n)); };
    auto lit = [&](std::size_t t) { return norms_[t * R_ + std::size_t(r)] > 0; };
    const double rms = ring_rms_[std::size_t(r)];
    auto radius = [&](std::size_t t) { return radiusFor(norms_[t * R_ + std::size_t(r)], rms); };
    std::vector<std::int64_t> match = initialMatches(T, lit);
    quantizeBatch(
        book, match,
        [&](std::size_t t, const Codebook::SearchOptions& options) {
          return firstPassing(book, unit(t), radius(t), 1, options, [](std::uint32_t) { return true; });
        },
        [&](std::size_t t) -> std::int64_t {
          // A basis-coded entry (level1_cut) may drop coefficients worth its tolerance less the
          // quantization share (vq_basis.h), so that with the rounding it stays within the tolerance.
          const double budget = std::max(0.0, double(tolerance(norms_[t * R_ + std::size_t(r)], rms)) -
                                                  kVqQuantizationShare * double(options_.epsilon));
          return book.add(storeLevel1Entry(r, unit(t), budget, precision_.value_shift));
        });
    parallelFor(T, [&](std::size_t t) {
      const std::size_t k = t * R_ + std::size_t(r);
      entries_[k] = std::uint32_t(match[t]);
      if (!lit(t)) return;
      const float* e = book.entry(std::size_t(match[t]));
      const double ee = dot(e, e, n);
      const double fe = norms_[k] * dot(unit(t).data(), e, n);
      scales_[k] = ee > 0 ? encodeVqScale(float(fe / ee), precision_.scale_shift) : 0;
    });
  }

  // ---- level 2 -------------------------------------------------------------------------------
  // Reconstruction of a light slice from level-1 codes (one value per light).
  void reconstructSlice(const std::uint32_t* e1, const std::uint16_t* sc, float* out, const float* rel = nullptr) const {
    for (int r = 0; r < int(R_); ++r) {
      const int n = layout_.size(r), start = layout_.start(r);
      const float s = rel ? rel[r] : decodeVqScale(sc[r]);
      const float* e = l1_[std::size_t(r)].entry(e1[r]);
      for (int a = 0; a < n; ++a) out[start + a] = s * e[a];
    }
  }
  std::uint32_t addLevel2Entry(const std::uint32_t* e1, const std::uint16_t* sc, const std::uint32_t* ch) {
    std::vector<float> recon(L_);
    reconstructSlice(e1, sc, recon.data());
    books_.l2_index.insert(books_.l2_index.end(), e1, e1 + R_);
    books_.l2_scale.insert(books_.l2_scale.end(), sc, sc + R_);
    books_.l2_chroma.insert(books_.l2_chroma.end(), ch, ch + R_);
    l2_norm2_.push_back(float(dot(recon.data(), recon.data(), int(L_))));
    return l2_->add(recon);
  }
  bool level2ChromaPasses(std::uint32_t entry, std::size_t t) const {
    for (int r = 0; r < int(R_); ++r) {
      const std::size_t k = t * R_ + std::size_t(r);
      if (!(norms_[k] > 0)) continue;
      const std::uint32_t c = books_.l2_chroma[std::size_t(entry) * R_ + std::size_t(r)];
      if (c != chroma_[k] && !chromaPasses(c, t, r)) return false;
    }
    return true;
  }

  void level2(int slot) {
    const std::size_t T = texels_;
    slices_.resize(T * L_);
    slice_norm_.resize(T);
    parallelFor(T, [&](std::size_t t) {
      float* y = &slices_[t * L_];
      reconstructSlice(&entries_[t * R_], &scales_[t * R_], y);
      const float len = norm(y, int(L_));
      slice_norm_[t] = len;
      for (std::size_t l = 0; l < L_; ++l) y[l] = len > 0 ? y[l] / len : 0.0f;
    });
    auto unit = [&](std::size_t t) { return std::span<const float>(&slices_[t * L_], L_); };
    const double rms = rmsOf(T, [&](std::size_t t) { return slice_norm_[t]; });
    auto radius = [&](std::size_t t) { return radiusFor(slice_norm_[t], rms); };
    std::vector<std::int64_t> match = initialMatches(T, [&](std::size_t t) { return slice_norm_[t] > 0; });
    quantizeBatch(
        *l2_, match,
        [&](std::size_t t, const Codebook::SearchOptions& options) {
          return firstPassing(*l2_, unit(t), radius(t), kCandidates, options,
                              [&](std::uint32_t e) { return level2ChromaPasses(e, t); });
        },
        [&](std::size_t t) -> std::int64_t {
          std::vector<std::uint16_t> rel(R_);
          for (int r = 0; r < int(R_); ++r)
            rel[r] = encodeVqScale(decodeVqScale(scales_[t * R_ + std::size_t(r)]) / slice_norm_[t],
                                   precision_.scale_shift);
          return addLevel2Entry(&entries_[t * R_], rel.data(), &chroma_[t * R_]);
        });
    parallelFor(T, [&](std::size_t t) {
      const std::uint32_t e = std::uint32_t(match[t]);
      std::uint16_t code = 0;
      if (slice_norm_[t] > 0) {
        const float* recon = l2_->entry(e);
        const double ls = slice_norm_[t] * dot(unit(t).data(), recon, int(L_)) / l2_norm2_[e];
        code = encodeVqScale(float(ls), precision_.scale_shift);
      }
      const std::size_t k = t * views_ + std::size_t(slot);
      if (options_.levels == 2) {
        out_->top_index[k] = e;
        out_->top_scale[k] = code;
      } else {
        view_index_[k] = e;
        view_scale_[k] = code;
        for (int r = 0; r < int(R_); ++r)
          view_chroma_[k * R_ + std::size_t(r)] =
              norms_[t * R_ + std::size_t(r)] > 0 ? chroma_[t * R_ + std::size_t(r)] : kNoChroma;
      }
    });
  }

  // ---- level 3 -------------------------------------------------------------------------------
  // `parent`: the entry this one repeats outside its exception views (vq_impl.h), or none.
  std::uint32_t addLevel3Entry(const std::uint32_t* e2, const std::uint16_t* sc, std::optional<std::uint32_t> parent = {}) {
    std::vector<float> key(views_);
    double y2 = 0;
    for (std::size_t v = 0; v < views_; ++v) {
      key[v] = decodeVqScale(sc[v]);
      y2 += double(key[v]) * key[v] * l2_norm2_[e2[v]];
    }
    out_->l3_index.insert(out_->l3_index.end(), e2, e2 + views_);
    out_->l3_scale.insert(out_->l3_scale.end(), sc, sc + views_);
    out_->l3_parent.push_back(parent ? *parent + 1 : 0);
    l3_norm2_.push_back(float(y2));
    return l3_->add(key);
  }
  // x . y of texel t's level-2 reconstruction x against entry `entry`'s reconstruction y
  // (unscaled); nothing when their chromaticities differ by more than the tolerance. The chroma
  // test is over the whole texel, as the luminance one is (vq_btf.h): the luminance-weighted
  // squared error sum_l Y_l^2 |c'_l - c_l|^2 over its views x lights samples, with Y from x and c from
  // its own chroma entries (each verified against the data at level 1 or 2; the data is gone by
  // level 3), <= chroma_epsilon^2 max(|x|^2, (energy_floor R)^2), R the RMS texel norm. On noisy
  // data a test per ring and view could not pass: a single light's chroma noise (ring 0) alone
  // exceeds the tolerance, so every texel of a camera-noise BTF was its own level-3 entry.
  std::optional<double> level3Dot(std::size_t t, std::uint32_t entry) const {
    double xy = 0, chroma_err = 0;
    const float* q = l3_->entry(entry);
    for (std::size_t v = 0; v < views_; ++v) {
      const std::size_t k = t * views_ + v;
      const float s = decodeVqScale(view_scale_[k]);
      const std::uint32_t a = view_index_[k], b = out_->l3_index[std::size_t(entry) * views_ + v];
      chroma_err += level3ViewChromaError(k, s, a, b);
      if (s == 0 || q[v] == 0) continue;
      xy += double(s) * q[v] * level2Dot(a, b);
    }
    if (chroma_err > level3ChromaTolerance2(t)) return std::nullopt;
    return xy;
  }
  // Dot product of level-2 entries a and b (unscaled).
  double level2Dot(std::uint32_t a, std::uint32_t b) const {
    return a == b ? double(l2_norm2_[a]) : dot(l2_->entry(a), l2_->entry(b), int(L_));
  }
  // The chroma term of level3Dot for one view: slot k = t * views_ + v of texel t, whose slice has
  // level-2 entry a at scale s, against level-2 entry b.
  double level3ViewChromaError(std::size_t k, float s, std::uint32_t a, std::uint32_t b) const {
    double err = 0;
    if (s > 0)
      for (int r = 0; r < int(R_); ++r) {
        const std::uint32_t own = view_chroma_[k * R_ + std::size_t(r)];
        const std::uint32_t c = books_.l2_chroma[std::size_t(b) * R_ + std::size_t(r)];
        // The slice's own level-2 entry's chroma passed level 2's test against the data.
        if (own != kNoChroma && c != own && c != books_.l2_chroma[std::size_t(a) * R_ + std::size_t(r)])
          err += double(s) * s * level3ChromaError(c, own, a, r);
      }
    return err;
  }
  double level3ChromaTolerance2(std::size_t t) const {
    const double floor = double(options_.energy_floor) * texel_rms_;
    return double(options_.chroma_epsilon) * options_.chroma_epsilon * std::max(texel_norm2_[t], floor * floor);
  }
  // sum_a y_a^2 |e_a - o_a|^2 over ring r's lights: chroma entries `entry` and `own` weighted by
  // the luminance y of level-2 entry a (unscaled).
  double level3ChromaError(std::uint32_t entry, std::uint32_t own, std::uint32_t a, int r) const {
    const int n = layout_.size(r), start = layout_.start(r);
    const float* y = l2_->entry(a) + start;
    const float* e = chroma_books_[std::size_t(r)].entry(entry);
    const float* o = chroma_books_[std::size_t(r)].entry(own);
    double err = 0;
    for (int i = 0; i < 2 * n; ++i) {
      const double d = double(e[i]) - o[i], w = y[i / 2];
      err += w * w * d * d;
    }
    return err;
  }
  // The fewest views of entry `entry` to replace with texel t's own codes so that the rest passes
  // level 3's tests for t (the tests of level3Passes, restricted to the views kept): greedily, the
  // view whose error uses the most of the tolerances first, refitting the texel's scale after each.
  // Its own codes reconstruct a replaced view as level 2 left it, so it adds no level-3 error.
  struct Level3Exceptions {
    std::vector<std::uint32_t> views;  // slots, ascending
    double scale = 0;                  // the texel's scale on the kept views
  };
  std::optional<Level3Exceptions> level3Exceptions(std::size_t t, std::uint32_t entry, std::size_t max_views) const {
    const std::size_t V = views_;
    std::vector<double> x2(V), y2(V), xy(V), chroma(V);
    const float* q = l3_->entry(entry);
    for (std::size_t v = 0; v < V; ++v) {
      const std::size_t k = t * V + v;
      const double s = decodeVqScale(view_scale_[k]);
      const std::uint32_t a = view_index_[k], b = out_->l3_index[std::size_t(entry) * V + v];
      x2[v] = s * s * l2_norm2_[a];
      y2[v] = double(q[v]) * q[v] * l2_norm2_[b];
      xy[v] = s == 0 || q[v] == 0 ? 0.0 : s * q[v] * level2Dot(a, b);
      chroma[v] = level3ViewChromaError(k, float(s), a, b);
    }
    const double texel2 = texel_norm2_[t];
    const double tol = tolerance(std::sqrt(texel2), texel_rms_);
    const double lum_tol2 = tol * tol * texel2;
    const double chroma_tol2 = level3ChromaTolerance2(t);
    if (!(lum_tol2 > 0) || !(chroma_tol2 > 0)) return std::nullopt;
    std::vector<bool> kept(V, true);
    Level3Exceptions out;
    for (;;) {
      double sx2 = 0, sy2 = 0, sxy = 0, sch = 0;
      for (std::size_t v = 0; v < V; ++v)
        if (kept[v]) sx2 += x2[v], sy2 += y2[v], sxy += xy[v], sch += chroma[v];
      const double c = sy2 > 0 ? sxy / sy2 : 0.0;
      if (c > 0 && sx2 - sxy * c <= lum_tol2 && sch <= chroma_tol2) {
        std::sort(out.views.begin(), out.views.end());
        out.scale = c;
        return out;
      }
      if (out.views.size() == max_views) return std::nullopt;
      std::size_t worst = V;
      double worst_share = -1;
      for (std::size_t v = 0; v < V; ++v) {
        if (!kept[v]) continue;
        const double share = std::max(0.0, x2[v] - 2 * c * xy[v] + c * c * y2[v]) / lum_tol2 + chroma[v] / chroma_tol2;
        if (share > worst_share) worst_share = share, worst = v;
      }
      if (worst == V) return std::nullopt;
      kept[worst] = false;
      out.views.push_back(std::uint32_t(worst));
    }
  }
  bool level3Passes(std::size_t t, std::uint32_t entry) const {
    const auto xy = level3Dot(t, entry);
    if (!xy) return false;
    const double x2 = texel_norm2_[t], y2 = l3_norm2_[entry];
    if (!(y2 > 0) || *xy <= 0) return false;
    const double err2 = 1.0 - (*xy * *xy) / (x2 * y2);
    const double tol = tolerance(std::sqrt(x2), texel_rms_);
    return err2 <= tol * tol;
  }

  // For a texel no entry passes (with VqOptions::level3_exceptions): the entry among the
  // kExceptionCandidates nearest (within twice the search radius) that passes with the fewest
  // exception views, at most kVqMaxExceptionShare of them (vq_impl.h), and those views. An entry that then needs none was
  // missed by the narrower search. A derived entry stores its exceptions alone (vq_io.cpp), a few
  // bytes each against a whole row of views.
  std::optional<std::pair<std::uint32_t, Level3Exceptions>> nearestWithExceptions(std::size_t t, std::span<const float> key,
                                                                                   float radius) const {
    if (!options_.level3_exceptions) return std::nullopt;
    thread_local std::vector<Codebook::Match> found;
    l3_->search(key, std::min(2.0f * radius, 1.415f), kExceptionCandidates, found, Codebook::SearchOptions{0, 0});
    const std::size_t max_views = std::size_t(std::floor(kVqMaxExceptionShare * double(views_)));
    std::optional<std::pair<std::uint32_t, Level3Exceptions>> best;
    for (const auto& m : found) {
      if (best && best->second.views.empty()) break;
      // Only an entry with fewer exceptions than the best so far is worth its evaluation.
      const std::size_t limit = best ? best->second.views.size() - 1 : max_views;
      if (auto e = level3Exceptions(t, m.index, limit)) best.emplace(m.index, std::move(*e));
    }
    return best;
  }
  // Texel t's entry: `parent`'s row with the exception views replaced by the texel's own codes,
  // their scales relative to the texel's scale on the kept views.
  std::uint32_t addLevel3Exception(std::size_t t, std::uint32_t parent, const Level3Exceptions& ex) {
    const std::size_t V = views_;
    std::vector<std::uint32_t> e2(&out_->l3_index[std::size_t(parent) * V], &out_->l3_index[std::size_t(parent) * V] + V);
    std::vector<std::uint16_t> sc(&out_->l3_scale[std::size_t(parent) * V], &out_->l3_scale[std::size_t(parent) * V] + V);
    for (const std::uint32_t v : ex.views) {
      e2[v] = view_index_[t * V + v];
      sc[v] = encodeVqScale(float(double(decodeVqScale(view_scale_[t * V + v])) / ex.scale), precision_.scale_shift);
    }
    return addLevel3Entry(e2.data(), sc.data(), parent);
  }

  void level3() {
    const std::size_t T = texels_;
    out_->top_index.assign(T, 0);
    out_->top_scale.assign(T, 0);
    texel_norm2_.resize(T);
    const std::size_t V = views_;
    std::vector<float> keys(T * V);
    parallelFor(T, [&](std::size_t t) {
      double x2 = 0, s2 = 0;
      for (std::size_t v = 0; v < V; ++v) {
        const std::size_t k = t * V + v;
        const double s = decodeVqScale(view_scale_[k]);
        x2 += s * s * l2_norm2_[view_index_[k]];
        s2 += s * s;
      }
      texel_norm2_[t] = x2;
      const double inv = s2 > 0 ? 1.0 / std::sqrt(s2) : 0.0;
      for (std::size_t v = 0; v < V; ++v) keys[t * V + v] = float(decodeVqScale(view_scale_[t * V + v]) * inv);
    });
    auto key = [&](std::size_t t) { return std::span<const float>(&keys[t * V], V); };
    texel_rms_ = rmsOf(T, [&](std::size_t t) { return std::sqrt(texel_norm2_[t]); });
    auto radius = [&](std::size_t t) { return std::min(1.5f * radiusFor(std::sqrt(texel_norm2_[t]), texel_rms_), 1.415f); };
    std::vector<std::int64_t> match = initialMatches(T, [&](std::size_t t) { return texel_norm2_[t] > 0; });
    quantizeBatch(
        *l3_, match,
        [&](std::size_t t, const Codebook::SearchOptions& options) {
          return firstPassing(*l3_, key(t), radius(t), kCandidates, options,
                              [&](std::uint32_t e) { return level3Passes(t, e); });
        },
        [&](std::size_t t) -> std::int64_t {
          if (const auto near = nearestWithExceptions(t, key(t), radius(t))) {
            if (near->second.views.empty()) return near->first;
            return addLevel3Exception(t, near->first, near->second);
          }
          std::vector<std::uint16_t> rel(V);
          for (std::size_t v = 0; v < V; ++v) rel[v] = encodeVqScale(key(t)[v], precision_.scale_shift);
          return addLevel3Entry(&view_index_[t * V], rel.data());
        },
        // Exact: the bounded search missed reusable texels on the calibrated print
        // (docs/design-notes.md#vq-level-3-search). Its cost grows as texels x entries, quadratic
        // where the bounded one is linear, but at the sizes of measured BTFs it is a small part of
        // the whole compression. Far larger BTFs would want a bound of a few hundred visits.
        0);
    parallelFor(T, [&](std::size_t t) {
      const std::uint32_t e = std::uint32_t(match[t]);
      out_->top_index[t] = e;
      if (!(texel_norm2_[t] > 0)) return;
      const auto xy = level3Dot(t, e);
      const double y2 = l3_norm2_[e];
      out_->top_scale[t] = xy && y2 > 0 ? encodeVqScale(float(*xy / y2), precision_.scale_shift) : 0;
    });
  }

  const VqOptions& options_;
  const VqPrecision precision_;
  VqBtf::Impl& books_;              // shared codebooks: level 1, chromaticity, level 2
  const BtfRingLayout& layout_;     // books_'s
  const std::size_t R_, L_;         // rings and lights
  // Level 1's parallel jobs per view: each ring's chroma and, for rings of more than one light,
  // its level-1 codebook; largest rings first.
  struct RingJob {
    int ring;
    bool chroma;
  };
  std::vector<RingJob> jobs_;
  const BtfSource* source_ = nullptr;  // the material being compressed
  VqBtf::Impl* out_ = nullptr;         // its level-3 codebook and top stream
  std::size_t texels_ = 0;
  std::size_t views_ = 0;  // held by the source; per-view streams are indexed by slot (btf_view_set.h)
  std::vector<Codebook> l1_;
  std::vector<std::vector<float>> level1_entry_;  // storeLevel1Entry's result, per ring
  std::optional<Codebook> l2_, l3_;
  std::vector<float> l2_norm2_, l3_norm2_;
  std::vector<Codebook> chroma_books_;  // per ring, decoded chroma functions (2 n values)
  // Per view (level 1 -> level 2).
  std::vector<float> units_, norms_, slices_, slice_norm_, cfun_;
  std::vector<double> ring_rms_;  // RMS of each ring's luminance norms over the texels
  std::vector<std::uint32_t> chroma_, entries_;
  std::vector<std::uint16_t> scales_;
  // Per (texel, view) for level 3.
  std::vector<std::uint32_t> view_index_, view_chroma_;
  std::vector<std::uint16_t> view_scale_;
  std::vector<double> texel_norm2_;
  double texel_rms_ = 0;
};

}  // namespace

namespace {

void checkVqOptions(const VqOptions& options) {
  if (!(options.epsilon >= 0.0f) || !(options.epsilon < 1.0f))
    throw Error("VQ tolerance epsilon = " + std::to_string(options.epsilon) + " is invalid: must be in [0, 1)");
  if (!(options.chroma_epsilon >= kVqMinChromaEpsilon) || !(options.chroma_epsilon <= 1.0f))
    throw Error("VQ chroma_epsilon = " + std::to_string(options.chroma_epsilon) + " is invalid: must be in [" +
                std::to_string(kVqMinChromaEpsilon) + ", 1]");
  if (options.levels < 1 || options.levels > 3)
    throw Error("VQ levels = " + std::to_string(options.levels) + " is invalid: must be 1, 2 or 3");
  if (!(options.energy_floor >= 0.0f) || !std::isfinite(options.energy_floor))
    throw Error("VQ energy_floor = " + std::to_string(options.energy_floor) + " is invalid: must be finite and >= 0");
  if (options.threads < 0) throw Error("VQ threads = " + std::to_string(options.threads) + " is invalid: must be >= 0");
}

template <class F>
void inArena(int threads, F&& work) {
  if (threads > 0) {
    tbb::task_arena arena(threads);
    arena.execute(work);
  } else {
    work();
  }
}

std::shared_ptr<VqBtf::Impl> materialImpl(const BtfSource& source, const VqOptions& options, std::string name) {
  auto impl = std::make_shared<VqBtf::Impl>();
  impl->setLayout(BtfRingLayout::of(source.directions(), "VQ compression of " + source.name()));
  impl->width = source.width();
  impl->height = source.height();
  impl->name = std::move(name);
  impl->views = source.views();
  impl->options = options;
  return impl;
}

// The level-1 ring bases (vq_basis.h), learned from the source's first view: only with
// level1_cut, and none at epsilon 0, where every value is kept as it is. `layout`: the source's
// (materialImpl derived it).
std::vector<VqRingBasis> vqRingBasesFor(const BtfSource& source, const BtfRingLayout& layout, const VqOptions& options) {
  if (!options.level1_cut || !(options.epsilon > 0.0f)) return {};
  std::vector<Rgb> view;
  source.loadView(source.views().view(0), view);
  if (view.size() != source.texelCount() * std::size_t(layout.lightCount()))
    throw Error(source.name() + ": view " + std::to_string(source.views().view(0)) + " has the wrong number of values");
  const int value_shift = vqPrecisionFor(options.epsilon, layout.maxSize()).value_shift;
  return learnVqRingBases(view, source.texelCount(), layout, float(std::exp2(value_shift) / 65535.0));
}

}  // namespace

VqBtf compressVq(const BtfSource& source, const VqOptions& options) {
  checkVqOptions(options);
  const auto start = std::chrono::steady_clock::now();
  auto impl = materialImpl(source, options, source.name() + " (vq)");
  inArena(options.threads, [&] { Compressor(options, *impl, vqRingBasesFor(source, impl->layout, options)).run(source, *impl); });
  VqBtf::Impl* const material = impl.get();
  pruneVqCodebooks(*impl, std::span(&material, 1));
  impl->prepare("compressVq");
  VqStats& stats = impl->stats;
  stats.codebook_entries = vqCodebookEntries(*impl);
  stats.compressed_bytes = vqCompressedBytes(*impl);
  stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const double raw = double(source.entryCount()) * 3.0;
  stats.ratio_u8 = raw / double(stats.compressed_bytes);
  stats.ratio_f32 = 4.0 * stats.ratio_u8;
  return VqBtf(impl);
}

namespace {

// compressVqDatabase, its shared codebooks starting from `seed`'s group of each layout when given
// (compress/vq_dataset.h).
VqDatabase compressVqDatabaseFrom(std::span<const BtfSource* const> sources, const std::vector<std::string>& names,
                                  const VqOptions& options, const VqCodebooks::Impl* seed) {
  checkVqOptions(options);
  if (sources.empty()) throw Error("a VQ database needs at least one material");
  if (names.size() != sources.size())
    throw Error("a VQ database needs one name per material (" + std::to_string(sources.size()) + " materials, " +
                std::to_string(names.size()) + " names)");
  const auto start = std::chrono::steady_clock::now();
  std::vector<std::shared_ptr<VqBtf::Impl>> impls;
  for (std::size_t i = 0; i < sources.size(); ++i) impls.push_back(materialImpl(*sources[i], options, names[i]));
  // The codebooks are per ring: one group of shared codebooks per ring layout, materials of a
  // layout compressed in their order into it (sets that differ only where lights were moved aside
  // share a layout). Groups in order of their first material.
  std::vector<std::size_t> group_of(sources.size());
  std::vector<std::size_t> group_first;
  for (std::size_t i = 0; i < sources.size(); ++i) {
    std::size_t g = 0;
    while (g < group_first.size() && impls[group_first[g]]->layout != impls[i]->layout) ++g;
    if (g == group_first.size()) group_first.push_back(i);
    group_of[i] = g;
  }
  for (std::size_t g = 0; g < group_first.size(); ++g) {
    VqBtf::Impl books;
    books.options = options;
    books.setLayout(impls[group_first[g]]->layout);
    inArena(options.threads, [&] {
      const VqBtf::Impl* seed_group = seed ? seed->groupOf(books.layout) : nullptr;
      Compressor compressor(options, books,
                            seed_group ? std::vector<VqRingBasis>{}
                                       : vqRingBasesFor(*sources[group_first[g]], books.layout, options),
                            seed_group);
      for (std::size_t i = 0; i < sources.size(); ++i)
        if (group_of[i] == g) compressor.run(*sources[i], *impls[i]);
    });
    std::vector<VqBtf::Impl*> pointers;
    for (std::size_t i = 0; i < sources.size(); ++i)
      if (group_of[i] == g) pointers.push_back(impls[i].get());
    pruneVqCodebooks(books, pointers);
    for (VqBtf::Impl* impl : pointers) {
      impl->l1 = books.l1;
      impl->l1_basis = books.l1_basis;
      impl->l1_coef = books.l1_coef;
      impl->chroma = books.chroma;
      impl->l2_index = books.l2_index;
      impl->l2_scale = books.l2_scale;
      impl->l2_chroma = books.l2_chroma;
    }
  }
  std::vector<VqBtf> materials;
  for (auto& impl : impls) {
    impl->prepare("compressVqDatabase");
    impl->stats.codebook_entries = vqCodebookEntries(*impl);
    materials.emplace_back(impl);
  }
  VqDatabase database(std::move(materials));
  database.setSeconds(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  return database;
}

}  // namespace

VqDatabase compressVqDatabase(std::span<const BtfSource* const> sources, const std::vector<std::string>& names,
                              const VqOptions& options) {
  return compressVqDatabaseFrom(sources, names, options, nullptr);
}

VqDatabase compressVqDatabase(std::span<const BtfSource* const> sources, const std::vector<std::string>& names,
                              const VqOptions& options, const VqCodebooks& seed) {
  const VqOptions& s = seed.options();
  if (s.levels != options.levels || s.epsilon != options.epsilon || s.chroma_epsilon != options.chroma_epsilon ||
      s.energy_floor != options.energy_floor)
    throw Error("the seed codebooks were made with other options (levels " + std::to_string(s.levels) + ", epsilon " +
                std::to_string(s.epsilon) + ", chroma_epsilon " + std::to_string(s.chroma_epsilon) + ", energy_floor " +
                std::to_string(s.energy_floor) + ") than this compression's");
  if (options.level1_cut)
    throw Error("compression from seed codebooks does not take level1_cut (each part would learn its own level-1 bases)");
  return compressVqDatabaseFrom(sources, names, options, &seed.impl());
}

double vqLuminanceBound(const VqOptions& o) {
  const double e = double(o.epsilon) * std::sqrt(1.0 + double(o.energy_floor) * o.energy_floor);
  // The stored rounding (vq_impl.h): within kVqQuantizationShare epsilon, and never finer than half
  // the finest 16-bit log2 scale step, 2^(1 / 2048) - 1.
  const double q = std::max(kVqQuantizationShare * double(o.epsilon), std::exp2(1.0 / 2048.0) - 1.0);
  return std::pow(1.0 + e + 2.0 * q, o.levels) - 1.0;
}

}  // namespace btf
