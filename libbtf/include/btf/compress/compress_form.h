// Which compressed form a BTF gets: the multi-level VQ codebooks (vq_btf.h) or the quantized
// factorisation (factor_btf.h), chosen by measuring both on a sample of the BTF.
//
// Where the codebooks pay and where they do not depends on the data: VQ stores a code per texel
// and level and an entry per distinct light slice, so it wins where texels repeat (woven, printed,
// synthetic materials) and loses where every texel is its own (camera noise, small texel counts
// with many lights per ring, and every Bonn file, which is already a factorisation). The choice
// compresses a centred crop of the BTF (all its views) in each form (the factor form in both
// colour models) at the same options, scales
// each file to the whole texel count (the factor form's basis is paid once, its coefficients per
// texel; VQ's bytes grow at most linearly with the texels, so the scaled VQ bytes are an upper
// estimate) and keeps the smaller. A candidate that re-codes the source's own factors (a DFMF
// file in the log-luminance model, factorFromSourceFactors) is measured on the whole source
// instead: it costs no pass over decoded values, and a crop would be factorised anew, which on
// noisy data needs more components than any sketch holds and so misses what the file itself meets.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "btf/compress/factor_btf.h"
#include "btf/compress/vq_btf.h"

namespace btf {

enum class CompressForm { Auto, Vq, Factor };
// "auto", "vq", "factor"; parse throws btf::Error naming the choices.
std::string compressFormName(CompressForm form);
CompressForm parseCompressForm(const std::string& name);

// A form to try: VQ, or the factor form in one colour model.
struct FormCandidate {
  CompressForm form = CompressForm::Vq;
  FactorColorModel color_model = FactorColorModel::Linear;  // of the factor form
};
std::string formCandidateName(const FormCandidate& candidate);  // "vq", "factor linear", "factor log-luminance"

struct FormTrial {
  FormCandidate candidate;
  std::string failure;              // why the form cannot meet the options on the sample (then no figures)
  std::uint64_t sample_bytes = 0;   // the sample's file
  double sample_rel_rmse = 0;       // the sample's decoded values against the sample
  double projected_bytes = 0;       // scaled to the whole BTF
  double seconds = 0;
  // Set when the trial ran on the whole BTF (the sample figures are then the whole's): the
  // compressed BTF itself, what to write.
  std::shared_ptr<const FactorBtf> compressed;
  bool whole() const { return compressed != nullptr; }
};

struct FormChoice {
  FormCandidate chosen;
  int sample_width = 0, sample_height = 0;  // the crop measured
  std::vector<FormTrial> trials;            // in the order tried
  std::string reason;                       // one line for reports
  const FormTrial& chosenTrial() const;     // the trial of `chosen`
};

// Texels per side of the crop measured (at most; the whole BTF when it is smaller).
inline constexpr int kFormSampleSide = 32;

// Measures each candidate on the crop (read through BtfLookup::value where the source is one, so a
// Bonn file decodes only the crop; otherwise view by view) and chooses the smallest projected file
// among those that meet the options. Throws btf::Error when none does (naming each one's failure).
FormChoice chooseCompressForm(const BtfSource& source, const VqOptions& vq, const FactorOptions& factor,
                              const std::vector<FormCandidate>& candidates, int sample_side = kFormSampleSide);

}  // namespace btf
