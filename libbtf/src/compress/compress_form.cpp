#include "btf/compress/compress_form.h"

#include <tbb/parallel_for.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>

#include <unistd.h>

#include "btf/core/error.h"
#include "btf/io/btf_subset.h"
#include "btf/io/container.h"

namespace btf {
namespace {

// The crop as a BtfData, by random access where the source allows it.
BtfData sampleOf(const BtfSource& source, int side) {
  const BtfRect rect = BtfSubset::centredRect(source, side, side);
  const auto* lookup = dynamic_cast<const BtfLookup*>(&source);
  if (!lookup) return BtfData::copyOf(BtfSubset(source, rect, source.views()));
  BtfData sample(rect.width, rect.height, source.name(), source.views());
  sample.setWhite(source.white());
  const BtfDirectionSet& set = source.directions();
  const std::vector<int>& views = source.views().views();
  tbb::parallel_for(std::size_t(0), views.size(), [&](std::size_t i) {
    const int v = views[i];
    for (int l = 0; l < set.lightCount(v); ++l)
      for (int y = 0; y < rect.height; ++y)
        for (int x = 0; x < rect.width; ++x) sample.at(x, y, v, l) = lookup->value(rect.x + x, rect.y + y, v, l);
  });
  return sample;
}

// A scratch file name beside nothing of the user's: the system's temporary folder.
std::filesystem::path scratchPath(const char* form) {
  static std::atomic<unsigned> counter{0};
  return std::filesystem::temp_directory_path() /
         ("libbtf-form-" + std::to_string(::getpid()) + "-" + std::to_string(counter++) + "-" + form + ".btfz");
}

struct Scratch {
  std::filesystem::path path;
  ~Scratch() {
    std::error_code ec;
    std::filesystem::remove(path, ec);
  }
};

}  // namespace

std::string compressFormName(CompressForm form) {
  switch (form) {
    case CompressForm::Auto: return "auto";
    case CompressForm::Vq: return "vq";
    case CompressForm::Factor: return "factor";
  }
  return "?";
}

CompressForm parseCompressForm(const std::string& name) {
  if (name == "auto") return CompressForm::Auto;
  if (name == "vq") return CompressForm::Vq;
  if (name == "factor") return CompressForm::Factor;
  throw Error("unknown compressed form '" + name + "' (choose auto, vq or factor)");
}

std::string formCandidateName(const FormCandidate& candidate) {
  if (candidate.form != CompressForm::Factor) return compressFormName(candidate.form);
  return "factor " + factorColorModelName(candidate.color_model);
}

const FormTrial& FormChoice::chosenTrial() const {
  for (const FormTrial& t : trials)
    if (t.candidate.form == chosen.form && t.candidate.color_model == chosen.color_model) return t;
  throw Error("FormChoice: no trial of the chosen form");
}

FormChoice chooseCompressForm(const BtfSource& source, const VqOptions& vq, const FactorOptions& factor,
                              const std::vector<FormCandidate>& candidates, int sample_side) {
  if (candidates.empty()) throw Error("chooseCompressForm: no candidate forms");
  const BtfData sample = sampleOf(source, sample_side);
  FormChoice choice;
  choice.sample_width = sample.width();
  choice.sample_height = sample.height();
  const double scale = double(source.texelCount()) / double(sample.texelCount());
  const FormTrial* best = nullptr;
  choice.trials.reserve(candidates.size());
  for (const FormCandidate& candidate : candidates) {
    const auto start = std::chrono::steady_clock::now();
    FormTrial t;
    t.candidate = candidate;
    Scratch file{scratchPath(candidate.form == CompressForm::Factor ? "factor" : "vq")};
    FactorOptions options = factor;
    options.color_model = candidate.color_model;
    try {
      if (candidate.form == CompressForm::Factor && factorFromSourceFactors(source, options)) {
        // Exact and cheap on the whole: its own bytes and its error measured on every entry.
        t.compressed = std::make_shared<const FactorBtf>(compressFactor(source, options));
        t.compressed->write(file.path);
        t.sample_bytes = std::filesystem::file_size(file.path);
        t.projected_bytes = double(t.sample_bytes);
        t.sample_rel_rmse = t.compressed->stats().measured_rel_rmse;
      } else if (candidate.form == CompressForm::Factor) {
        compressFactor(sample, options).write(file.path);
        t.sample_bytes = std::filesystem::file_size(file.path);
        t.sample_rel_rmse = compareBtf(sample, FactorBtf::read(file.path)).rel_rmse;
        // The basis (and the header) are paid once; the coefficients grow with the texels.
        double coefficient_bytes = 0;
        for (const ContainerSection& s : readContainer(file.path))
          if (s.name == "coefficients") coefficient_bytes = double(s.stored_bytes);
        t.projected_bytes = double(t.sample_bytes) + coefficient_bytes * (scale - 1.0);
      } else {
        compressVq(sample, vq).write(file.path);
        t.sample_bytes = std::filesystem::file_size(file.path);
        t.sample_rel_rmse = compareBtf(sample, VqBtf::read(file.path)).rel_rmse;
        t.projected_bytes = double(t.sample_bytes) * scale;
      }
    } catch (const Error& e) {
      t.failure = e.what();
    }
    t.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    choice.trials.push_back(t);
  }
  for (const FormTrial& t : choice.trials)
    if (t.failure.empty() && (!best || t.projected_bytes < best->projected_bytes)) best = &t;
  if (!best) {
    std::string why;
    for (const FormTrial& t : choice.trials) why += "; " + formCandidateName(t.candidate) + ": " + t.failure;
    throw Error(source.name() + ": no compressed form meets the options" + why);
  }
  choice.chosen = best->candidate;
  std::string text = formCandidateName(choice.chosen) + " (on a " + std::to_string(choice.sample_width) + " x " +
                     std::to_string(choice.sample_height) + " crop, scaled to the whole BTF:";
  for (const FormTrial& t : choice.trials) {
    char part[160];
    if (t.failure.empty())
      std::snprintf(part, sizeof part, " %s %.3g MB at rel_rmse %.4f%s;", formCandidateName(t.candidate).c_str(),
                    t.projected_bytes * 1e-6, t.sample_rel_rmse, t.whole() ? " (whole, its own factors)" : "");
    else
      std::snprintf(part, sizeof part, " %s out of reach;", formCandidateName(t.candidate).c_str());
    text += part;
  }
  text.back() = ')';
  choice.reason = text;
  return choice;
}

}  // namespace btf
