// Test-side reference for the published MERL fits: a naive CSV reader (independent of
// btf/fit/merl_fits.h) and the three models written out straightforwardly from SOURCES.md, in
// double, so that the library's Sgd/Abc/Lafortune are checked against a second implementation.
#pragma once

#include <glm/glm.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "support/test_support.h"

namespace btf::test {

// One CSV row as column name -> text.
using CsvRecord = std::map<std::string, std::string>;

inline std::vector<CsvRecord> readCsvRecords(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open " + path.string());
  // The tables have CRLF line ends.
  auto split = [](std::string line) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::vector<std::string> out;
    std::stringstream ss(line);
    std::string field;
    while (std::getline(ss, field, ',')) out.push_back(field);
    if (!line.empty() && line.back() == ',') out.emplace_back();
    return out;
  };
  std::string line;
  std::getline(in, line);
  const std::vector<std::string> header = split(line);
  std::vector<CsvRecord> rows;
  while (std::getline(in, line)) {
    if (line.empty() || line == "\r") continue;
    const std::vector<std::string> fields = split(line);
    CsvRecord r;
    for (std::size_t i = 0; i < header.size(); ++i) r[header[i]] = i < fields.size() ? fields[i] : "";
    rows.push_back(r);
  }
  return rows;
}

inline std::filesystem::path fitsDir() { return sharedDataDir() / "fits"; }
inline double num(const CsvRecord& r, const std::string& column) { return std::stod(r.at(column)); }
inline const char* channelSuffix(int c) { return c == 0 ? "_r" : (c == 1 ? "_g" : "_b"); }

// SOURCES.md: f = (Kd + Ks F D G / (cos_i cos_o)) / pi, unclamped (the library clamps at 0).
inline double referenceSgd(const CsvRecord& r, int c, const glm::dvec3& i, const glm::dvec3& o) {
  auto p = [&](const char* name) { return num(r, std::string(name) + channelSuffix(c)); };
  const double pi = std::numbers::pi;
  const glm::dvec3 h = glm::normalize(i + o);
  const double cos_h = h.z, t2 = (1.0 - cos_h * cos_h) / (cos_h * cos_h);
  const double alpha = p("alpha"), s = alpha + t2 / alpha;
  const double d = p("kap") * std::exp(-s) / (pi * std::pow(s, p("p")) * std::pow(cos_h, 4));
  auto g1 = [&](const glm::dvec3& k) {
    const double theta = std::acos(k.z);
    return std::clamp(1.0 + p("lambda") * (1.0 - std::exp(p("c") * std::pow(std::max(0.0, theta - p("theta0")), p("k")))),
                      0.0, 1.0);
  };
  const double cos_d = glm::dot(i, h);
  const double f = p("f0") - cos_d * p("f1") + std::pow(1.0 - cos_d, 5) * (1.0 - p("f0"));
  return (p("rhoD") + p("rhoS") * f * d * g1(i) * g1(o) / (i.z * o.z)) / pi;
}

// SOURCES.md: f = Kd/pi + F D G / (pi cos_i cos_o), D = A / (1 + B (1 - cos_h))^C, G = min(1, ...),
// F the unpolarized Fresnel reflectance of a dielectric (textbook form with s and p polarizations).
inline double referenceAbc(const CsvRecord& r, int c, const glm::dvec3& i, const glm::dvec3& o) {
  const double pi = std::numbers::pi;
  const glm::dvec3 h = glm::normalize(i + o);
  const double d = num(r, std::string("A") + channelSuffix(c)) / std::pow(1.0 + num(r, "B") * (1.0 - h.z), num(r, "C"));
  const double g = std::min({1.0, 2.0 * h.z * i.z / glm::dot(h, i), 2.0 * h.z * o.z / glm::dot(h, o)});
  const double n = num(r, "ior"), cos_t = glm::dot(i, h);
  const double sin_t2 = (1.0 - cos_t * cos_t) / (n * n), cos_r = std::sqrt(1.0 - sin_t2);
  const double rs = (cos_t - n * cos_r) / (cos_t + n * cos_r), rp = (n * cos_t - cos_r) / (n * cos_t + cos_r);
  const double fresnel = 0.5 * (rs * rs + rp * rp);
  return num(r, std::string("kD") + channelSuffix(c)) / pi + fresnel * d * g / (pi * i.z * o.z);
}

// SOURCES.md: f = rho_d / pi + rho_s (n + 2) / (2 pi) / max(|Cxy|,|Cz|)^n (Cxy(ix ox + iy oy) + Cz iz oz)^n.
inline double referenceLafortune(const CsvRecord& r, int c, const glm::dvec3& i, const glm::dvec3& o) {
  const double pi = std::numbers::pi;
  const double cxy = num(r, "Cxy"), cz = num(r, "Cz"), n = num(r, "n");
  const double dot = cxy * (i.x * o.x + i.y * o.y) + cz * i.z * o.z;
  // (dot / max)^n rather than dot^n / max^n, which is 0 / 0 in double for n in the thousands.
  const double lobe = dot > 0 ? std::pow(dot / std::max(std::abs(cxy), std::abs(cz)), n) : 0.0;
  return num(r, std::string("rho_d") + channelSuffix(c)) / pi +
         num(r, std::string("rho_s") + channelSuffix(c)) * (n + 2.0) / (2.0 * pi) * lobe;
}

}  // namespace btf::test
