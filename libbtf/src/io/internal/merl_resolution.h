// The MERL table's resolutions under the short names that its index formulas use (theta_h, theta_d,
// phi_d), shared by the sources that index the table so that each does not define them again.
#pragma once

#include "btf/io/merl.h"

namespace btf {

inline constexpr int kNh = MerlTable::kThetaHalfRes;
inline constexpr int kNd = MerlTable::kThetaDiffRes;
inline constexpr int kNp = MerlTable::kPhiDiffRes;

}  // namespace btf
