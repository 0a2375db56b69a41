// The tensor_file reader on the shared RGL files (../shared/data/real/rgl_bsdf) and on corrupted
// copies of them built in a temp dir: truncation, wrong magic, unknown version, unknown dtype, a
// field with the wrong dtype or shape, NaN values. Every error must name the file and the problem.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "btf/core/error.h"
#include "btf/io/rgl_tensor.h"
#include "btf/material/rgl_brdf.h"
#include "support/test_support.h"

namespace {

namespace fs = std::filesystem;

using btf::test::kRglFiles;
using btf::test::rglPath;

std::vector<char> readBytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void writeBytes(const fs::path& path, const std::vector<char>& bytes) {
  std::ofstream(path, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

// Where each field's header entries sit in the file, found by walking the header independently
// of the reader under test.
struct FieldHeader {
  std::size_t dtype_pos, offset_pos, shape_pos;
};
std::map<std::string, FieldHeader> walkHeader(const std::vector<char>& b) {
  auto u = [&](std::size_t pos, int n) {
    std::uint64_t v = 0;
    for (int i = n - 1; i >= 0; --i) v = (v << 8) | static_cast<unsigned char>(b[pos + i]);
    return v;
  };
  std::map<std::string, FieldHeader> out;
  std::size_t pos = 18;
  for (std::uint64_t k = 0, n = u(14, 4); k < n; ++k) {
    const std::size_t name_len = u(pos, 2);
    const std::string name(b.data() + pos + 2, name_len);
    pos += 2 + name_len;
    const std::size_t ndim = u(pos, 2);
    out[name] = {pos + 2, pos + 3, pos + 11};
    pos += 11 + 8 * ndim;
  }
  return out;
}

// Runs f, expects a btf::FileError, and returns its message.
template <typename F>
std::string fileErrorOf(F&& f) {
  try {
    f();
  } catch (const btf::FileError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no FileError thrown";
  return {};
}

class RglTensorFile : public ::testing::TestWithParam<std::string> {};

TEST_P(RglTensorFile, ReadsEveryFieldWithConsistentShapes) {
  const btf::TensorFile file = btf::readTensorFile(rglPath(GetParam()));
  EXPECT_EQ(file.version_major, 1);
  EXPECT_EQ(file.version_minor, 0);
  for (const char* name : {"description", "phi_i", "theta_i", "sigma", "ndf", "vndf", "luminance", "rgb", "jacobian"})
    EXPECT_NE(file.find(name), nullptr) << name;
  const auto& theta = file.require("theta_i", btf::TensorDtype::Float32, {-1});
  const auto n = static_cast<std::int64_t>(theta.shape[0]);
  EXPECT_EQ(n, 8);  // SOURCES.md: every shared file has 8 incidences
  const auto& rgb = file.require("rgb", btf::TensorDtype::Float32, {1, n, 3, -1, -1});
  file.require("luminance", btf::TensorDtype::Float32,
               {1, n, static_cast<std::int64_t>(rgb.shape[3]), static_cast<std::int64_t>(rgb.shape[4])});
  EXPECT_EQ(rgb.toFloats().size(), rgb.elementCount());
  // theta_i spans normal to grazing incidence.
  const std::vector<double> t = theta.toDoubles();
  EXPECT_DOUBLE_EQ(t.front(), 0.0);
  EXPECT_NEAR(t.back(), M_PI / 2, 1e-6);
  EXPECT_FALSE(file.require("description", btf::TensorDtype::UInt8, {-1}).toText().empty());
}

INSTANTIATE_TEST_SUITE_P(SharedFiles, RglTensorFile, ::testing::ValuesIn(kRglFiles));

class RglTensorBadInput : public ::testing::Test {
 protected:
  void SetUp() override {
    bytes_ = readBytes(rglPath("paper_white_rgb"));
    header_ = walkHeader(bytes_);
  }
  fs::path write(const std::string& name, const std::vector<char>& bytes) {
    const fs::path p = dir_ / name;
    writeBytes(p, bytes);
    return p;
  }
  btf::test::TempDir dir_;
  std::vector<char> bytes_;
  std::map<std::string, FieldHeader> header_;
};

TEST_F(RglTensorBadInput, TruncatedHeaderAndData) {
  const fs::path header_cut = write("header_cut.bsdf", {bytes_.begin(), bytes_.begin() + 30});
  const std::string m1 = fileErrorOf([&] { btf::readTensorFile(header_cut); });
  EXPECT_NE(m1.find(header_cut.string()), std::string::npos) << m1;
  EXPECT_NE(m1.find("truncated header"), std::string::npos) << m1;
  const fs::path data_cut = write("data_cut.bsdf", {bytes_.begin(), bytes_.end() - 2000});
  const std::string m2 = fileErrorOf([&] { btf::readTensorFile(data_cut); });
  EXPECT_NE(m2.find("truncated"), std::string::npos) << m2;
  EXPECT_NE(m2.find("field '"), std::string::npos) << m2;
  const fs::path empty = write("empty.bsdf", {});
  EXPECT_NE(fileErrorOf([&] { btf::readTensorFile(empty); }).find("not a tensor_file"), std::string::npos);
}

TEST_F(RglTensorBadInput, WrongMagicAndVersion) {
  auto magic = bytes_;
  magic[0] = 'T';
  const std::string m1 = fileErrorOf([&] { btf::readTensorFile(write("magic.bsdf", magic)); });
  EXPECT_NE(m1.find("not a tensor_file"), std::string::npos) << m1;
  auto version = bytes_;
  version[12] = 2;
  const std::string m2 = fileErrorOf([&] { btf::readTensorFile(write("version.bsdf", version)); });
  EXPECT_NE(m2.find("version 2.0"), std::string::npos) << m2;
}

TEST_F(RglTensorBadInput, UnknownDtypeCode) {
  auto b = bytes_;
  b[header_.at("ndf").dtype_pos] = 42;
  const std::string m = fileErrorOf([&] { btf::readTensorFile(write("dtype42.bsdf", b)); });
  EXPECT_NE(m.find("field 'ndf' has the unknown dtype code 42"), std::string::npos) << m;
}

TEST_F(RglTensorBadInput, FieldWithWrongDtypeIsRejectedByTheMaterial) {
  // i32 has the size of f32, so the file stays readable and only the material's check can object.
  auto b = bytes_;
  b[header_.at("rgb").dtype_pos] = 6;
  const fs::path p = write("rgb_i32.bsdf", b);
  EXPECT_NO_THROW(btf::readTensorFile(p));
  const std::string m = fileErrorOf([&] { btf::RglBrdf material(p); });
  EXPECT_NE(m.find("field 'rgb' has dtype i32, expected f32"), std::string::npos) << m;
}

TEST_F(RglTensorBadInput, FieldWithWrongShapeIsRejected) {
  auto b = bytes_;
  b[header_.at("rgb").shape_pos + 16] = 2;  // the channel extent: 3 -> 2 (the data then fits too)
  const std::string m = fileErrorOf([&] { btf::RglBrdf material(write("rgb_2ch.bsdf", b)); });
  EXPECT_NE(m.find("field 'rgb' has shape (1, 8, 2, 32, 32)"), std::string::npos) << m;
  // A shape beyond the file is a truncation, found by the reader itself.
  auto big = bytes_;
  big[header_.at("vndf").shape_pos + 8 * 3 + 5] = 1;  // 128 -> 2^40 + 128 columns
  const std::string m2 = fileErrorOf([&] { btf::readTensorFile(write("vndf_big.bsdf", big)); });
  EXPECT_NE(m2.find("field 'vndf'"), std::string::npos) << m2;
  EXPECT_NE(m2.find("beyond the file"), std::string::npos) << m2;
}

TEST_F(RglTensorBadInput, NanValueIsRejected) {
  auto b = bytes_;
  std::uint64_t offset = 0;
  std::memcpy(&offset, b.data() + header_.at("luminance").offset_pos, 8);  // little-endian host
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::memcpy(b.data() + offset + 4 * 77, &nan, 4);
  const std::string m = fileErrorOf([&] { btf::readTensorFile(write("nan.bsdf", b)); });
  EXPECT_NE(m.find("field 'luminance' holds a non-finite value"), std::string::npos) << m;
  EXPECT_NE(m.find("element 77"), std::string::npos) << m;
}

// The probe's case: 3.4e38 in one rgb entry is a finite float the reader accepts, but the material
// overflowed to an albedo of inf. The material refuses values beyond the measured range by name.
TEST_F(RglTensorBadInput, HugeFiniteValueIsRejectedByTheMaterial) {
  for (const char* field : {"rgb", "ndf"}) {
    auto b = bytes_;
    std::uint64_t offset = 0;
    std::memcpy(&offset, b.data() + header_.at(field).offset_pos, 8);  // little-endian host
    const float huge = 3.4e38f;
    std::memcpy(b.data() + offset + 4 * 5, &huge, 4);
    const fs::path p = write(std::string("huge_") + field + ".bsdf", b);
    EXPECT_NO_THROW(btf::readTensorFile(p));
    const std::string m = fileErrorOf([&] { btf::RglBrdf material(p); });
    EXPECT_NE(m.find("field '" + std::string(field) + "' holds 3.4e+38 at element 5"), std::string::npos) << m;
  }
}

TEST_F(RglTensorBadInput, MissingFileNamesThePath) {
  const fs::path p = dir_ / "absent.bsdf";
  const std::string m = fileErrorOf([&] { btf::readTensorFile(p); });
  EXPECT_NE(m.find(p.string()), std::string::npos) << m;
}

}  // namespace
