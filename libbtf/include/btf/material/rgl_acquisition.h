// Virtual acquisition: the measurement pipeline of Dupuy & Jakob 2018 ("An Adaptive
// Parameterization for Efficient Material Acquisition and Rendering", Sec. 4-5) run against a
// material libbtf can evaluate instead of a gonioreflectometer, producing the fields of an RGL
// `tensor_file` (.bsdf) that Mitsuba 3's `measured` plugin and libbtf's RglBrdf read.
//
// The steps, each on the file's unit coordinates (u_theta = sqrt(theta / (pi/2)), which is dense
// near the pole where glossy lobes are; u_phi = (phi + pi) / (2 pi)):
// 1. NDF: the back-scattering f(w, w) of a microfacet material with Smith masking is
//    F D(w) / (4 cos(theta) sigma(w)), where sigma(w) = int D(m) <m, w>+ dm is the projected area.
//    So D is the eigenvector of D(w) = k f(w, w) cos(theta) sigma_D(w), found by power iteration
//    from D = 1 (the paper's Sec. 4.1) on ndf_resolution theta nodes. The material is isotropic, so
//    the integral over phi_m is done in closed form; over theta_m by the midpoint rule on the
//    piecewise-linear D, 8 points per node interval. D is normalized so that sigma(normal) = 1.
//    The retro-reflection is measured as luminance (the paper measures at 532 nm).
// 2. sigma on the same nodes, from D.
// 3. theta_i: theta_i_count incidence angles placed uniformly in sigma from sigma(0) = 1 to
//    sigma(pi/2), as the RGL database places them (dense where the projected area changes).
// 4. vndf: per theta_i, D(m) <wi, m>+ / sigma(wi) times the Jacobian 2 pi^2 u_theta sin(theta_m)
//    of the unit square, on vndf_resolution^2 nodes: a density over the square whose warp draws m
//    with the visible-normal distribution.
// 5. Per theta_i and per node s of a resolution^2 grid: m = the VNDF warp of s, wr = the
//    reflection of wi about m, and the material measured there. `rgb` holds f cos(theta_r) divided
//    by the VNDF density D(m) / (4 sigma(wi)) (the file's `jacobian` flag is 1), which is smooth
//    where f follows the microfacet model; `luminance` holds its luminance, the density that the
//    sampling warp draws s with.
// 6. `wavelengths` and `spectra` (unless options.spectral is false): each RGB value of step 5
//    upsampled to a reflectance spectrum at 360, 370, ..., 830 nm by the sigmoid polynomials of
//    Jakob & Hanika 2019 with a scale per value (btf/core/rgb_to_spectrum.h): pbrt-v4's
//    MeasuredBRDF reads only these, Mitsuba 3's spectral variants too, its RGB variants read `rgb`.
//    Their colour under D65 (btf/core/cie.h) is the RGB value within 1e-5 of its largest channel.
// 7. `valid`: one bit per sample (theta_i, row, column; most significant bit first), set where the
//    reflected direction leaves the upper hemisphere and nothing was measured, as in the database's
//    files. No public loader reads it.
//
// Directions are evaluated at cos(theta) >= 1e-3: a material evaluated exactly at the horizon
// returns 0, which would leave the theta_i = 90 deg tables empty (a warp of no mass).
#pragma once

#include <string>
#include <vector>

#include "btf/io/rgl_tensor.h"
#include "btf/material/material.h"

namespace btf {

struct RglAcquisitionOptions {
  // The RGL database's resolutions.
  int theta_i_count = 8;      // incidence angles
  int ndf_resolution = 128;   // theta nodes of `ndf` and `sigma`
  int vndf_resolution = 128;  // nodes per side of each VNDF warp
  int resolution = 32;        // nodes per side of each luminance and RGB table
  std::string description;    // the file's `description`; empty: "virtual acquisition of <name>"
  bool spectral = true;       // write `wavelengths` and `spectra` (step 6) besides `rgb`
  // Steps 1 to 4 taken from this RGL file instead (its theta_i, ndf, sigma and vndf; the options'
  // resolutions of those are then unused): an RGL source re-measured on its own parameterization
  // keeps its tables at the nodes, up to float rounding.
  const TensorFile* parameterization = nullptr;
};

// Throws btf::Error naming the option for a resolution out of range: theta_i_count in [2, 90],
// ndf_resolution and vndf_resolution in [8, 1024], resolution in [4, 256].
void checkRglAcquisitionOptions(const RglAcquisitionOptions& options);

// The fields of the .bsdf file, in the order of the RGL database's files: version, description,
// phi_i, theta_i, sigma, ndf, vndf, luminance, rgb, wavelengths, spectra, jacobian, valid. Throws btf::Error for an
// anisotropic material (the file would hold its phi_h = 0 slice), options out of range, and a
// material whose eval returns a NaN, infinite or negative value (the message names the directions).
std::vector<TensorField> acquireRglFields(const Material& material, const RglAcquisitionOptions& options = {});

// The fields as a TensorFile in memory, as readTensorFile would return it (RglBrdf reads it);
// `label` stands for the path in messages.
TensorFile inMemoryTensorFile(std::vector<TensorField> fields, const std::string& label);

}  // namespace btf
