// Counter-based random numbers: the value drawn is a pure function of (seed, stream, counter).
// Give every independent piece of work (pixel, table row, sample batch) its own stream index and
// results no longer depend on how the work is split across threads.
#pragma once

#include <glm/glm.hpp>

#include <cmath>
#include <cstdint>

#include "btf/core/math.h"

namespace btf {

// A strong 64-bit mixing function (the SplitMix64 finalizer).
constexpr std::uint64_t mix64(std::uint64_t x) {
  x ^= x >> 30;
  x *= 0xbf58476d1ce4e5b9ULL;
  x ^= x >> 27;
  x *= 0x94d049bb133111ebULL;
  x ^= x >> 31;
  return x;
}

class Rng {
 public:
  constexpr explicit Rng(std::uint64_t seed = 0, std::uint64_t stream = 0)
      : key_(mix64(seed ^ mix64(stream + 0x9e3779b97f4a7c15ULL))) {}

  constexpr std::uint64_t nextU64() { return mix64(key_ + 0x9e3779b97f4a7c15ULL * ++counter_); }
  // Uniform in [0, 1): the top 24 bits, so the result is exactly representable and never 1.
  constexpr float uniform() { return static_cast<float>(nextU64() >> 40) * 0x1p-24f; }
  // Uniform in [0, 1) with 53 bits.
  constexpr double uniformDouble() { return static_cast<double>(nextU64() >> 11) * 0x1p-53; }
  glm::vec2 uniform2D() {
    const float a = uniform();
    return {a, uniform()};
  }
  // Uniform integer in [0, n) (n > 0), by Lemire's multiply-shift (bias < 2^-32 for n < 2^32).
  constexpr std::uint32_t uniformInt(std::uint32_t n) {
    return static_cast<std::uint32_t>(((nextU64() >> 32) * n) >> 32);
  }
  // Jump to an absolute position in this stream.
  constexpr void seek(std::uint64_t counter) { counter_ = counter; }
  constexpr std::uint64_t position() const { return counter_; }

 private:
  std::uint64_t key_;
  std::uint64_t counter_ = 0;
};

// Standard normal deviates drawn from an Rng by Box-Muller, both deviates of each pair used (one
// log, sqrt and sin/cos per two). Like the Rng, a pure function of the stream: keep one per stream.
class NormalDeviates {
 public:
  explicit NormalDeviates(Rng& rng) : rng_(rng) {}
  float next() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    const float u1 = 1.0f - rng_.uniform(), u2 = rng_.uniform();  // u1 in (0, 1]: a finite log
    const float r = std::sqrt(-2.0f * std::log(u1)), phi = kTwoPi * u2;
    spare_ = r * std::sin(phi);
    has_spare_ = true;
    return r * std::cos(phi);
  }

 private:
  Rng& rng_;
  float spare_ = 0.0f;
  bool has_spare_ = false;
};

}  // namespace btf
