# ctest fixture script (docs/examples/CMakeLists.txt): the runtime example's input, made as a user
# makes it: a synthetic 8 x 8 BTF, compressed to a .btfz, exported for the runtime.
# Expects DATAGEN, BTF (the programs) and OUT (a folder).
file(REMOVE_RECURSE "${OUT}")
file(MAKE_DIRECTORY "${OUT}")
foreach(step IN ITEMS
        "${DATAGEN};btf;--pattern;stones;--size;8;--format;exr;-o;${OUT}/stones"
        "${BTF};compress;${OUT}/stones;${OUT}/stones.btfz"
        "${BTF};export;--runtime;${OUT}/stones.btfz;${OUT}/stones.btfrt")
  execute_process(COMMAND ${step} RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT status EQUAL 0)
    message(FATAL_ERROR "${step} failed (${status}):\n${out}${err}")
  endif()
endforeach()
