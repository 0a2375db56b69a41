// Test tiers, declared where a test is defined. A test program has one default tier (its ctest
// label: `unit` for tests/unit, `cli` for tests/cli); a test that belongs to another one is
// written BTF_STATISTICAL_TEST(...) or BTF_SLOW_TEST(...) in place of TEST(...) (and likewise
// _F and _P). So a test keeps its tier when it is renamed or moved, and no list of names elsewhere
// has to follow it.
//
// The tiers:
// - statistical: chi-square, Monte Carlo and estimator-agreement runs at high sample counts. Each
//   states its significance level and sample count; they repeat the arithmetic that the unit tier
//   reaches at small sizes, so the sanitizer run leaves them out.
// - slow: large fits and thousands of image reads or writes, whose code paths the unit tier
//   also covers at small sizes.
//
// tests/cmake/BtfGTestSuites.cmake registers one ctest test per suite and tier, reading the tiers
// from the test program itself (--btf_list_tiers, answered by support/test_main.cpp).
#pragma once

#include <gtest/gtest.h>

#include <string>
#include <utility>
#include <vector>

namespace btf::test {

// Records that suite.name (as written in the source: no instantiation prefix or parameter suffix)
// belongs to the tier; returns true so that it can initialize a static.
bool registerTier(const char* suite, const char* name, const char* tier);

// Every registration so far, as ("suite.name", tier).
const std::vector<std::pair<std::string, std::string>>& registeredTiers();

}  // namespace btf::test

#define BTF_TIERED_TEST(tier, test_macro, suite, name)                                         \
  [[maybe_unused]] static const bool btf_tier_of_##suite##_##name =                            \
      ::btf::test::registerTier(#suite, #name, tier);                                          \
  test_macro(suite, name)

#define BTF_STATISTICAL_TEST(suite, name) BTF_TIERED_TEST("statistical", TEST, suite, name)
#define BTF_STATISTICAL_TEST_F(suite, name) BTF_TIERED_TEST("statistical", TEST_F, suite, name)
#define BTF_STATISTICAL_TEST_P(suite, name) BTF_TIERED_TEST("statistical", TEST_P, suite, name)
#define BTF_SLOW_TEST(suite, name) BTF_TIERED_TEST("slow", TEST, suite, name)
#define BTF_SLOW_TEST_F(suite, name) BTF_TIERED_TEST("slow", TEST_F, suite, name)
#define BTF_SLOW_TEST_P(suite, name) BTF_TIERED_TEST("slow", TEST_P, suite, name)
