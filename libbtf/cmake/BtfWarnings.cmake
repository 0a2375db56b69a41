# Warnings and sanitizers applied to every target of the project (not to dependencies).
add_library(btf_warnings INTERFACE)
target_compile_options(btf_warnings INTERFACE -Wall -Wextra -Wpedantic)
if(BTF_SANITIZE)
  target_compile_options(btf_warnings INTERFACE -fsanitize=address,undefined -fno-omit-frame-pointer
                                                -fno-sanitize-recover=undefined)
  target_link_options(btf_warnings INTERFACE -fsanitize=address,undefined)
endif()
