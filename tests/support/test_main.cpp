// The main of every test program: GoogleTest's, plus --btf_list_tiers, which prints each test that
// support/tier.h places in a tier of its own as "suite.name tier", one per line, and exits. The
// build reads it to give ctest's tests their labels (tests/cmake/BtfGTestSuites.cmake).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>

#include "support/tier.h"

namespace btf::test {

namespace {
std::vector<std::pair<std::string, std::string>>& tierTable() {
  static std::vector<std::pair<std::string, std::string>> table;
  return table;
}
}  // namespace

bool registerTier(const char* suite, const char* name, const char* tier) {
  tierTable().emplace_back(std::string(suite) + "." + name, tier);
  return true;
}

const std::vector<std::pair<std::string, std::string>>& registeredTiers() { return tierTable(); }

}  // namespace btf::test

int main(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--btf_list_tiers") == 0) {
      for (const auto& [test, tier] : btf::test::registeredTiers()) std::printf("%s %s\n", test.c_str(), tier.c_str());
      return 0;
    }
  }
  testing::InitGoogleMock(&argc, argv);
  return RUN_ALL_TESTS();
}
