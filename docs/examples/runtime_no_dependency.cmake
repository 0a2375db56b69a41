# ctest script (docs/examples/CMakeLists.txt): the runtime needs the C++17 standard library and
# nothing else. Builds the runtime example from the runtime's own sources with nothing but
# -std=c++17 (no CMake target, no include path but the runtime's), then lists the shared libraries
# the program needs (readelf -d): only the C and C++ runtime libraries may appear.
# Expects CXX, RUNTIME_DIR (runtime/), EXAMPLE (the .cpp), OUT (the program to write), READELF.
file(GLOB sources "${RUNTIME_DIR}/src/*.cpp")
execute_process(COMMAND "${CXX}" -std=c++17 -O2 -ffp-contract=off -Wall -Wextra -Werror -pedantic
                        -I "${RUNTIME_DIR}/include" ${sources} "${EXAMPLE}" -o "${OUT}"
                RESULT_VARIABLE built OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT built EQUAL 0)
  message(FATAL_ERROR "the runtime and its example do not build with -std=c++17 alone:\n${out}${err}")
endif()
foreach(program IN ITEMS "${OUT}" ${TARGET_PROGRAM})
  execute_process(COMMAND "${READELF}" -d "${program}" RESULT_VARIABLE read OUTPUT_VARIABLE dynamic ERROR_VARIABLE err)
  if(NOT read EQUAL 0)
    message(FATAL_ERROR "readelf -d ${program} failed: ${err}")
  endif()
  string(REGEX MATCHALL "Shared library: \\[[^]]+\\]" needed "${dynamic}")
  foreach(entry IN LISTS needed)
    string(REGEX REPLACE "Shared library: \\[([^]]+)\\]" "\\1" library "${entry}")
    if(NOT library MATCHES "^(libstdc\\+\\+|libm|libgcc_s|libc|ld-linux[-a-z0-9_]*)\\.so")
      message(FATAL_ERROR "${program} needs ${library}: the runtime must need only the C and C++ runtime libraries")
    endif()
    message(STATUS "${program} needs ${library}")
  endforeach()
endforeach()
