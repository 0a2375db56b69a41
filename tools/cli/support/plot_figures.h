// The two pictures of `btf plot`, as display-ready sRGB images (values in [0, 1]).
#pragma once

#include <glm/glm.hpp>

#include "btf/io/image.h"
#include "btf/material/material.h"

namespace btf::cli {

struct SliceFigure {
  Image image;            // size x size, colour-mapped
  float log10_min = 0;    // value range of the colour map (log10 of luminance(f) * cos theta_i)
  float log10_max = 0;
};

// Axes of the slice: x = theta_h on the MERL table's square-root scale (x / size = sqrt(theta_h /
// 90 deg), which spreads out the specular peak as the table does), y = theta_d from 0 (bottom) to
// 90 deg (top), at phi_d = 90 deg (where every (theta_h, theta_d) pair is above the horizon).
// The colour map spans `decades` below the slice's maximum.
SliceFigure renderHalfDiffSlice(const Material& material, int size, float decades = 4.0f);
// Horizontal pixel position of theta_h (degrees) on the slice's axis.
int sliceColumnOf(float theta_h_deg, int size);

// A perceptually ordered dark-to-bright colour map, t in [0, 1].
Rgb colorMap(float t);

// An orthographic sphere seen from +z under one directional light of irradiance pi at normal
// incidence (so a white Lambertian surface facing the light shows its albedo), exposure in stops,
// then clamped and sRGB-encoded; 2x2 samples per pixel; dark grey background.
Image renderSpherePreview(const Material& material, int size, const glm::vec3& to_light, float exposure_stops);

}  // namespace btf::cli
