#include "btf/io/rgl_tensor.h"

#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <set>

#include "btf/core/error.h"

namespace btf {
namespace {

constexpr char kMagic[12] = {'t', 'e', 'n', 's', 'o', 'r', '_', 'f', 'i', 'l', 'e', '\0'};
constexpr std::uint16_t kMaxDims = 16;  // RGL files use at most 5; more is a corrupt header

// Little-endian unsigned integer of n bytes, independent of the host's byte order.
std::uint64_t loadLittle(const std::byte* p, int n) {
  std::uint64_t v = 0;
  for (int i = n - 1; i >= 0; --i) v = (v << 8) | std::to_integer<std::uint64_t>(p[i]);
  return v;
}

float halfToFloat(std::uint16_t h) {
  const int sign = h >> 15, exponent = (h >> 10) & 0x1f, mantissa = h & 0x3ff;
  float magnitude;
  if (exponent == 0) magnitude = std::ldexp(static_cast<float>(mantissa), -24);  // subnormal
  else if (exponent == 31) magnitude = mantissa ? std::numeric_limits<float>::quiet_NaN()
                                                : std::numeric_limits<float>::infinity();
  else magnitude = std::ldexp(static_cast<float>(mantissa | 0x400), exponent - 25);
  return sign ? -magnitude : magnitude;
}

// A cursor over the header bytes that turns running out of bytes into a clear error.
class HeaderReader {
 public:
  HeaderReader(const std::vector<std::byte>& bytes, const std::filesystem::path& path) : bytes_(bytes), path_(path) {}
  std::uint64_t unsignedInt(int n, const std::string& what) {
    need(n, what);
    const std::uint64_t v = loadLittle(bytes_.data() + pos_, n);
    pos_ += n;
    return v;
  }
  std::string text(std::size_t n, const std::string& what) {
    need(n, what);
    std::string s(reinterpret_cast<const char*>(bytes_.data() + pos_), n);
    pos_ += n;
    return s;
  }

