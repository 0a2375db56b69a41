# Warnings and sanitizers applied to every target of the project (not to dependencies).
add_library(btf_warnings INTERFACE)
target_compile_options(btf_warnings INTERFACE -Wall -Wextra -Wpedantic)
if(BTF_SANITIZE)
  target_compile_options(btf_warnings INTERFACE -fsanitize=address,undefined -fno-omit-frame-pointer
                                                -fno-sanitize-recover=undefined)
  target_link_options(btf_warnings INTERFACE -fsanitize=address,undefined)
endif()
if(BTF_BUILD_FUZZERS)
  if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    message(FATAL_ERROR "BTF_BUILD_FUZZERS needs clang (libFuzzer): configure with -DCMAKE_CXX_COMPILER=clang++")
  endif()
  # Coverage feedback for libFuzzer in the library; the targets link the fuzzer's main
  # (tests/fuzz/CMakeLists.txt). UBSan findings abort, so the fuzzer counts them as crashes.
  target_compile_options(btf_warnings INTERFACE -fsanitize=fuzzer-no-link,address,undefined
                                                -fno-sanitize-recover=undefined -fno-omit-frame-pointer)
  target_link_options(btf_warnings INTERFACE -fsanitize=address,undefined)
endif()
