// Writer of the `tensor_file` format (layout in btf/io/rgl_tensor.h): the inverse of
// readTensorFile, so that what libbtf writes is read back field for field.
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <set>

#include "btf/core/error.h"
#include "btf/io/atomic_file.h"
#include "btf/io/rgl_tensor.h"

namespace btf {
namespace {

constexpr char kTensorFileMagic[12] = {'t', 'e', 'n', 's', 'o', 'r', '_', 'f', 'i', 'l', 'e', '\0'};
constexpr std::uint64_t kAlignment = 8;

void storeLittle(std::vector<std::byte>& out, std::uint64_t v, int n) {
  for (int i = 0; i < n; ++i) out.push_back(static_cast<std::byte>((v >> (8 * i)) & 0xff));
}

template <class T>
void storeValue(std::vector<std::byte>& out, T v) {
  std::byte raw[sizeof(T)];
  std::memcpy(raw, &v, sizeof(T));
  // Little-endian on disk whatever the host: bytes in significance order.
  if constexpr (std::endian::native == std::endian::big) std::reverse(std::begin(raw), std::end(raw));
  out.insert(out.end(), std::begin(raw), std::end(raw));
}

template <class T>
T integerOf(double v, const TensorField& f) {
  if (!(v == std::floor(v) && v >= double(std::numeric_limits<T>::lowest()) && v <= double(std::numeric_limits<T>::max())))
    throw Error("tensor field '" + f.name + "': " + std::to_string(v) + " is not a " + std::string(dtypeName(f.dtype)) +
                " value");
  return static_cast<T>(v);
}

}  // namespace

TensorField tensorField(std::string name, TensorDtype dtype, std::vector<std::uint64_t> shape,
                        std::span<const double> values) {
  TensorField f;
  f.name = std::move(name);
  f.dtype = dtype;
  f.shape = std::move(shape);
  if (f.elementCount() != values.size())
    throw Error("tensor field '" + f.name + "' " + f.shapeString() + " needs " + std::to_string(f.elementCount()) +
                " values, got " + std::to_string(values.size()));
  f.bytes.reserve(values.size() * dtypeSize(dtype));
  for (const double v : values) {
    switch (dtype) {
      case TensorDtype::UInt8: storeValue(f.bytes, integerOf<std::uint8_t>(v, f)); break;
      case TensorDtype::Int8: storeValue(f.bytes, integerOf<std::int8_t>(v, f)); break;
      case TensorDtype::UInt16: storeValue(f.bytes, integerOf<std::uint16_t>(v, f)); break;
      case TensorDtype::Int16: storeValue(f.bytes, integerOf<std::int16_t>(v, f)); break;
      case TensorDtype::UInt32: storeValue(f.bytes, integerOf<std::uint32_t>(v, f)); break;
      case TensorDtype::Int32: storeValue(f.bytes, integerOf<std::int32_t>(v, f)); break;
      case TensorDtype::UInt64: storeValue(f.bytes, integerOf<std::uint64_t>(v, f)); break;
      case TensorDtype::Int64: storeValue(f.bytes, integerOf<std::int64_t>(v, f)); break;
      case TensorDtype::Float32: storeValue(f.bytes, static_cast<float>(v)); break;
      case TensorDtype::Float64: storeValue(f.bytes, v); break;
      case TensorDtype::Float16: throw Error("tensor field '" + f.name + "': writing f16 is not supported");
    }
  }
  return f;
}

TensorField tensorTextField(std::string name, std::string_view text) {
  TensorField f;
  f.name = std::move(name);
  f.dtype = TensorDtype::UInt8;
  f.shape = {text.size()};
  for (const char c : text) f.bytes.push_back(static_cast<std::byte>(c));
  return f;
}

std::vector<std::byte> encodeTensorFile(const std::vector<TensorField>& fields) {
  std::set<std::string> names;
  std::uint64_t header_size = sizeof kTensorFileMagic + 2 + 4;
  for (const TensorField& f : fields) {
    if (!names.insert(f.name).second) throw Error("tensor field '" + f.name + "' appears twice");
    if (f.name.size() > 0xffff || f.shape.size() > 0xffff) throw Error("tensor field '" + f.name + "': name or rank too long");
    if (f.bytes.size() != f.elementCount() * dtypeSize(f.dtype))
      throw Error("tensor field '" + f.name + "' " + f.shapeString() + " holds " + std::to_string(f.bytes.size()) +
                  " bytes, not " + std::to_string(f.elementCount() * dtypeSize(f.dtype)));
    header_size += 2 + f.name.size() + 2 + 1 + 8 + 8 * f.shape.size();
  }
  auto aligned = [](std::uint64_t n) { return (n + kAlignment - 1) / kAlignment * kAlignment; };
  std::vector<std::byte> out(std::begin(reinterpret_cast<const std::byte(&)[12]>(kTensorFileMagic)),
                             std::end(reinterpret_cast<const std::byte(&)[12]>(kTensorFileMagic)));
  storeLittle(out, 1, 1);
  storeLittle(out, 0, 1);
  storeLittle(out, fields.size(), 4);
  std::uint64_t offset = aligned(header_size);
  for (const TensorField& f : fields) {
    storeLittle(out, f.name.size(), 2);
    for (const char c : f.name) out.push_back(static_cast<std::byte>(c));
    storeLittle(out, f.shape.size(), 2);
    storeLittle(out, static_cast<std::uint64_t>(f.dtype), 1);
    storeLittle(out, offset, 8);
    for (const std::uint64_t extent : f.shape) storeLittle(out, extent, 8);
    offset = aligned(offset + f.bytes.size());
  }
  for (const TensorField& f : fields) {
    out.resize(aligned(out.size()), std::byte{0});
    out.insert(out.end(), f.bytes.begin(), f.bytes.end());
  }
  return out;
}

void writeTensorFile(const std::filesystem::path& path, const std::vector<TensorField>& fields) {
  const std::vector<std::byte> bytes = encodeTensorFile(fields);
  writeFileAtomically(path, [&](std::ofstream& stream) {
    stream.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  });
}

}  // namespace btf
