#include "btf/core/half_diff.h"

#include <cmath>
#include <numbers>

namespace btf {
namespace {

// The transform runs in double: in float, normalize(wi + wo) loses accuracy for nearly opposite
// pairs, and angles near the pole need atan2 rather than acos (acos is ill-conditioned at 1).
using Vec = glm::dvec3;

Vec rotateZ(const Vec& v, double a) {
  const double c = std::cos(a), s = std::sin(a);
  return {c * v.x - s * v.y, s * v.x + c * v.y, v.z};
}
Vec rotateY(const Vec& v, double a) {
  const double c = std::cos(a), s = std::sin(a);
  return {c * v.x + s * v.z, v.y, -s * v.x + c * v.z};
}
double thetaOf(const Vec& v) { return std::atan2(std::hypot(v.x, v.y), v.z); }
double phiOf(const Vec& v) {
  const double phi = std::atan2(v.y, v.x);
  return phi < 0 ? phi + 2 * std::numbers::pi : phi;
}
Vec direction(double theta, double phi) {
  const double s = std::sin(theta);
  return {s * std::cos(phi), s * std::sin(phi), std::cos(theta)};
}

}  // namespace

HalfDiff toHalfDiff(const glm::vec3& wi_f, const glm::vec3& wo_f) {
  const Vec wi = glm::normalize(Vec(wi_f)), wo = glm::normalize(Vec(wo_f));
  const Vec h = glm::normalize(wi + wo);
  const double theta_h = thetaOf(h), phi_h = phiOf(h);
  const Vec d = rotateY(rotateZ(wi, -phi_h), -theta_h);
  return {float(theta_h), float(phi_h), float(thetaOf(d)), float(phiOf(d))};
}

DirectionPair fromHalfDiff(const HalfDiff& hd) {
  const Vec h = direction(hd.theta_h, hd.phi_h);
  const Vec d = direction(hd.theta_d, hd.phi_d);
  const Vec wi = rotateZ(rotateY(d, hd.theta_h), hd.phi_h);
  const Vec wo = 2.0 * glm::dot(wi, h) * h - wi;
  return {glm::vec3(wi), glm::vec3(wo)};
}

}  // namespace btf
