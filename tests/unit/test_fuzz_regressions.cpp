// Every input a fuzz target (tests/fuzz) found a defect with, kept in its seed corpus as
// tests/fuzz/corpus/<target>/regression-*, run through the same reader as the target: each must
// now fail with a FileError naming the file and the problem, not crash, hang or exhaust memory.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

#include "btf/core/error.h"
#include "btf/io/btf_images.h"
#include "btf/io/image.h"
#include "btf/material/rgl_brdf.h"
#include "btf/render/scene_loader.h"
#include "btf/render/triangle_mesh.h"
#include "support/test_support.h"

namespace btf {
namespace {
namespace fs = std::filesystem;
using testing::HasSubstr;

const fs::path kCorpus = BTF_FUZZ_CORPUS_DIR;

// The bytes of a corpus input, as the fuzz target received them.
std::string corpusBytes(const fs::path& input) {
  std::ifstream in(kCorpus / input, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

// fuzz_mesh's first input byte picks the format (odd: PLY, even: OBJ); the rest is the file,
// written here as dir/name the way the target writes it.
fs::path writeMeshInput(const fs::path& input, const fs::path& dir, const char* name = "mesh.ply") {
  const std::string bytes = corpusBytes(input);
  EXPECT_FALSE(bytes.empty()) << input;
  const fs::path mesh = dir / name;
  if (!bytes.empty()) std::ofstream(mesh, std::ios::binary).write(bytes.data() + 1, std::streamsize(bytes.size() - 1));
  return mesh;
}

// The reader's message for the input; fails the test when it does not throw a FileError.
template <class Read>
std::string fileErrorOf(Read&& read) {
  try {
    read();
  } catch (const FileError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no FileError";
  return {};
}

// fuzz_scene: a number beyond a double ("...1e39000...") made nlohmann-json throw out_of_range,
// which the loader did not catch (std::terminate).
TEST(FuzzRegressions, SceneNumberBeyondADoubleIsMalformedJson) {
  const fs::path input = kCorpus / "fuzz_scene" / "regression-number-overflow.json";
  EXPECT_THAT(fileErrorOf([&] { (void)render::loadSceneDescription(input); }), HasSubstr("malformed JSON"));
}

// fuzz_mesh: a PLY whose vertices have no x aborted inside Assimp's triangulation (Assimp read PLY
// then; an assertion: `btf render` exited on SIGABRT). The first byte of the input picks the
// format (odd: PLY).
TEST(FuzzRegressions, PlyVerticesWithoutAPositionAreRefused) {
  test::TempDir dir;
  const fs::path ply = writeMeshInput("fuzz_mesh/regression-ply-without-x.ply", dir.path());
  const std::string message = fileErrorOf([&] { (void)render::loadTriangleMeshes(ply); });
  EXPECT_THAT(message, HasSubstr(ply.string()));
  EXPECT_THAT(message, HasSubstr("without the position property 'x'"));
}

// fuzz_mesh: a binary PLY whose one face lists 0 vertices, which Assimp's triangulation aborted on.
TEST(FuzzRegressions, PlyFaceOfFewerThanThreeVerticesIsRefused) {
  test::TempDir dir;
  const fs::path ply = writeMeshInput("fuzz_mesh/regression-ply-face-of-0-vertices.ply", dir.path());
  EXPECT_THAT(fileErrorOf([&] { (void)render::loadTriangleMeshes(ply); }), HasSubstr("has 0 vertices (a face needs 3 or more)"));
}

// fuzz_mesh: "end_header" followed by a vertical tab. istream takes \v as a space, Assimp's PLY
// tokenizer does not: it never found the end of the header and read on for ever (a timeout).
TEST(FuzzRegressions, PlyHeaderWithAControlCharacterIsRefused) {
  test::TempDir dir;
  const fs::path ply = writeMeshInput("fuzz_mesh/regression-ply-vertical-tab-after-end-header.ply", dir.path());
  const std::string message = fileErrorOf([&] { (void)render::loadTriangleMeshes(ply); });
  EXPECT_THAT(message, HasSubstr(ply.string()));
  EXPECT_THAT(message, HasSubstr("a control character in line 5"));
}

// fuzz_mesh: "element face 2147483647 list<bytes>nt vertex_indices" declared two billion faces
// whose property line Assimp's parser (which read PLY then) and ours both read as no property at
// all, and Assimp built every face (minutes). Extra words on an element line are refused; faces
// need their vertex list; and an element without properties, which takes no bytes, is not read.
TEST(FuzzRegressions, PlyElementOfBillionsWithoutPropertiesIsRefused) {
  test::TempDir dir;
  const fs::path ply = writeMeshInput("fuzz_mesh/regression-ply-2147483647-faces-without-properties.ply", dir.path());
  const std::string message = fileErrorOf([&] { (void)render::loadTriangleMeshes(ply); });
  EXPECT_THAT(message, HasSubstr(ply.string()));
  EXPECT_THAT(message, HasSubstr("malformed PLY header line 'element face 2147483647 list"));

  // The same header written cleanly declares faces without vertices.
  const fs::path clean = dir.path() / "faces-without-properties.ply";
  std::ofstream(clean) << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                          "property float z\nelement face 2147483647\nend_header\n0 0 0\n1 0 0\n0 1 0\n";
  EXPECT_THAT(fileErrorOf([&] { (void)render::loadTriangleMeshes(clean); }), HasSubstr("PLY faces without a vertex_indices list"));
  // Another element of billions without properties is nothing to read.
  const fs::path other = dir.path() / "markers-without-properties.ply";
  std::ofstream(other) << "ply\nformat ascii 1.0\nelement marker 18446744073709551615\nelement vertex 3\nproperty float x\n"
                          "property float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                          "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  EXPECT_EQ(render::loadTriangleMeshes(other).at(0).triangles.size(), 1u);
}

// fuzz_mesh: "element 4444...44vertex 3", an element name of 77 digits and a word. Assimp, which
// read PLY then, took the count of an element it did not know from the start of its name: the
// digits became billions of instances, which it allocated (a timeout, and memory far past the
// fuzzer's limit). An element of any
// name is now read for its declared count, and one that is not the vertices or faces skipped.
TEST(FuzzRegressions, PlyElementNameBeginningWithDigitsIsReadLikeAnyOther) {
  test::TempDir dir;
  const fs::path ply = writeMeshInput("fuzz_mesh/regression-ply-element-name-beginning-with-digits.ply", dir.path());
  const std::string message = fileErrorOf([&] { (void)render::loadTriangleMeshes(ply); });
  EXPECT_THAT(message, HasSubstr(ply.string()));
  EXPECT_THAT(message, HasSubstr("the mesh has no faces"));

  auto triangleWithElement = [&](const std::string& name, const std::string& element) {
    const fs::path file = dir.path() / name;
    std::ofstream(file) << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                           "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                        << element << "\nproperty int id\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n7\n";
    return file;
  };
  for (const char* element : {"element 4camera 1", "element camera 1", "element _extra 1"})
    EXPECT_EQ(render::loadTriangleMeshes(triangleWithElement("extra.ply", element)).at(0).triangles.size(), 1u) << element;
  // The extra element's data must be there.
  EXPECT_THAT(fileErrorOf([&] { (void)render::loadTriangleMeshes(triangleWithElement("two.ply", "element camera 2")); }),
              HasSubstr("truncated PLY: the data ends in element 'camera' 1 of 2"));
}

// fuzz_mesh: a binary PLY declaring its vertex and face elements twice (3 vertices, then 6).
// Assimp's PLY reader, which read PLY then, wrote past a heap block sized for the first; Assimp is
// not instrumented, so AddressSanitizer saw only the allocator's corrupted state, far from the
// cause (its CHECK failed in a later free). Found by fuzzing PLY inputs alone; confirmed with
// Valgrind on the input. PLY is now read by libbtf, and an element declared twice is refused.
TEST(FuzzRegressions, PlyElementDeclaredTwiceIsRefused) {
  test::TempDir dir;
  const fs::path ply = writeMeshInput("fuzz_mesh/regression-ply-vertex-element-declared-twice.ply", dir.path());
  const std::string message = fileErrorOf([&] { (void)render::loadTriangleMeshes(ply); });
  EXPECT_THAT(message, HasSubstr(ply.string()));
  EXPECT_THAT(message, HasSubstr("PLY element 'vertex' declared twice"));
}

// fuzz_mesh (a leak): an OBJ whose `mtllib` names a folder. Assimp, which read OBJ then, opened the
// folder, failed to read it and threw without closing it. Material libraries are regular files
// only: a folder, or a device, is a library not found, and the mesh loads without it. (A leak
// shows under the sanitizers, where CI runs this test.)
TEST(FuzzRegressions, ObjMaterialLibraryNamingAFolderIsNotOpened) {
  test::TempDir dir;
  const fs::path obj = writeMeshInput("fuzz_mesh/regression-obj-mtllib-naming-a-folder.obj", dir.path(), "mesh.obj");
  // The fuzzed file holds no face: an error naming the file.
  const std::string message = fileErrorOf([&] { (void)render::loadTriangleMeshes(obj); });
  EXPECT_THAT(message, HasSubstr(obj.string()));
  EXPECT_THAT(message, HasSubstr("the mesh has no faces"));

  fs::create_directory(dir.path() / "materials.mtl");
  // /proc/kmsg is a regular file whose read blocks (as root) until the kernel logs something.
  for (const char* library : {"materials.mtl", "/dev/zero", "missing.mtl", "/proc/kmsg"}) {
    const fs::path file = dir.path() / "triangle.obj";
    std::ofstream(file) << "mtllib " << library << "\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl red\nf 1 2 3\n";
    const std::vector<render::TriangleMesh> meshes = render::loadTriangleMeshes(file);
    ASSERT_EQ(meshes.size(), 1u) << library;
    EXPECT_EQ(meshes[0].triangles.size(), 1u) << library;
  }
}

// fuzz_mesh (a leak): an OBJ with "v  0 0", a vertex of two numbers. Assimp, which read OBJ then,
// skipped it; the element check counted it, so a face that indexed the last vertex passed the
// check and lay past Assimp's list; Assimp threw after building its meshes and leaked them. Now
// every entry must hold the numbers its statement takes, finite (tinyobjloader reads a missing or
// unreadable number as 0, silently).
TEST(FuzzRegressions, ObjEntryOfTooFewNumbersIsRefused) {
  test::TempDir dir;
  const fs::path obj = writeMeshInput("fuzz_mesh/regression-obj-vertex-of-two-numbers-not-counted-by-assimp.obj", dir.path(), "mesh.obj");
  std::string message = fileErrorOf([&] { (void)render::loadTriangleMeshes(obj); });
  EXPECT_THAT(message, HasSubstr(obj.string()));
  EXPECT_THAT(message, HasSubstr("line 1: 'v' with 2 numbers (it needs 3, 4, or 6 with a colour)"));

  const std::string triangle = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  const std::pair<std::string, std::string> refused[] = {
      {"v 0 0 0 0 0\n" + triangle + "f 2 3 4\n", "line 1: 'v' with 5 numbers"},
      {"v nan 0 0\n" + triangle + "f 2 3 4\n", "line 1: 'nan' is not a finite number"},
      {"v 1e999 0 0\n" + triangle + "f 2 3 4\n", "line 1: '1e999' is not a finite number"},
      {"v 0 0 zero\n" + triangle + "f 2 3 4\n", "line 1: 'zero' is not a finite number"},
      {triangle + "vt 0\nf 1/1 2/1 3/1\n", "line 4: 'vt' with 1 numbers (it needs 2 or 3)"},
      {triangle + "vn 0 1\nf 1//1 2//1 3//1\n", "line 4: 'vn' with 2 numbers (it needs 3)"},
  };
  for (const auto& [text, problem] : refused) {
    const fs::path file = dir.path() / "case.obj";
    std::ofstream(file, std::ios::binary) << text;
    EXPECT_THAT(fileErrorOf([&] { (void)render::loadTriangleMeshes(file); }), HasSubstr(problem)) << text;
  }
  // What OBJ files hold loads: 4 or 6 components, exponents, signs, a leading point, indented
  // statements, trailing comments (also after a face), CRLF.
  const fs::path file = dir.path() / "counted.obj";
  std::ofstream(file, std::ios::binary) << "v 0 0 0 1\r\nv +1e0 0 0 # x\r\n  v 0 .5 0 1 0.5 0.5\r\nvt 0 0\r\nvt 0 1 0\r\n"
                                           "vn 0 0 1\r\n\tf 1/1/1 2/2/1 3/1/1 # a face\r\n";
  const std::vector<render::TriangleMesh> meshes = render::loadTriangleMeshes(file);
  ASSERT_EQ(meshes.size(), 1u);
  ASSERT_EQ(meshes[0].triangles.size(), 1u);
  EXPECT_EQ(meshes[0].positions[meshes[0].triangles[0][2]], glm::vec3(0.0f, 0.5f, 0.0f));
  EXPECT_EQ(meshes[0].uvs.size(), meshes[0].positions.size());
  EXPECT_EQ(meshes[0].normals.size(), meshes[0].positions.size());
}

// fuzz_mesh: an OBJ whose line element, after a group statement, has one vertex that lies past the
// vertex list (a NUL ended the line before it, as Assimp, which read OBJ then, read lines). Assimp
// threw and leaked the meshes it had built. Faces are now checked before the OBJ is read, control
// characters refused, and lines and points not read at all.
TEST(FuzzRegressions, ObjElementIndexingPastTheVerticesIsRefused) {
  test::TempDir dir;
  const fs::path obj = writeMeshInput("fuzz_mesh/regression-obj-line-after-group-indexing-past-the-vertices.obj", dir.path(), "mesh.obj");
  std::string message = fileErrorOf([&] { (void)render::loadTriangleMeshes(obj); });
  EXPECT_THAT(message, HasSubstr(obj.string()));
  EXPECT_THAT(message, HasSubstr("line 3: a control character (code 0)"));

  // The same defects written cleanly, and their neighbours.
  const std::string triangle = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  const std::pair<std::string, std::string> cases[] = {
      {"v 1 1 0\np 1\ng 4\nl 4\n", "the mesh has no faces"},  // lines and points are not read
      {triangle + "f 1 2 3\ng part\nf 1 2 9\n", "line 6: '9' indexes past the 3 'v' entries of the file"},
      {triangle + "f -4 -2 -1\n", "line 4: '-4' indexes past the 3 'v' entries defined before it"},
      {triangle + "f 1/1 2/1 3/1\n", "line 4: '1/1' indexes past the 0 'vt' entries of the file"},
      {triangle + "f 0 1 2\n", "line 4: '0' is not a valid v index"},
      {triangle + "f 1 2 x\n", "line 4: 'x' is not a valid v index"},
      {triangle + "vn 0 0 1\nf 1//1 2//1 3//1/1\n", "'3//1/1' has more than three indices"},
      {triangle + "f 1 2\n", "line 4: 'f' with 2 vertices (it needs 3 or more)"},
  };
  for (const auto& [text, problem] : cases) {
    const fs::path file = dir.path() / "case.obj";
    std::ofstream(file, std::ios::binary) << text;
    message = fileErrorOf([&] { (void)render::loadTriangleMeshes(file); });
    EXPECT_THAT(message, HasSubstr(problem)) << text;
  }
  // Relative indices, texture coordinates and normals within their lists load.
  const fs::path good = dir.path() / "good.obj";
  std::ofstream(good, std::ios::binary) << triangle << "vt 0 0\nvn 0 0 1\ng part\nf -3/1/1 -2/1/1 -1//1\n";
  const std::vector<render::TriangleMesh> meshes = render::loadTriangleMeshes(good);
  ASSERT_EQ(meshes.size(), 1u);
  EXPECT_EQ(meshes[0].triangles.size(), 1u);
}

// fuzz_rgl: a tensor file whose RGB values (8e10 1/sr) and the luminance its warp was built from
// (a density of 2e-32) disagree by over 40 orders of magnitude. At a grazing view (89.9 degrees)
// sample() returned an infinite weight. Such draws are now dropped.
TEST(FuzzRegressions, RglWarpFarFromItsValuesGivesNoInfiniteWeight) {
  const RglBrdf material(kCorpus / "fuzz_rgl" / "regression-warp-and-values-40-orders-apart.bsdf");
  const float theta = 89.9f * 3.14159265f / 180.0f;
  for (float x : {1.0f, -1.0f}) {
    const glm::vec3 wo(x * std::sin(theta), 0.0f, std::cos(theta));
    const auto s = material.sample(wo, {0.5f, 0.5f}, {0.01f, 0.99f});
    EXPECT_FALSE(s.has_value()) << "weight " << s->weight[0] << " at pdf " << s->pdf;
  }
}

// fuzz_exr_stack: 21 and 22 bytes of WebP (named .exr) whose headers claim 12485 x 2053 and
// 12485 x 5125 pixels. OpenImageIO fell back to its WebP reader: the first allocated and filled
// the claimed image in floats before failing, the second decoded and premultiplied 64 megapixels, both far
// past the 2 s limit under the sanitizers. Formats libbtf does not read are now refused by name,
// and pixel memory is committed only once the first row has decoded.
TEST(FuzzRegressions, WebpNamedExrIsRefusedByItsFormat) {
  for (const char* name : {"regression-webp-claiming-12485x2053.exr", "regression-webp-decoding-to-megapixels.exr"}) {
    const fs::path input = kCorpus / "fuzz_exr_stack" / name;
    const std::string message = fileErrorOf([&] { (void)readImage(input); });
    EXPECT_THAT(message, HasSubstr(input.string()));
    EXPECT_THAT(message, HasSubstr("is not an OpenEXR, PNG, JPEG, TIFF or Radiance HDR image (by its first bytes)"));
  }
}

// fuzz_exr_stack (an abort): a corrupt header named .exr that OpenEXR refused; OpenImageIO then
// tried each of its readers on it, and the RLA reader aborted (an assertion) in open. Only the
// reader of the format the first bytes name is opened now, and only for the five formats libbtf
// reads.
TEST(FuzzRegressions, OnlyTheReaderOfTheFilesOwnFormatIsTried) {
  const fs::path input = kCorpus / "fuzz_exr_stack" / "regression-corrupt-header-reaching-the-rla-reader.exr";
  const std::string message = fileErrorOf([&] { (void)readImageStack(input); });
  EXPECT_THAT(message, HasSubstr(input.string()));
  EXPECT_THAT(message, HasSubstr("is not an OpenEXR, PNG, JPEG, TIFF or Radiance HDR image (by its first bytes)"));
}

// fuzz_btf_json: an angle of 74 digits overflowed std::stof, whose std::out_of_range escaped the
// name parser (std::terminate). The input is parsed as a file name, as the target does.
TEST(FuzzRegressions, ImageNameWithAnAngleBeyondAFloatIsAnError) {
  const std::string name = corpusBytes("fuzz_btf_json/regression-angle-beyond-float.json");
  ASSERT_FALSE(name.empty());
  try {
    (void)parseBtfImageName(name);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_THAT(e.what(), HasSubstr("is not a number of degrees"));
  }
}

// fuzz_exr_stack: a channel of pixel type 514 in an EXR's channel list, which OpenEXR keeps and
// OpenImageIO aborts on (an assertion).
TEST(FuzzRegressions, ExrChannelOfAnUnknownPixelTypeIsRefused) {
  const fs::path input = kCorpus / "fuzz_exr_stack" / "regression-exr-unknown-pixel-type.exr";
  EXPECT_THAT(fileErrorOf([&] { (void)readImageStack(input); }), HasSubstr("channel 'G' has the unknown pixel type 514"));
}

// fuzz_exr_stack (out of memory): the second part's channel list holds fewer bytes of entries
// than its declared size; OpenEXR reads a channel list by its entries, lost its place in the
// header and read the following bytes as a string attribute of gigabytes.
TEST(FuzzRegressions, ExrChannelListNotFillingItsSizeIsRefused) {
  const fs::path input = kCorpus / "fuzz_exr_stack" / "regression-exr-channel-list-size.exr";
  const std::string message = fileErrorOf([&] { (void)readImageStack(input); });
  EXPECT_THAT(message, HasSubstr("corrupt OpenEXR header: attribute 'channels'")) << message;
}

// fuzz_exr_stack (out of memory): an int attribute declaring 0 bytes; OpenEXR reads an int's 4
// bytes whatever the declared size, lost its place, and read on as further headers.
TEST(FuzzRegressions, ExrFixedSizeAttributeOfAnotherSizeIsRefused) {
  const fs::path input = kCorpus / "fuzz_exr_stack" / "regression-exr-int-of-size-0.exr";
  EXPECT_THAT(fileErrorOf([&] { (void)readImageStack(input); }),
              HasSubstr("attribute 'channel' (int) declares 0 bytes, its type holds 4"));
}

// fuzz_btf_image (out of memory) and fuzz_exr_stack (timeout): EXR headers whose attributes claim
// 1.6 GB and more in files of a few hundred bytes; OpenEXR 3.1 allocated the claimed size first.
TEST(FuzzRegressions, ExrAttributesClaimingMoreThanTheFileAreRefused) {
  for (const fs::path& input : {kCorpus / "fuzz_btf_image" / "regression-exr-string-attribute-1.6gb.exr",
                               kCorpus / "fuzz_exr_stack" / "regression-exr-attribute-size.exr"}) {
    const std::string message = fileErrorOf([&] { (void)readImage(input); });
    EXPECT_THAT(message, HasSubstr("corrupt OpenEXR header")) << input;
    EXPECT_THAT(message, HasSubstr("beyond the file")) << input;
  }
}

}  // namespace
}  // namespace btf
