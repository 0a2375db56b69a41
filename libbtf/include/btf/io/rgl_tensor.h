// Reader and writer of the `tensor_file` format of Mitsuba and the RGL measured-material database
// (Dupuy & Jakob 2018): a small header naming typed n-dimensional arrays ("fields") stored in the
// same file. Layout, little-endian:
//   char[12] "tensor_file\0", u8 major, u8 minor (1.0 is the only version), u32 field count,
//   then per field: u16 name length, name bytes, u16 ndim, u8 dtype, u64 data offset,
//   u64 shape[ndim]; the field's elements follow at its offset, row-major (last index fastest).
// dtype codes: 1 u8, 2 i8, 3 u16, 4 i16, 5 u32, 6 i32, 7 u64, 8 i64, 9 f16, 10 f32, 11 f64.
//
// Every field is read and checked: known dtype, shape without overflow, data inside the file,
// unique names, and floating-point values finite (a NaN in measured data is a corrupt file, not a
// value to render). Problems throw btf::FileError naming the file, the field and the problem.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace btf {

enum class TensorDtype : std::uint8_t {
  UInt8 = 1, Int8, UInt16, Int16, UInt32, Int32, UInt64, Int64, Float16, Float32, Float64
};

// "u8", "i8", ..., "f16", "f32", "f64".
std::string_view dtypeName(TensorDtype dtype);
std::size_t dtypeSize(TensorDtype dtype);

struct TensorField {
  std::string name;
  TensorDtype dtype = TensorDtype::UInt8;
  std::uint64_t offset = 0;            // of the data in the file
  std::vector<std::uint64_t> shape;    // row-major, last index fastest
  std::vector<std::byte> bytes;        // the raw little-endian elements

  std::uint64_t elementCount() const;
  // All elements converted (any dtype; f16 exactly, 64-bit integers rounded to the nearest float).
  std::vector<float> toFloats() const;
  std::vector<double> toDoubles() const;
  // A u8 field as text (e.g. `description`); empty for other dtypes.
  std::string toText() const;
  // "(1, 8, 32, 32)"
  std::string shapeString() const;
};

struct TensorFile {
  std::filesystem::path path;
  int version_major = 1, version_minor = 0;
  std::uint64_t file_size = 0;
  std::vector<TensorField> fields;  // in file order

  const TensorField* find(std::string_view name) const;
  // The field, checked to have this dtype and shape; -1 in `shape` accepts any extent. Throws
  // FileError("<path>: field 'rgb' ...") when it is missing or differs.
  const TensorField& require(std::string_view name, TensorDtype dtype, std::vector<std::int64_t> shape) const;
};

TensorFile readTensorFile(const std::filesystem::path& path);

// A field of the given dtype and shape from values (converted to the dtype: f32 rounds, u8 and u32
// must be integers in range). Throws btf::Error when the values do not fill the shape.
TensorField tensorField(std::string name, TensorDtype dtype, std::vector<std::uint64_t> shape,
                        std::span<const double> values);
// A u8 field of rank 1 holding `text` (e.g. `description`).
TensorField tensorTextField(std::string name, std::string_view text);

// The bytes of a tensor_file 1.0 holding `fields` in this order: the header, then each field's
// data at the next multiple of 8 bytes, as the files of the RGL database are laid out. Throws
// btf::Error for duplicate names or a field whose bytes do not match its dtype and shape.
std::vector<std::byte> encodeTensorFile(const std::vector<TensorField>& fields);
// encodeTensorFile written atomically (a temporary file renamed into place; FileError names `path`).
void writeTensorFile(const std::filesystem::path& path, const std::vector<TensorField>& fields);

}  // namespace btf
