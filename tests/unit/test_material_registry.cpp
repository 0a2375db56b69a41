// The material registry (btf/material/registry.h): every built-in type registered once; files
// recognised by content before extension; specs; parameter sets checked key by key with errors
// naming where they came from; the BTF and table views of a material; and SceneDocument, which
// writes a scene back with its file names rebased.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "btf/compress/octree_table.h"
#include "btf/core/error.h"
#include "btf/fit/fit_file.h"
#include "btf/io/merl.h"
#include "btf/material/ggx.h"
#include "btf/material/registry.h"
#include "btf/material/tabulated_brdf.h"
#include "btf/render/scene_document.h"
#include "btf/render/scene_loader.h"
#include "support/test_support.h"

namespace btf {
namespace {
namespace fs = std::filesystem;
using testing::HasSubstr;

MerlTable smallGgxTable() { return tabulate(Ggx(Rgb(0.3f, 0.2f, 0.1f), Rgb(0.04f), 0.3f, 0.3f)); }

void writeText(const fs::path& path, const std::string& text) { std::ofstream(path) << text; }

TEST(MaterialRegistry, RegistersEveryBuiltInTypeOnce) {
  std::vector<std::string> names;
  for (const MaterialType* t : materialTypes()) names.push_back(t->name);
  EXPECT_THAT(names, testing::IsSupersetOf({"lambert", "phong", "ggx", "ward", "lafortune", "merl", "octree", "rgl",
                                            "fitted", "merl-fit", "btf", "azimuthal-average"}));
  EXPECT_THROW(registerMaterialType({.name = "ggx", .create = [](const MaterialParams&) {
                                       return std::shared_ptr<const Material>();
                                     }}),
               Error);
  EXPECT_THROW(registerMaterialType({.name = "no-create"}), Error);
}

TEST(MaterialRegistry, BuildsTheSameMaterialAsItsConstructor) {
  MaterialParams p("ggx");
  p.set("diffuse", Rgb(0.55f, 0.05f, 0.04f)).set("f0", 0.04).set("alpha", 0.1);
  const auto built = createMaterial(p);
  const Ggx direct(Rgb(0.55f, 0.05f, 0.04f), Rgb(0.04f), 0.1f, 0.1f);
  const glm::vec3 wi = glm::normalize(glm::vec3(0.3f, 0.1f, 0.9f)), wo = glm::normalize(glm::vec3(-0.2f, 0.2f, 0.8f));
  const Rgb a = built->eval(wi, wo), b = direct.eval(wi, wo);
  EXPECT_EQ(a.r, b.r);
  EXPECT_EQ(a.g, b.g);
  EXPECT_EQ(a.b, b.b);
  EXPECT_EQ(built->name(), direct.name());
}

TEST(MaterialRegistry, ParameterErrorsNameTheKey) {
  try {
    createMaterial(MaterialParams("ggx").set("diffuse", 0.5).set("f0", 0.04).set("alpha", -1.0));
    FAIL() << "a negative alpha was accepted";
  } catch (const Error& e) {
    EXPECT_THAT(e.what(), HasSubstr("/alpha"));
    EXPECT_THAT(e.what(), HasSubstr("positive"));
  }
  try {
    createMaterial(MaterialParams("lambert").set("albedo", 0.5).set("albdo", 0.5));
    FAIL() << "a misspelt key was accepted";
  } catch (const Error& e) {
    EXPECT_THAT(e.what(), HasSubstr("/albdo: unknown key (expected one of: type, albedo)"));
  }
  try {
    createMaterial(MaterialParams("glass"));
    FAIL() << "an unknown type was accepted";
  } catch (const Error& e) {
    EXPECT_THAT(e.what(), HasSubstr("unknown material type 'glass'"));
    EXPECT_THAT(e.what(), HasSubstr("lambert"));
  }
  // A set parsed from a file names the file.
  const MaterialParams parsed = MaterialParams::parse(R"({"type": "lambert", "albedo": [0.5, -1, 0.5]})", "mine.json");
  try {
    createMaterial(parsed);
    FAIL();
  } catch (const FileError& e) {
    EXPECT_EQ(e.path(), fs::path("mine.json"));
    EXPECT_THAT(e.what(), HasSubstr("/albedo: a colour must not be negative"));
  }
}

TEST(MaterialRegistry, RecognisesFilesByContentBeforeExtension) {
  test::TempDir dir;
  const MerlTable table = smallGgxTable();
  writeMerl(dir / "table.binary", table);
  fs::copy_file(dir / "table.binary", dir / "table.dat");  // a MERL table under another name
  writeOctreeFile(dir / "tree.octree", OctreeTable::build(table, 0.1));
  fs::copy_file(dir / "tree.octree", dir / "tree.btfz");  // an octree named like a .btfz

  EXPECT_EQ(identifyMaterial((dir / "table.binary").string()).type->name, "merl");
  EXPECT_EQ(identifyMaterial((dir / "table.dat").string()).type->name, "merl");
  EXPECT_EQ(identifyMaterial((dir / "tree.octree").string()).type->name, "octree");
  EXPECT_EQ(identifyMaterial((dir / "tree.btfz").string()).type->name, "octree");
  EXPECT_THAT(identifyMaterial((dir / "table.dat").string()).description, HasSubstr("MERL binary"));

  // The table view of each is the table as stored.
  const MerlTable read = openTable((dir / "table.dat").string());
  EXPECT_EQ(read.values, table.values);
  EXPECT_EQ(openTable((dir / "tree.btfz").string()).values, OctreeTable::build(table, 0.1).expand().values);
}

TEST(MaterialRegistry, ExtensionDecidesWhenNoContentIsRecognised) {
  test::TempDir dir;
  writeText(dir / "broken.binary", "not a table");
  EXPECT_EQ(identifyMaterial((dir / "broken.binary").string()).type->name, "merl");
  try {
    openMaterial((dir / "broken.binary").string());
    FAIL();
  } catch (const FileError& e) {
    EXPECT_EQ(e.path(), dir / "broken.binary");  // the reader's own error
  }
  writeText(dir / "notes.xyz", "nothing");
  try {
    identifyMaterial((dir / "notes.xyz").string());
    FAIL();
  } catch (const FileError& e) {
    EXPECT_THAT(e.what(), HasSubstr("is of no known format (extension '.xyz')"));
    EXPECT_THAT(e.what(), HasSubstr("RGL measured material"));  // the formats are listed
  }
  EXPECT_THROW(identifyMaterial((dir / "missing.binary").string()), FileError);
}

TEST(MaterialRegistry, SpecsSetTheTypesSpecKeys) {
  const IdentifiedMaterial m = identifyMaterial("merl-fit:abc:gold-metallic-paint");
  EXPECT_EQ(m.type->name, "merl-fit");
  EXPECT_EQ(m.params.string("model"), "abc");
  EXPECT_EQ(m.params.string("name"), "gold-metallic-paint");
  EXPECT_EQ(m.format, nullptr);
  EXPECT_EQ(materialLabel(m), "gold-metallic-paint-abc");
  try {
    identifyMaterial("merl-fit:sgd");
    FAIL();
  } catch (const Error& e) {
    EXPECT_THAT(e.what(), HasSubstr("expected merl-fit:model:name"));
  }
  // A spec of a type without spec keys is no spec: a missing file.
  EXPECT_THROW(identifyMaterial("ggx:0.1"), FileError);
}

TEST(MaterialRegistry, OpenOptionsApplyWhereTheTypeTakesThem) {
  test::TempDir dir;
  writeMerl(dir / "t.binary", smallGgxTable());
  OpenOptions options;
  options.lookup = TableLookup::Nearest;
  const IdentifiedMaterial m = identifyMaterial((dir / "t.binary").string(), options);
  EXPECT_EQ(m.params.string("lookup"), "nearest");
  const auto brdf = std::dynamic_pointer_cast<const TabulatedBrdf>(createMaterial(m.params));
  ASSERT_NE(brdf, nullptr);
  EXPECT_EQ(brdf->lookup(), TableLookup::Nearest);
  options = {};
  options.database_material = "wood";
  try {
    identifyMaterial((dir / "t.binary").string(), options);
    FAIL();
  } catch (const FileError& e) {
    EXPECT_THAT(e.what(), HasSubstr("selects a material of a .btfz database"));
  }
}

TEST(MaterialRegistry, ABrdfAsABtfIsOneTexelNamedAfterItsFile) {
  test::TempDir dir;
  writeMerl(dir / "plastic.binary", smallGgxTable());
  const auto btf = openBtf((dir / "plastic.binary").string());
  EXPECT_EQ(btf->width(), 1);
  EXPECT_EQ(btf->height(), 1);
  EXPECT_EQ(btf->name(), "plastic");
}

TEST(MaterialRegistry, NestedSetsBuildWrappers) {
  const MaterialParams p = MaterialParams::parse(
      R"({"type": "azimuthal-average", "material": {"type": "ward", "diffuse": 0.02, "specular": 0.7, "alpha": [0.06, 0.25]}})");
  const auto m = createMaterial(p);
  EXPECT_FALSE(m->isAnisotropic());
  const MaterialParams bad =
      MaterialParams::parse(R"({"type": "azimuthal-average", "material": {"type": "ward", "diffuse": 0.02, "alpha": 0.1}})", "p.json");
  try {
    createMaterial(bad);
    FAIL();
  } catch (const FileError& e) {
    EXPECT_THAT(e.what(), HasSubstr("/material: missing \"specular\""));
  }
}

TEST(SceneDocument, WritesTheSceneWithFileNamesRebasedForItsFolder) {
  test::TempDir dir;
  fs::create_directories(dir / "scene" / "data");
  fs::create_directories(dir / "out");
  writeMerl(dir / "scene" / "data" / "t.binary", smallGgxTable());
  writeFitFile(dir / "fit.json",
               AnalyticFit{{ModelFamily::Ggx, Rgb(0.3f), Rgb(0.04f), 0.2f, {}}, nullptr, {}}, "test");
  writeText(dir / "scene" / "scene.json", R"({
    "camera": {"position": [0, 0, 3], "look_at": [0, 0, 0], "resolution": [8, 8]},
    "materials": {"table": {"type": "merl", "file": "data/t.binary"},
                  "grey": {"type": "lambert", "albedo": 0.5}},
    "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "table"}]
  })");
  render::SceneDocument doc = render::SceneDocument::read(dir / "scene" / "scene.json");
  EXPECT_EQ(doc.materialNames(), (std::vector<std::string>{"grey", "table"}));
  EXPECT_EQ(doc.material("table").path("file"), dir / "scene" / "data/t.binary");
  // A material set in code names its file from the current directory: here, absolute.
  doc.setMaterial("grey", MaterialParams("fitted").set("file", (dir / "fit.json").string()));
  doc.setComment("rewritten");
  doc.write(dir / "out" / "lean.json");

  render::SceneDocument written = render::SceneDocument::read(dir / "out" / "lean.json");
  EXPECT_EQ(written.material("table").string("file"), "../scene/data/t.binary");
  EXPECT_EQ(written.material("grey").string("type"), "fitted");
  const render::SceneDescription scene = render::loadSceneDescription(written);
  EXPECT_EQ(scene.materials.size(), 2u);
  try {
    written.material("wood");
    FAIL();
  } catch (const FileError& e) {
    EXPECT_THAT(e.what(), HasSubstr("no material 'wood'"));
  }
}

}  // namespace
}  // namespace btf
