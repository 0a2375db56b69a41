// Materials and sampler settings shared by the sampler tests (test_sampler_*.cpp).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "btf/material/ggx.h"
#include "btf/material/lambert.h"
#include "btf/material/phong.h"
#include "btf/material/tabulated_brdf.h"
#include "btf/material/ward.h"
#include "btf/sampling/binned_sampler.h"

namespace btf::test {

struct NamedMaterial {
  std::string label;
  std::shared_ptr<const Material> material;
};

// From diffuse to near-mirror, one anisotropic, one measured-style table (a GGX tabulated into the
// MERL layout, built once per process: 1.46 M evaluations).
inline const std::vector<NamedMaterial>& samplerTestMaterials() {
  static const std::vector<NamedMaterial> materials = [] {
    std::vector<NamedMaterial> m;
    m.push_back({"lambert", std::make_shared<Lambert>(Rgb(0.8f))});
    m.push_back({"phong_n20", std::make_shared<Phong>(Rgb(0.3f), Rgb(0.6f), 20.0f)});
    m.push_back({"ggx_a0.2", std::make_shared<Ggx>(Rgb(0.2f), Rgb(0.9f), 0.2f, 0.2f)});
    m.push_back({"ward_aniso", std::make_shared<Ward>(Rgb(0.1f), Rgb(0.6f), 0.08f, 0.35f)});
    m.push_back({"ggx_a0.02_near_mirror", std::make_shared<Ggx>(Rgb(0.0f), Rgb(0.95f), 0.02f, 0.02f)});
    const Ggx glossy(Rgb(0.3f, 0.2f, 0.1f), Rgb(0.5f), 0.15f, 0.15f);
    m.push_back({"merl_table_ggx_a0.15",
                 std::make_shared<TabulatedBrdf>(std::make_shared<MerlTable>(tabulate(glossy)))});
    return m;
  }();
  return materials;
}

// Coarse grids keep the suite fast; they change how well the density follows f, never whether
// sample() and pdf() agree, which is what the tests check. 20 x 40 cells in (cos theta_i, phi_i)
// put every jump of the tabulated densities on a boundary of the chi-square harness's cells when
// it uses 40 x 40 of them (kSamplerChi2ThetaBins; 20 rows on the upper hemisphere), for isotropic
// materials when phi_o = 0, where its quadrature converges at once.
inline constexpr int kSamplerChi2ThetaBins = 40;
inline constexpr int kSamplerChi2PhiBins = 40;
// Incident unless a test asks for Half (whose coarse grid is 32 x 32 cells of the half-vector
// square); Auto would build probes of both for every sampler.
inline SamplerOptions coarseSamplerOptions(Parameterization p = Parameterization::Incident) {
  SamplerOptions o;
  o.parameterization = p;
  o.half_vector_bins = 32;
  o.theta_o_bins = 8;
  o.phi_o_bins = 6;
  o.cos_theta_bins = 20;
  o.phi_bins = 40;
  o.supersampling = 2;
  o.min_depth = 2;
  o.max_depth = 7;
  o.quadtree_probes = 3;
  return o;
}

}  // namespace btf::test
