// writeVqRuntimeFile: the decoded tables of VqBtf::Impl (vq_impl.h, built by prepare()) copied as
// they are into the runtime file's sections, so that the runtime walks the same numbers with the
// same arithmetic (runtime/src/vq_codec.cpp) and needs no decoding of its own.
#include "btf/compress/vq_runtime_export.h"

#include <bit>
#include <cstring>
#include <vector>

#include "btf/core/btf_directions.h"
#include "btf/core/error.h"
#include "btf/io/atomic_file.h"
#include "btf_runtime/file_layout.h"
#include "vq_impl.h"

namespace btf {

static_assert(std::endian::native == std::endian::little, "the runtime file is little-endian: written as the host's bytes");

namespace {

struct SectionBytes {
  std::vector<unsigned char> bytes;
  template <class T>
  static SectionBytes of(const std::vector<T>& v) {
    SectionBytes s;
    s.bytes.resize(v.size() * sizeof(T));
    if (!v.empty()) std::memcpy(s.bytes.data(), v.data(), s.bytes.size());
    return s;
  }
};

}  // namespace

void writeVqRuntimeFile(const VqBtf& vq, const std::filesystem::path& path) {
  namespace rf = btfrt::file;
  const VqBtf::Impl& m = vq.impl();
  const std::string what = "runtime export of " + (m.name.empty() ? std::string("the BTF") : m.name);
  if (!m.views.directions().indexedAsUbo2003())
    throw Error(what + ": the runtime evaluates BTFs on the 81-direction set only; this one is on " +
                m.views.directions().describe());
  const int view_rings = m.views.completeRingsFromPole();
  if (view_rings == 0 || m.views.count() != btfRingStart(view_rings - 1) + btfRingSize(view_rings - 1))
    throw Error(what + ": the runtime needs the views of whole rings from the pole; the BTF holds " + m.views.describe());
  if (m.layout.ringCount() != kBtfRingCount) throw Error(what + ": " + m.layout.describe() + " is not the 81-direction set's rings");
  for (int r = 0; r < kBtfRingCount; ++r) {
    if (m.layout.size(r) != btfRingSize(r)) throw Error(what + ": " + m.layout.describe() + " is not the 81-direction set's rings");
    for (int a = 0; a < btfRingSize(r); ++a)
      if (m.layout.light(r, a) != btfRingStart(r) + a)
        throw Error(what + ": " + m.layout.describe() + " orders its lights unlike the 81-direction set");
  }

  std::vector<std::int32_t> view_slot(kBtfDirectionCount, -1);
  for (int v = 0; v < kBtfDirectionCount; ++v)
    if (m.views.contains(v)) view_slot[std::size_t(v)] = m.views.slot(v);
  std::vector<rf::Ring> rings(kBtfRingCount);
  std::vector<float> l1_cdf, l1_sum;
  for (int r = 0; r < kBtfRingCount; ++r) {
    const VqBtf::Impl::LightAddress& first = m.lights[std::size_t(btfRingStart(r))];
    rings[std::size_t(r)] = {std::uint32_t(btfRingSize(r)), std::uint32_t(btfRingStart(r)), first.l1,
                             std::uint32_t(m.l1Count(r)), first.chroma, std::uint32_t(m.chromaCount(r)),
                             std::uint32_t(l1_cdf.size()), std::uint32_t(l1_sum.size())};
    l1_cdf.insert(l1_cdf.end(), m.l1_cdf[std::size_t(r)].begin(), m.l1_cdf[std::size_t(r)].end());
    l1_sum.insert(l1_sum.end(), m.l1_sum[std::size_t(r)].begin(), m.l1_sum[std::size_t(r)].end());
  }
  std::vector<rf::Light> lights(m.lights.size());
  for (std::size_t l = 0; l < lights.size(); ++l) lights[l] = {m.lights[l].l1, m.lights[l].chroma, m.lights[l].ring, m.lights[l].size};
  auto ringCodes = [](const std::vector<VqBtf::Impl::RingCode>& codes) {
    std::vector<rf::RingCode> out(codes.size());
    for (std::size_t i = 0; i < codes.size(); ++i) out[i] = {codes[i].entry, codes[i].scale, codes[i].chroma};
    return out;
  };
  auto sliceCodes = [](const std::vector<VqBtf::Impl::ScaledIndex>& codes) {
    std::vector<rf::SliceCode> out(codes.size());
    for (std::size_t i = 0; i < codes.size(); ++i) out[i] = {codes[i].entry, codes[i].scale};
    return out;
  };
  // Level 3 in the form prepare() built: packed (entry, scale code), or (entry, float scale).
  std::vector<rf::SliceCode> l3;
  std::vector<rf::PackedCode> l3_packed(m.l3_packed.size());
  for (std::size_t k = 0; k < l3_packed.size(); ++k) l3_packed[k] = {m.l3_packed[k].entry, m.l3_packed[k].scale};
  if (m.options.levels == 3 && l3_packed.empty()) l3 = sliceCodes(m.l3_codes);
  const std::vector<float> fractions(kVqScaleFractions.begin(), kVqScaleFractions.end());

  std::vector<SectionBytes> sections(rf::kVqSectionCount);
  sections[rf::kViewSlot] = SectionBytes::of(view_slot);
  sections[rf::kRings] = SectionBytes::of(rings);
  sections[rf::kLights] = SectionBytes::of(lights);
  sections[rf::kL1Values] = SectionBytes::of(m.l1_flat);
  sections[rf::kChroma] = SectionBytes::of(m.chroma_flat);
  sections[rf::kL1Cdf] = SectionBytes::of(l1_cdf);
  sections[rf::kL1Sum] = SectionBytes::of(l1_sum);
  sections[rf::kL2Codes] = SectionBytes::of(ringCodes(m.l2_codes));
  sections[rf::kL3Codes] = SectionBytes::of(l3);
  sections[rf::kL3Packed] = SectionBytes::of(l3_packed);
  sections[rf::kScaleFractions] = SectionBytes::of(fractions);
  sections[rf::kTopCodes] = SectionBytes::of(sliceCodes(m.top_codes));
  sections[rf::kTopRingCodes] = SectionBytes::of(ringCodes(m.top_ring_codes));

  std::vector<rf::Section> table(sections.size());
  std::uint64_t offset = rf::kHeaderBytes + sizeof(rf::Section) * table.size();
  auto align = [](std::uint64_t o) { return (o + rf::kSectionAlignment - 1) / rf::kSectionAlignment * rf::kSectionAlignment; };
  for (std::size_t s = 0; s < sections.size(); ++s) {
    offset = align(offset);
    table[s] = {offset, sections[s].bytes.size()};
    offset += sections[s].bytes.size();
  }
  rf::Header header{};
  std::memcpy(header.magic, rf::kMagic, sizeof header.magic);
  header.version = rf::kVersion;
  header.codec = rf::kCodecVq;
  header.width = std::uint32_t(m.width);
  header.height = std::uint32_t(m.height);
  header.levels = std::uint32_t(m.options.levels);
  header.view_count = std::uint32_t(m.views.count());
  header.view_rings = std::uint32_t(view_rings);
  header.ring_count = std::uint32_t(kBtfRingCount);
  header.light_count = std::uint32_t(kBtfDirectionCount);
  header.chroma_step = m.chroma_step;
  header.section_count = std::uint32_t(table.size());
  header.file_bytes = offset;

  std::vector<unsigned char> bytes(offset, 0);
  std::memcpy(bytes.data(), &header, sizeof header);
  std::memcpy(bytes.data() + rf::kHeaderBytes, table.data(), table.size() * sizeof(rf::Section));
  for (std::size_t s = 0; s < sections.size(); ++s)
    if (!sections[s].bytes.empty()) std::memcpy(bytes.data() + table[s].offset, sections[s].bytes.data(), sections[s].bytes.size());
  writeFileAtomically(path, [&](std::ofstream& out) {
    out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
  });
}

}  // namespace btf
