#include "support/bonn_btf_bytes.h"

#include <Imath/half.h>

#include <cstring>
#include <fstream>
#include <stdexcept>

namespace btf::test {
namespace {

struct Bytes {
  std::vector<unsigned char> data;
  template <class T>
  void put(T v) {
    unsigned char raw[sizeof v];
    std::memcpy(raw, &v, sizeof v);
    data.insert(data.end(), raw, raw + sizeof v);
  }
  void text(const std::string& s, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) data.push_back(i < s.size() ? static_cast<unsigned char>(s[i]) : 0);
  }
  void scalar(double v, int bytes) {
    if (bytes == 2) put(Imath::half(float(v)).bits());
    else if (bytes == 4) put(float(v));
    else if (bytes == 8) put(v);
    else data.insert(data.end(), std::size_t(bytes), 0);  // an invalid size: bytes of nothing
  }
};

void putFactorData(Bytes& b, const BonnFactorBytes& f, bool pvf) {
  for (const double s : f.sigma) b.scalar(s, f.scalar_bytes);
  if (pvf)
    for (const double m : f.mean) b.scalar(m, f.scalar_bytes);
  for (const double x : f.u) b.scalar(x, f.scalar_bytes);
  for (const double x : f.sv) b.scalar(x, f.scalar_bytes);
}

}  // namespace

std::vector<unsigned char> bonnFileBytes(const BonnFileSpec& s, BonnFileOffsets* offsets) {
  BonnFileOffsets o;
  Bytes b;
  b.text(s.signature, s.signature.size());
  const bool pvf = s.signature.rfind("!PVF", 0) == 0;
  const auto sampling = [&] {
    o.sampling = b.data.size();
    b.put<std::uint32_t>(std::uint32_t(s.views.size()));
    for (std::size_t v = 0; v < s.views.size(); ++v) {
      b.put(s.views[v].theta_rad);
      b.put(s.views[v].phi_rad);
      b.put<std::uint32_t>(std::uint32_t(s.lights[v].size()));
      for (const BonnAngles& l : s.lights[v]) {
        b.put(l.theta_rad);
        b.put(l.phi_rad);
      }
    }
  };
  if (pvf && s.legacy_pvf) {
    o.meta = b.data.size();
    b.put<std::int32_t>(301074);
    b.put<std::uint32_t>(s.factors.empty() ? 0 : s.factors[0].components);
    b.put(s.width);
    b.put(s.height);
    b.put<std::uint32_t>(std::uint32_t(s.factors.size()));
    sampling();
    o.size = o.rotations = o.layout = b.data.size();
  } else {
    o.meta = b.data.size();
    Bytes meta;
    meta.put(s.meta_version);
    meta.text("set-up", 80);
    meta.text("sensor", 80);
    meta.text("light", 80);
    meta.put(float(100));
    for (int c = 0; c < 3; ++c) meta.put(float(1));
    if (s.meta_version > 1) meta.put<std::uint32_t>(s.cosine_flag ? 1 : 0);
    if (s.meta_version > 2) {
      meta.put<std::uint32_t>(std::uint32_t(s.xml.size()));
      meta.text(s.xml, s.xml.size());
    }
    if (s.meta_version > 3) {
      meta.put<std::uint32_t>(std::uint32_t(s.channel_names.size()));
      for (const std::string& name : s.channel_names) {
        meta.put<std::uint32_t>(std::uint32_t(name.size()));
        meta.text(name, name.size());
      }
    }
    b.put<std::uint32_t>(std::uint32_t(meta.data.size() + 4));
    b.data.insert(b.data.end(), meta.data.begin(), meta.data.end());
    sampling();
    o.size = b.data.size();
    b.put(s.width);
    b.put(s.height);
    o.rotations = b.data.size();
    if (s.signature.back() == 'R') {
      b.put(s.rotations);
      for (std::uint32_t r = 0; r < s.rotations; ++r)
        for (int i = 0; i < 9; ++i) b.put(float(i % 4 == 0 ? 1 : 0));
    }
    o.layout = b.data.size();
  }
  if (s.signature.rfind("!DFMF", 0) == 0) {
    std::uint32_t most = 0;
    for (const BonnFactorBytes& f : s.factors) most = std::max(most, f.components);
    b.put(most);
    b.put(s.color_model);
    for (const float m : s.color_mean) b.put(m);
    for (const float t : s.color_transform) b.put(t);
    o.first_factor = b.data.size();
    for (const BonnFactorBytes& f : s.factors) {
      b.put<std::uint8_t>(std::uint8_t(f.scalar_bytes));
      b.put(f.components);
      b.put(f.rows);
      b.put(f.columns);
      putFactorData(b, f, false);
    }
  } else if (s.signature.rfind("!FMF", 0) == 0) {
    if (s.signature == "!FMF12FCER") {
      b.put<std::uint8_t>(std::uint8_t(s.fmf_header_version));
      if (s.fmf_header_version >= 1) b.put(s.dynamic_range_reduction);
      if (s.fmf_header_version >= 2) {
        b.put(s.height_map_width);
        b.put(s.height_map_height);
        for (std::uint32_t i = 0; i < s.height_map_width * s.height_map_height; ++i) b.put(Imath::half(0.5f).bits());
      }
    }
    const BonnFactorBytes& f = s.factors.at(0);
    b.put(f.components);
    o.first_factor = b.data.size();
    b.put<std::uint8_t>(std::uint8_t(f.scalar_bytes));
    b.put(f.components);
    b.put(f.rows);
    b.put(f.columns);
    putFactorData(b, f, false);
  } else {
    if (!s.legacy_pvf) {
      b.put<std::uint32_t>(s.factors.empty() ? 0 : s.factors[0].components);
      b.put<std::uint32_t>(std::uint32_t(s.factors.size()));
    }
    o.first_factor = b.data.size();
    for (const BonnFactorBytes& f : s.factors) {
      b.put<std::uint8_t>(std::uint8_t(f.scalar_bytes));
      b.put(f.components);
      b.put(f.columns);  // weights
      b.put(f.rows);     // dimension
      putFactorData(b, f, true);
    }
  }
  o.end = b.data.size();
  if (offsets) *offsets = o;
  return b.data;
}

void writeBytes(const std::filesystem::path& path, const std::vector<unsigned char>& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
  if (!out) throw std::runtime_error("cannot write " + path.string());
}

}  // namespace btf::test
