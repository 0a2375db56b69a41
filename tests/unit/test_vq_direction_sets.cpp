// VQ compression on direction sets other than the 81-direction one: the ring layouts level 1 codes
// (core/btf_ring_layout.h), the tolerance bounds on the Bonn dome and on scattered view-dependent
// lights, .btfz keeping the set, databases of one layout, and the refusals where layouts differ.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <tbb/global_control.h>

#include <cmath>
#include <fstream>
#include <set>

#include <nlohmann/json.hpp>

#include "btf/compress/vq_btf.h"
#include "btf/compress/vq_database.h"
#include "btf/core/btf_ring_layout.h"
#include "btf/core/error.h"
#include "btf/io/container.h"
#include "btf_test_data.h"
#include "support/test_support.h"
#include "synthetic_btf.h"

namespace btf {
namespace {

using ::testing::HasSubstr;

template <class F>
std::string errorOf(F&& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "(no error)";
}

// The 81-direction set with one light of view 0 moved aside, as UTIA's shifted lights: indexed as
// UBO2003 (its nominal set).
BtfDirectionSetPtr shiftedUboSet() {
  const BtfDirectionSet& ubo = *BtfDirectionSet::ubo2003();
  std::vector<BtfAngles> views;
  std::vector<std::vector<BtfAngles>> lights;
  for (int v = 0; v < ubo.viewCount(); ++v) {
    views.push_back(ubo.viewAngles(v));
    const auto list = ubo.lights(v);
    lights.emplace_back(list.begin(), list.end());
  }
  lights[0][0] = {4.0f, 90.0f};
  return std::make_shared<const BtfDirectionSet>("shifted", views, lights, BtfDirectionSet::ubo2003());
}

void expectRingsAreRings(const BtfRingLayout& layout, const BtfDirectionSet& set) {
  std::set<int> seen;
  for (int r = 0; r < layout.ringCount(); ++r) {
    EXPECT_LE(layout.size(r), BtfRingLayout::kBandSize);
    for (int a = 0; a < layout.size(r); ++a) {
      const int l = layout.light(r, a);
      EXPECT_TRUE(seen.insert(l).second);
      EXPECT_EQ(layout.ringOf(l), r);
      EXPECT_EQ(layout.placeOf(l), a);
      EXPECT_NEAR(set.lights(0)[std::size_t(l)].theta_deg, set.lights(0)[std::size_t(layout.light(r, 0))].theta_deg, 0.5f);
    }
  }
  EXPECT_EQ(int(seen.size()), set.lightCount(0));
}

TEST(BtfRingLayout, TheKnownSetsGetTheirRings) {
  EXPECT_EQ(BtfRingLayout::of(*BtfDirectionSet::ubo2003(), "test"), BtfRingLayout::ubo2003());
  EXPECT_EQ(BtfRingLayout::ubo2003().sizes(), (std::vector<int>{1, 6, 12, 18, 20, 24}));
  EXPECT_TRUE(BtfRingLayout::ubo2003().inIndexOrder());
  // The dome: its ten rings (btflib's rings of 1, 6, 12, 12, 12, 18, 18, 24, 24, 24 lights).
  const BtfRingLayout dome = BtfRingLayout::of(*BtfDirectionSet::uboDome1(), "test");
  EXPECT_EQ(dome.sizes(), (std::vector<int>{1, 6, 12, 12, 12, 18, 18, 24, 24, 24}));
  expectRingsAreRings(dome, *BtfDirectionSet::uboDome1());
  // Lights moved aside keep their nominal set's rings.
  EXPECT_EQ(BtfRingLayout::of(*shiftedUboSet(), "test"), BtfRingLayout::ubo2003());
}

TEST(BtfRingLayout, ScatteredLightsAreCutIntoBandsOfElevation) {
  const BtfDirectionSetPtr set = synthetic::scatteredDirectionSet(5, 60);
  const BtfRingLayout layout = BtfRingLayout::of(*set, "test");
  EXPECT_EQ(layout.sizes(), (std::vector<int>{24, 24, 12}));
  std::set<int> seen(layout.order().begin(), layout.order().end());
  EXPECT_EQ(seen.size(), 60u);
  // Bands follow elevation: every light of band r lies no higher than every light of band r + 1.
  for (int r = 0; r + 1 < layout.ringCount(); ++r) {
    float top = 0, bottom = 90;
    for (int a = 0; a < layout.size(r); ++a) top = std::max(top, set->lights(0)[std::size_t(layout.light(r, a))].theta_deg);
    for (int a = 0; a < layout.size(r + 1); ++a)
      bottom = std::min(bottom, set->lights(0)[std::size_t(layout.light(r + 1, a))].theta_deg);
    EXPECT_LE(top, bottom);
  }
  // A dense spiral shares a few elevations by chance (within the half degree that makes a ring):
  // still bands, not rings of two or three lights.
  EXPECT_EQ(BtfRingLayout::of(*synthetic::scatteredDirectionSet(3, 200), "test").sizes(),
            (std::vector<int>{24, 24, 24, 24, 24, 24, 24, 24, 8}));
}

TEST(BtfRingLayout, RefusesWhatCannotBeOneLayout) {
  // A light list that differs in length between views: no one grouping serves every view.
  const auto uneven = std::make_shared<const BtfDirectionSet>(
      "uneven", std::vector<BtfAngles>{{0, 0}, {30, 0}},
      std::vector<std::vector<BtfAngles>>{{{0, 0}, {30, 0}, {30, 180}}, {{0, 0}, {30, 90}}});
  EXPECT_THAT(errorOf([&] { BtfRingLayout::of(*uneven, "VQ compression of x"); }),
              HasSubstr("VQ compression of x needs the same number of lights in every view"));
  EXPECT_THAT(errorOf([&] { BtfRingLayout({2, 1}, {0, 1, 1}); }), HasSubstr("not a permutation"));
  EXPECT_THAT(errorOf([&] { BtfRingLayout({2, 2}, {0, 1, 2}); }), HasSubstr("hold 4 lights, its order 3"));
  EXPECT_THAT(errorOf([&] { BtfRingLayout({0, 3}, {0, 1, 2}); }), HasSubstr("a ring of 0 lights"));
  EXPECT_THAT(errorOf([&] { BtfRingLayout({25}, std::vector<int>(25, 0)); }), HasSubstr("a ring of 25 lights"));
  // Compression refuses it before reading data, and writes nothing.
  BtfData data(2, 2, "uneven", BtfViewSet::all(uneven));
  EXPECT_THAT(errorOf([&] { compressVq(data, {}); }), HasSubstr("needs the same number of lights in every view"));
}

// Tolerance bounds of vq_btf.h and the .btfz round trip on a set: the same decode from the file, the
// same set (one shared object for a known set), value() as loadView().
void expectCompressesWithinTheBounds(const BtfData& data, const BtfDirectionSetPtr& set) {
  test::TempDir dir;
  for (int levels = 1; levels <= 3; ++levels) {
    SCOPED_TRACE("levels " + std::to_string(levels));
    VqOptions options;
    options.levels = levels;
    options.epsilon = 0.02f;
    const VqBtf vq = compressVq(data, options);
    EXPECT_TRUE(vq.directions() == *set);
    const double lum = test::luminanceRelRmse(data, vq);
    EXPECT_LE(lum, test::vqLuminanceBound(options.epsilon, levels));
    EXPECT_LE(compareBtf(data, vq).rel_rmse, test::vqRgbBound(vq, lum, options.chroma_epsilon, options.energy_floor, levels));
    vq.write(dir / "set.btfz");
    const VqBtf back = VqBtf::read(dir / "set.btfz");
    EXPECT_TRUE(back.directions() == *set);
    EXPECT_EQ(back.ringLayout(), vq.ringLayout());
    test::expectSameDecode(vq, back);
    std::vector<Rgb> view;
    const int v = set->viewCount() / 2;
    back.loadView(v, view);
    for (int l = 0; l < set->lightCount(v); l += 7)
      for (int t : {0, 5, int(data.texelCount()) - 1})
        EXPECT_EQ(back.value(t % data.width(), t / data.width(), v, l), view[std::size_t(l) * data.texelCount() + std::size_t(t)]);
  }
}

TEST(VqDirectionSets, TheDomeCompressesWithinTheBoundsAndKeepsItsSet) {
  const BtfData data = test::makeGgxBtf(4, 4, false, BtfDirectionSet::uboDome1());
  expectCompressesWithinTheBounds(data, BtfDirectionSet::uboDome1());
  // Read back, a known set is the shared object, so that reports name it.
  test::TempDir dir;
  compressVq(data, {}).write(dir / "dome.btfz");
  EXPECT_EQ(VqBtf::read(dir / "dome.btfz").views().directionSet(), BtfDirectionSet::uboDome1());
}

TEST(VqDirectionSets, ScatteredViewDependentLightsCompressWithinTheBounds) {
  const BtfDirectionSetPtr set = synthetic::scatteredDirectionSet(12, 30);
  ASSERT_FALSE(set->sharedLights());
  expectCompressesWithinTheBounds(test::makeGgxBtf(4, 3, false, set), set);
}

TEST(VqDirectionSets, OutputDoesNotDependOnTheThreadCount) {
  const BtfData data = test::makeGgxBtf(6, 6, false, BtfDirectionSet::uboDome1());
  test::TempDir dir;
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    compressVq(data, {}).write(dir / "one.btfz");
  }
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
    compressVq(data, {}).write(dir / "two.btfz");
  }
  std::ifstream a(dir / "one.btfz", std::ios::binary), b(dir / "two.btfz", std::ios::binary);
  const std::string bytes_a((std::istreambuf_iterator<char>(a)), {}), bytes_b((std::istreambuf_iterator<char>(b)), {});
  EXPECT_FALSE(bytes_a.empty());
  EXPECT_TRUE(bytes_a == bytes_b);
}

