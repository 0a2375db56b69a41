// What the library's hand-written AVX2 paths share (sampling/dp_cdf_batch.cpp, compress/vq_stream.cpp):
// the attribute that compiles one function for AVX2 (and not FMA, so that no multiply-add is fused
// and the lanes round as the scalar code does), and the run-time check that chooses them.
#pragma once

#define BTF_AVX2 __attribute__((target("avx2")))

namespace btf {

inline bool cpuHasAvx2() {
  static const bool has = __builtin_cpu_supports("avx2");
  return has;
}

}  // namespace btf
