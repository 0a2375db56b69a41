cmake_policy(PUSH)
cmake_policy(VERSION 3.25)
# Run by ctest before the tests (BtfGTestSuites.cmake): lists a test program's cases and tiers, writes
# OUT, a ctest file with one add_test per suite and tier.
# Inputs: EXE, TARGET, LABEL (default tier), OUT, WORKING_DIR.
execute_process(COMMAND "${EXE}" --gtest_list_tests OUTPUT_VARIABLE listing RESULT_VARIABLE rc
                TIMEOUT 120)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "${EXE} --gtest_list_tests failed (${rc})")
endif()
execute_process(COMMAND "${EXE}" --btf_list_tiers OUTPUT_VARIABLE tier_listing RESULT_VARIABLE rc
                TIMEOUT 120)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "${EXE} --btf_list_tiers failed (${rc})")
endif()

# "suite.name tier" lines -> variables tier_of_<suite.name>
string(REPLACE "\n" ";" tier_lines "${tier_listing}")
set(tiered_tests "")
foreach(line IN LISTS tier_lines)
  if(line MATCHES "^([^ ]+) ([a-z]+)$")
    set("tier_of_${CMAKE_MATCH_1}" "${CMAKE_MATCH_2}")
    list(APPEND tiered_tests "${CMAKE_MATCH_1}")
  endif()
endforeach()
set(placed_tests "")

# GoogleTest's listing: "Suite." (or "Prefix/Suite.") lines, then "  Case" (or "  Case/3") lines,
# either possibly followed by "  # TypeParam = ..." / "  # GetParam() = ...".
set(groups "")
string(REPLACE "\n" ";" lines "${listing}")
foreach(line IN LISTS lines)
  string(REGEX REPLACE " +#.*$" "" line "${line}")
  if(line STREQUAL "")
    continue()
  endif()
  if(line MATCHES "^([^ ].*)\\.$")
    set(suite "${CMAKE_MATCH_1}")
    # As written in the source: without a typed test's index ("Suite/3") and without a
    # parameterized test's instantiation prefix ("Prefix/Suite").
    string(REGEX REPLACE "/[0-9]+$" "" source_suite "${suite}")
    string(REGEX REPLACE "^.*/" "" source_suite "${source_suite}")
    set("all_${suite}" "")
  elseif(line MATCHES "^  +(.+)$")
    set(case "${CMAKE_MATCH_1}")
    string(REGEX REPLACE "/.*$" "" source_case "${case}")   # a parameter's name or index
    set(tier "${LABEL}")
    if(DEFINED "tier_of_${source_suite}.${source_case}")
      set(tier "${tier_of_${source_suite}.${source_case}}")
      list(APPEND placed_tests "${source_suite}.${source_case}")
    endif()
    # Group key: suite and tier. CMake lists cannot hold ';' and names cannot hold it either.
    string(MAKE_C_IDENTIFIER "${suite}|${tier}" key)
    if(NOT DEFINED "cases_${key}")
      list(APPEND groups "${key}")
      set("suite_${key}" "${suite}")
      set("tier_${key}" "${tier}")
      set("cases_${key}" "")
    endif()
    list(APPEND "cases_${key}" "${suite}.${case}")
    list(APPEND "all_${suite}" "${tier}")
  endif()
endforeach()

# A tier declared for a test that the listing does not hold would leave that test in the default
# tier unnoticed: refuse it.
foreach(test IN LISTS tiered_tests)
  if(NOT test IN_LIST placed_tests)
    message(FATAL_ERROR "${EXE}: ${test} is declared ${tier_of_${test}} (support/tier.h) but is not among its tests")
  endif()
endforeach()

set(content "# Written by BtfGTestSuitesList.cmake from ${TARGET}'s listing; do not edit.\n")
foreach(key IN LISTS groups)
  set(suite "${suite_${key}}")
  set(tier "${tier_${key}}")
  set(tiers_here "${all_${suite}}")
  list(REMOVE_DUPLICATES tiers_here)
  list(LENGTH tiers_here tier_count)
  if(tier_count EQUAL 1)
    set(filter "${suite}.*")
    set(name "${suite}")
  else()
    list(JOIN "cases_${key}" ":" filter)
    set(name "${suite}/${tier}")
  endif()
  string(APPEND content
    "add_test([==[${name}]==] \"${EXE}\" [==[--gtest_filter=${filter}]==])\n"
    "set_tests_properties([==[${name}]==] PROPERTIES LABELS ${tier} WORKING_DIRECTORY \"${WORKING_DIR}\")\n")
endforeach()
file(WRITE "${OUT}.tmp" "${content}")
file(RENAME "${OUT}.tmp" "${OUT}")
cmake_policy(POP)