TEST(VqDirectionSets, PartialViewsOfTheDome) {
  const BtfData whole = test::makeGgxBtf(3, 3, true, BtfDirectionSet::uboDome1());
  const BtfViewSet low = BtfViewSet::upToTheta(30.0f, BtfDirectionSet::uboDome1());
  BtfData part(3, 3, "low views", low);
  std::vector<Rgb> view;
  for (const int v : low.views()) {
    whole.loadView(v, view);
    for (int l = 0; l < 151; ++l)
      for (int t = 0; t < 9; ++t) part.at(t % 3, t / 3, v, l) = view[std::size_t(l) * 9 + std::size_t(t)];
  }
  test::TempDir dir;
  compressVq(part, {}).write(dir / "low.btfz");
  const VqBtf back = VqBtf::read(dir / "low.btfz");
  EXPECT_EQ(back.views().views(), low.views());
  EXPECT_LE(test::luminanceRelRmse(part, back), test::vqLuminanceBound(0.02f, 3));
}

TEST(VqDirectionSets, DatabasesShareCodebooksPerRingLayout) {
  const BtfData a = test::makeGgxBtf(4, 4, false, BtfDirectionSet::uboDome1());
  const BtfData b = test::makeGgxBtf(4, 4, true, BtfDirectionSet::uboDome1());
  const BtfSource* dome[] = {&a, &b};
  const VqDatabase database = compressVqDatabase(dome, {"a", "b"});
  test::TempDir dir;
  VqDatabase(database).write(dir / "dome.btfz");
  const VqDatabase back = VqDatabase::read(dir / "dome.btfz");
  ASSERT_EQ(back.size(), 2u);
  EXPECT_TRUE(back.material("b").directions() == *BtfDirectionSet::uboDome1());
  test::expectSameDecode(database.material("a"), back.material("a"));
  EXPECT_LE(test::luminanceRelRmse(b, back.material("b")), test::vqLuminanceBound(0.02f, 3));

  // Sets with other rings share no codebooks but may share a database: one group of shared
  // codebooks per ring layout, in compression, in the file and in merges (lossless).
  const BtfData ubo = test::makeGgxBtf(4, 4, false);
  const BtfSource* mixed[] = {&a, &ubo, &b};
  VqDatabase mixed_db = compressVqDatabase(mixed, {"dome", "ubo", "dome2"});
  mixed_db.write(dir / "mixed.btfz");
  const VqDatabase mixed_back = VqDatabase::read(dir / "mixed.btfz");
  ASSERT_EQ(mixed_back.names(), (std::vector<std::string>{"dome", "ubo", "dome2"}));
  EXPECT_TRUE(mixed_back.material("ubo").directions().isUbo2003());
  EXPECT_EQ(mixed_back.material("dome2").ringLayout().ringCount(), 10);
  for (const char* name : {"dome", "ubo", "dome2"}) test::expectSameDecode(mixed_db.material(name), mixed_back.material(name));
  // A material pointed at a group the file does not have, or a group left without material: an error.
  for (const int group : {7, 0}) {
    const auto edited = test::rewriteContainer(dir / "mixed.btfz", dir / "bad-group.btfz", [&](std::vector<ContainerSection>& sections) {
      for (auto& sec : sections) {
        if (sec.name != "header") continue;
        auto header = nlohmann::json::parse(std::string(reinterpret_cast<const char*>(sec.data.data()), sec.data.size()));
        header["materials"][1]["group"] = group;
        const std::string text = header.dump();
        sec.data.assign(reinterpret_cast<const std::byte*>(text.data()), reinterpret_cast<const std::byte*>(text.data()) + text.size());
      }
    });
    EXPECT_THAT(errorOf([&] { VqDatabase::read(edited); }),
                HasSubstr(group == 7 ? "has group 7, not one of its 2 groups" : "codebook group 1 has no material"));
  }
  // Each material alone in its group is compressed as in a database of its layout alone.
  const BtfSource* ubo_only[] = {&ubo};
  test::expectSameDecode(compressVqDatabase(ubo_only, {"ubo"}).material("ubo"), mixed_back.material("ubo"));
  EXPECT_LE(test::luminanceRelRmse(ubo, mixed_back.material("ubo")), test::vqLuminanceBound(0.02f, 3));
  // A merge of databases on different sets keeps every material's decode.
  const VqDatabase ubo_alone(std::vector<VqBtf>{compressVq(ubo, {})});
  const VqDatabase parts[] = {back, ubo_alone};
  const VqDatabase merged = mergeVqDatabases(parts);
  test::expectSameDecode(merged.material("a"), back.material("a"));
  test::expectSameDecode(merged.material(ubo_alone.names().front()), ubo_alone.materials().front());
  VqDatabase(merged).write(dir / "merged.btfz");
  test::expectSameDecode(VqDatabase::read(dir / "merged.btfz").material("b"), back.material("b"));

  // Lights moved aside keep the nominal rings: such a set shares a database with the 81 set, and
  // each material keeps its own directions.
  const BtfData shifted = test::makeGgxBtf(4, 4, false, shiftedUboSet());
  const BtfSource* same_rings[] = {&ubo, &shifted};
  VqDatabase joint = compressVqDatabase(same_rings, {"ubo", "shifted"});
  joint.write(dir / "joint.btfz");
  const VqDatabase joint_back = VqDatabase::read(dir / "joint.btfz");
  EXPECT_TRUE(joint_back.material("ubo").directions().isUbo2003());
  EXPECT_TRUE(joint_back.material("shifted").directions() == *shiftedUboSet());
  EXPECT_LE(test::luminanceRelRmse(shifted, joint_back.material("shifted")), test::vqLuminanceBound(0.02f, 3));
}

