// How compressible a BTF is at a given tolerance, measured on the data itself rather than on any
// one compressor: "where does it break" for every method.
//
// Each texel is the vector of its luminances (Rgb::luminance) over D of the 6561 (view, light)
// pairs, chosen at random by seed (a T x D matrix, T = texels). (Of a BTF holding only some views,
// or on another direction set, its pairs: read 6561 below as their number.) Three measures:
//
// 1. Nearest neighbour. The scale-optimal relative distance of texel x to texel y is
//      d(x, y) = min_s |x - s y| / |x| = sqrt(1 - cos^2(x, y)),
//    i.e. the relative error of coding x as a scaled copy of y (a texel of zero luminance is coded
//    exactly by any texel, d = 0). For every texel the nearest other texel: quantiles of d, and the
//    energy-weighted global relative error if every texel were replaced by its scaled nearest
//    neighbour, sqrt(sum |x_t|^2 d_t^2 / sum |x_t|^2) (the rel_rmse of that replacement, luminance
//    only). If this median is far above epsilon, no texel can reuse another at epsilon.
//    With D < 6561 the distances are estimates over a sample of directions, and the minimum over
//    all neighbours picks the ones the sample happens to underestimate: d is biased low (optimistic),
//    the more so the smaller D (`btf bench compressibility --directions 0` measures with all 6561).
//
// 2. Greedy one-pass texel codebook, per epsilon: texels in row-major order; a texel reuses the
//    best earlier *entry* (smallest d) if d <= epsilon, else becomes an entry. Entries and the
//    resulting energy-weighted global relative error. This is what texel-level (level-3) reuse of
//    a one-pass scaled-codebook VQ whose entries are texels can find at that tolerance: the reuse
//    shrinks storage by at most texels / entries over coding every texel on its own. Codebooks of
//    centroids or an optimal clustering could do somewhat better, but not beyond what the distances
//    of measure 1 allow: d = sin(angle), angles obey the triangle inequality, so two texels farther
//    apart than sin(2 asin(epsilon)) ~ 2 epsilon can share no entry, centroid or not.
//
// 3. Linear-basis bound: the singular values s_i of the T x D matrix. Per epsilon, the smallest
//    rank k with sqrt(sum_{i>k} s_i^2 / sum_i s_i^2) <= epsilon (the Eckart-Young error of the best
//    rank-k model, luminance only), and the ratio of such a model stored as float16 coefficients
//    (T x k) and basis (k x 6561):
//      ratio_u8_bound = (T * 6561 * 3 bytes) / (2 bytes * k * (T + 6561)).
//    Optimistic, i.e. a bound from above on what a rank-k linear model achieves:
//      - colour is ignored: the model stores luminance only, yet is credited with the 3 bytes of RGB
//        per entry (an RGB model needs at least as many components and more bytes);
//      - k is measured on D sampled directions, the basis is charged for all 6561: a random column
//        subset has, in expectation, the relative tail energy of the full matrix's best rank-k
//        space *or less* (the best rank-k space of the subset fits the subset at least as well),
//        and the rank of a T x D matrix can never exceed D, so k is biased low, the more so the
//        smaller D is relative to k;
//      - no mean row, quantization error of float16, or headers are counted.
//
// Cost: O(T^2 D) brute force (all pairs, TBB-parallel over fixed blocks of rows, candidates ranked
// in float, the chosen neighbour or entry measured exactly in double), plus one symmetric
// eigen-decomposition of size min(T, D). Fine up to 64 x 64 texels and usable to 128 x 128
// (kMaxCompressibilityTexels), where the quadratic cost dominates. Memory: T x D floats plus a block
// of rows against all texels.
// Views are streamed with loadView one at a time, in order.
//
// Deterministic: the same source, seed and options give the same report for any thread count
// (every row's result depends only on the data; sums run in a fixed order).
#pragma once

#include <cstdint>
#include <vector>

#include "btf/io/btf_data.h"

namespace btf {

// Texels the brute-force analysis accepts (128 x 128): beyond that use a smaller BTF (a crop).
inline constexpr int kMaxCompressibilityTexels = 16384;

struct CompressibilityOptions {
  // (view, light) pairs sampled at random from the 6561; 0 or >= 6561: all of them.
  int directions = 1024;
  std::uint64_t seed = 1;
  // Tolerances of the greedy codebook and the rank bound, each in (0, 1).
  std::vector<double> epsilons = {0.02, 0.05, 0.1, 0.2};
};

struct CompressibilityAtEpsilon {
  double epsilon = 0;
  int greedy_entries = 0;          // texel codebook entries of the greedy pass
  double greedy_rel_error = 0;     // energy-weighted global relative error of the greedy coding
  int rank = 0;                    // smallest k with relative tail energy <= epsilon
  double rank_rel_error = 0;       // sqrt(sum_{i>k} s_i^2 / sum s_i^2) at that k
  double ratio_u8_bound = 0;       // formula above (+infinity for k = 0)
};

struct CompressibilityReport {
  int texels = 0, directions = 0;  // T and D
  // Per texel (row-major y * width + x): distance to and index of the nearest other texel.
  std::vector<double> nearest_distance;
  std::vector<int> nearest_texel;
  // Quantiles of nearest_distance (linear interpolation between order statistics, h = (T-1) p).
  double nn_p10 = 0, nn_p25 = 0, nn_p50 = 0, nn_p75 = 0, nn_p90 = 0, nn_max = 0;
  double nn_rel_error = 0;  // energy-weighted, as above
  std::vector<double> singular_values;  // min(T, D) values, largest first
  // Relative error of the best rank-k model, sqrt(sum_{i>k} s_i^2 / sum s_i^2) (1-based i), for
  // k = 0 .. min(T, D): the curve each epsilon's rank is read from.
  std::vector<double> rank_rel_error;
  std::vector<CompressibilityAtEpsilon> at_epsilon;  // in the order of options.epsilons
};

// Throws btf::Error for fewer than 2 or more than kMaxCompressibilityTexels texels, a negative
// direction count, an epsilon outside (0, 1), or a BTF whose luminance is zero at every chosen
// direction; passes on the source's errors. Reports progress (views read, rows searched).
CompressibilityReport analyzeCompressibility(const BtfSource& source, const CompressibilityOptions& options = {});

// The ratio_u8 bound of a rank-k float16 model of T texels over `pairs` (view, light) pairs (formula
// above); +infinity for k = 0.
double rankRatioU8Bound(int texels, int rank, int pairs = kBtfDirectionCount * kBtfDirectionCount);

}  // namespace btf
