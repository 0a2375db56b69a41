# btf_add_gtest_suites(TARGET LABEL): registers the GoogleTest program TARGET with ctest as one test
# per suite and tier, not one per case. A case started in a process of its own paid the program's
# start-up and rebuilt the fixtures that a suite shares (static "built once" tables) every time;
# a suite in one process pays both once. ctest -R SUITE still selects a suite; a single case runs
# with the program's own --gtest_filter.
#
# LABEL is the program's default tier; a test that support/tier.h marks as statistical or slow gets
# that label instead (read from the program with --btf_list_tiers), so that a tier is selected with
# ctest -L and follows the test wherever it is defined. ctest makes the list when it starts
# (BtfGTestSuitesList.cmake), whenever the program is newer than the list, as gtest_discover_tests'
# PRE_TEST mode does.
set(BTF_GTEST_SUITES_LIST_SCRIPT "${CMAKE_CURRENT_LIST_DIR}/BtfGTestSuitesList.cmake")

function(btf_add_gtest_suites target label)
  set(list_file "${CMAKE_CURRENT_BINARY_DIR}/${target}_suites.cmake")
  set(include_file "${CMAKE_CURRENT_BINARY_DIR}/${target}_include.cmake")
  file(GENERATE OUTPUT "${include_file}" CONTENT
"# Written by BtfGTestSuites.cmake; read by ctest. The list is made again whenever the program or the
# script that lists it is newer than the list.
set(EXE [==[$<TARGET_FILE:${target}>]==])
if(NOT EXISTS \"\${EXE}\")
  add_test(${target}_NOT_BUILT ${target}_NOT_BUILT)
  return()
endif()
set(OUT [==[${list_file}]==])
set(SCRIPT [==[${BTF_GTEST_SUITES_LIST_SCRIPT}]==])
if(NOT EXISTS \"\${OUT}\" OR \"\${EXE}\" IS_NEWER_THAN \"\${OUT}\" OR \"\${SCRIPT}\" IS_NEWER_THAN \"\${OUT}\")
  set(TARGET [==[${target}]==])
  set(LABEL [==[${label}]==])
  set(WORKING_DIR [==[${CMAKE_CURRENT_BINARY_DIR}]==])
  include(\"\${SCRIPT}\")
endif()
include(\"\${OUT}\")
")
  set_property(DIRECTORY APPEND PROPERTY TEST_INCLUDE_FILES "${include_file}")
endfunction()