TEST(VqDirectionSets, ReaderRejectsADamagedSetOrLayout) {
  test::TempDir dir;
  const BtfData data = test::makeGgxBtf(3, 3, true, BtfDirectionSet::uboDome1());
  compressVq(data, {}).write(dir / "good.btfz");
  auto edited = [&](const std::string& name, auto edit) {
    return test::rewriteContainer(dir / "good.btfz", dir / (name + ".btfz"), [&](std::vector<ContainerSection>& sections) {
      for (auto& s : sections) {
        if (s.name != "header") continue;
        auto header = nlohmann::json::parse(std::string(reinterpret_cast<const char*>(s.data.data()), s.data.size()));
        edit(header);
        const std::string text = header.dump();
        s.data.assign(reinterpret_cast<const std::byte*>(text.data()), reinterpret_cast<const std::byte*>(text.data()) + text.size());
      }
    });
  };
  const struct {
    std::string name;
    std::function<void(nlohmann::json&)> edit;
    std::string words;
  } cases[] = {
      {"no-rings", [](nlohmann::json& h) { h.erase("rings"); }, "directions but no rings"},
      {"no-directions", [](nlohmann::json& h) { h.erase("directions"); }, "rings but no directions"},
      {"order", [](nlohmann::json& h) { h["rings"]["order"][3] = 0; }, "not a permutation"},
      {"sizes", [](nlohmann::json& h) { h["rings"]["sizes"][1] = 5; }, "rings hold 150 lights"},
      {"angle", [](nlohmann::json& h) { h["directions"]["views"][2] = {95.0, 0.0}; }, "theta must lie in [0, 90)"},
      {"pair", [](nlohmann::json& h) { h["directions"]["lights"][0][1] = "x"; }, "not a (theta, phi) pair"},
      {"nominal", [](nlohmann::json& h) { h["directions"]["nominal"] = "dome9"; }, "nominal set"},
  };
  for (const auto& c : cases) {
    const auto path = edited(c.name, c.edit);
    try {
      VqBtf::read(path);
      ADD_FAILURE() << c.name << " accepted";
    } catch (const FileError& e) {
      EXPECT_THAT(e.what(), HasSubstr(c.words)) << c.name;
      EXPECT_THAT(e.what(), HasSubstr(path.filename().string())) << c.name;
    }
  }
}

}  // namespace
}  // namespace btf
