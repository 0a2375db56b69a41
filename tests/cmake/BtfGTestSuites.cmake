# btf_add_gtest_suites(TARGET LABEL): registers the GoogleTest program TARGET with ctest as one test
# per suite and tier, not one per case. A case started in a process of its own paid the program's
# start-up and rebuilt the fixtures that a suite shares (static "built once" tables) every time;
# a suite in one process pays both once. ctest -R SUITE still selects a suite; a single case runs
# with the program's own --gtest_filter.
#
# LABEL is the program's default tier; a test that support/tier.h marks as statistical or slow gets
# that label instead (read from the program with --btf_list_tiers), so that a tier is selected with
# ctest -L and follows the test wherever it is defined. The list is made after each build of TARGET
# (like gtest_discover_tests, whose POST_BUILD mode this follows) by BtfGTestSuitesList.cmake.
set(BTF_GTEST_SUITES_LIST_SCRIPT "${CMAKE_CURRENT_LIST_DIR}/BtfGTestSuitesList.cmake")

function(btf_add_gtest_suites target label)
  set(list_file "${CMAKE_CURRENT_BINARY_DIR}/${target}_suites.cmake")
  set(include_file "${CMAKE_CURRENT_BINARY_DIR}/${target}_include.cmake")
  add_custom_command(TARGET ${target} POST_BUILD
    COMMAND "${CMAKE_COMMAND}" -D "EXE=$<TARGET_FILE:${target}>" -D "TARGET=${target}"
            -D "LABEL=${label}" -D "OUT=${list_file}" -D "WORKING_DIR=${CMAKE_CURRENT_BINARY_DIR}"
            -P "${BTF_GTEST_SUITES_LIST_SCRIPT}"
    BYPRODUCTS "${list_file}"
    VERBATIM)
  file(WRITE "${include_file}"
    "if(EXISTS \"${list_file}\")\n"
    "  include(\"${list_file}\")\n"
    "else()\n"
    "  add_test(${target}_NOT_BUILT ${target}_NOT_BUILT)\n"
    "endif()\n")
  set_property(DIRECTORY APPEND PROPERTY TEST_INCLUDE_FILES "${include_file}")
endfunction()