 private:
  void need(std::size_t n, const std::string& what) const {
    if (bytes_.size() - pos_ < n)
      throw FileError(path_, "truncated header: " + what + " needs " + std::to_string(n) + " bytes at offset " +
                                 std::to_string(pos_) + " but the file has " + std::to_string(bytes_.size()) +
                                 " bytes");
  }
  const std::vector<std::byte>& bytes_;
  const std::filesystem::path& path_;
  std::size_t pos_ = 0;
};

std::vector<std::byte> readAll(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw FileError(path, "cannot open file for reading");
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  if (size < 0) throw FileError(path, "cannot determine the file size");
  in.seekg(0);
  std::vector<std::byte> bytes(static_cast<std::size_t>(size));
  if (!in.read(reinterpret_cast<char*>(bytes.data()), size)) throw FileError(path, "read error");
  return bytes;
}

template <typename T>
std::vector<T> convertAll(const TensorField& field) {
  const std::size_t n = static_cast<std::size_t>(field.elementCount());
  const std::size_t size = dtypeSize(field.dtype);
  std::vector<T> out(n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::byte* p = field.bytes.data() + i * size;
    const std::uint64_t raw = loadLittle(p, static_cast<int>(size));
    switch (field.dtype) {
      case TensorDtype::UInt8: case TensorDtype::UInt16: case TensorDtype::UInt32: case TensorDtype::UInt64:
        out[i] = static_cast<T>(raw);
        break;
      case TensorDtype::Int8: out[i] = static_cast<T>(static_cast<std::int8_t>(raw)); break;
      case TensorDtype::Int16: out[i] = static_cast<T>(static_cast<std::int16_t>(raw)); break;
      case TensorDtype::Int32: out[i] = static_cast<T>(static_cast<std::int32_t>(raw)); break;
      case TensorDtype::Int64: out[i] = static_cast<T>(static_cast<std::int64_t>(raw)); break;
      case TensorDtype::Float16: out[i] = static_cast<T>(halfToFloat(static_cast<std::uint16_t>(raw))); break;
      case TensorDtype::Float32: {
        const auto bits = static_cast<std::uint32_t>(raw);
        float f;
        std::memcpy(&f, &bits, sizeof f);
        out[i] = static_cast<T>(f);
        break;
      }
      case TensorDtype::Float64: {
        double d;
        std::memcpy(&d, &raw, sizeof d);
        out[i] = static_cast<T>(d);
        break;
      }
    }
  }
  return out;
}

bool isFloating(TensorDtype dtype) {
  return dtype == TensorDtype::Float16 || dtype == TensorDtype::Float32 || dtype == TensorDtype::Float64;
}

}  // namespace

std::string_view dtypeName(TensorDtype dtype) {
  switch (dtype) {
    case TensorDtype::UInt8: return "u8";
    case TensorDtype::Int8: return "i8";
    case TensorDtype::UInt16: return "u16";
    case TensorDtype::Int16: return "i16";
    case TensorDtype::UInt32: return "u32";
    case TensorDtype::Int32: return "i32";
    case TensorDtype::UInt64: return "u64";
    case TensorDtype::Int64: return "i64";
    case TensorDtype::Float16: return "f16";
    case TensorDtype::Float32: return "f32";
    case TensorDtype::Float64: return "f64";
  }
  return "invalid";
}

std::size_t dtypeSize(TensorDtype dtype) {
  switch (dtype) {
    case TensorDtype::UInt8: case TensorDtype::Int8: return 1;
    case TensorDtype::UInt16: case TensorDtype::Int16: case TensorDtype::Float16: return 2;
    case TensorDtype::UInt32: case TensorDtype::Int32: case TensorDtype::Float32: return 4;
    case TensorDtype::UInt64: case TensorDtype::Int64: case TensorDtype::Float64: return 8;
  }
  return 0;
}

std::uint64_t TensorField::elementCount() const {
  std::uint64_t n = 1;
  for (const std::uint64_t extent : shape) n *= extent;  // overflow was excluded when reading
  return n;
}

std::vector<float> TensorField::toFloats() const { return convertAll<float>(*this); }
std::vector<double> TensorField::toDoubles() const { return convertAll<double>(*this); }

std::string TensorField::toText() const {
  if (dtype != TensorDtype::UInt8) return {};
  std::string s(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  // Writers may pad with NULs; they are not part of the text.
  while (!s.empty() && s.back() == '\0') s.pop_back();
  return s;
}

std::string TensorField::shapeString() const {
  std::string s = "(";
  for (std::size_t i = 0; i < shape.size(); ++i) s += (i ? ", " : "") + std::to_string(shape[i]);
  return s + ")";
}

const TensorField* TensorFile::find(std::string_view name) const {
  for (const TensorField& f : fields)
    if (f.name == name) return &f;
  return nullptr;
}

const TensorField& TensorFile::require(std::string_view name, TensorDtype dtype, std::vector<std::int64_t> shape) const {
  const TensorField* f = find(name);
  const std::string label = "field '" + std::string(name) + "'";
  if (!f) throw FileError(path, "missing " + label);
  if (f->dtype != dtype)
    throw FileError(path, label + " has dtype " + std::string(dtypeName(f->dtype)) + ", expected " +
                              std::string(dtypeName(dtype)));
  bool ok = f->shape.size() == shape.size();
  for (std::size_t i = 0; ok && i < shape.size(); ++i)
    ok = shape[i] < 0 || f->shape[i] == static_cast<std::uint64_t>(shape[i]);
  if (!ok) {
    std::string expected = "(";
    for (std::size_t i = 0; i < shape.size(); ++i)
      expected += (i ? ", " : "") + (shape[i] < 0 ? std::string("any") : std::to_string(shape[i]));
    throw FileError(path, label + " has shape " + f->shapeString() + ", expected " + expected + ")");
  }
  return *f;
}

TensorFile readTensorFile(const std::filesystem::path& path) {
  const std::vector<std::byte> bytes = readAll(path);
  TensorFile file;
  file.path = path;
  file.file_size = bytes.size();
  HeaderReader header(bytes, path);

  if (bytes.size() < sizeof kMagic || std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0)
    throw FileError(path, "not a tensor_file (the file does not start with \"tensor_file\\0\")");
  header.text(sizeof kMagic, "magic");
  file.version_major = static_cast<int>(header.unsignedInt(1, "version"));
  file.version_minor = static_cast<int>(header.unsignedInt(1, "version"));
  if (file.version_major != 1 || file.version_minor != 0)
    throw FileError(path, "unsupported tensor_file version " + std::to_string(file.version_major) + "." +
                              std::to_string(file.version_minor) + " (only 1.0 is known)");
  const std::uint64_t field_count = header.unsignedInt(4, "field count");

  std::set<std::string> names;
  for (std::uint64_t k = 0; k < field_count; ++k) {
    const std::string which = "field " + std::to_string(k);
    TensorField field;
    field.name = header.text(header.unsignedInt(2, which + " name length"), which + " name");
    const std::string label = "field '" + field.name + "'";
    if (!names.insert(field.name).second) throw FileError(path, label + " appears twice");
    const auto ndim = static_cast<std::uint16_t>(header.unsignedInt(2, label + " rank"));
    if (ndim > kMaxDims) throw FileError(path, label + " has " + std::to_string(ndim) + " dimensions (corrupt header?)");
    const std::uint64_t code = header.unsignedInt(1, label + " dtype");
    if (code < 1 || code > 11) throw FileError(path, label + " has the unknown dtype code " + std::to_string(code));
    field.dtype = static_cast<TensorDtype>(code);
    field.offset = header.unsignedInt(8, label + " offset");
    std::uint64_t byte_count = dtypeSize(field.dtype);
    for (std::uint16_t d = 0; d < ndim; ++d) {
      const std::uint64_t extent = header.unsignedInt(8, label + " shape");
      field.shape.push_back(extent);
      // Overflow-safe product: any byte count beyond the file size is an error below anyway.
      if (extent != 0 && byte_count > file.file_size / extent) byte_count = file.file_size + 1;
      else byte_count *= extent;
    }
    if (field.offset > file.file_size || byte_count > file.file_size - field.offset)
      throw FileError(path, "truncated: " + label + " " + field.shapeString() + " " +
                                std::string(dtypeName(field.dtype)) + " needs bytes up to offset " +
                                (byte_count > file.file_size ? std::string("beyond the file")
                                                             : std::to_string(field.offset + byte_count)) +
                                " but the file has " + std::to_string(file.file_size) + " bytes");
    const auto begin = bytes.begin() + static_cast<std::ptrdiff_t>(field.offset);
    field.bytes.assign(begin, begin + static_cast<std::ptrdiff_t>(byte_count));
    if (isFloating(field.dtype)) {
      const std::vector<double> values = field.toDoubles();
      for (std::size_t i = 0; i < values.size(); ++i)
        if (!std::isfinite(values[i]))
          throw FileError(path, label + " holds a non-finite value (" + std::to_string(values[i]) + ") at element " +
                                    std::to_string(i));
    }
    file.fields.push_back(std::move(field));
  }
  return file;
}

}  // namespace btf
