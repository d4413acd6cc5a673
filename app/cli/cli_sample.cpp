// kcwarp-cli sample: the sample set of a cage over an image domain, its quality figures and,
// with --png, a picture of the samples coloured by kind (thesis Figs 6.6, 6.9).

#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <utility>
#include <nlohmann/json.hpp>

#include "cli_common.h"
#include "kc/app/errors.h"
#include "kc/app/file_io.h"
#include "kc/app/structure.h"
#include "kc/app/heatmap.h"
#include "kc/app/image_io.h"
#include "kc/app/limits.h"
#include "kc/app/session.h"
#include "kc/sampling/point_metrics.h"
#include "kc/sampling/sampler.h"
#include "kc/sampling/sigma.h"

namespace kc::cli {
namespace {

/// The defaults of the options: sampling::SamplingOptions' own.
const sampling::SamplingOptions kSampleDefaults{};

struct SampleArgs {
  std::string cage, image, size, output, png, sampler = nameOf(kSampleDefaults.kind), structure;
  double spacing = kSampleDefaults.spacing, margin = kSampleDefaults.margin;
  std::uint64_t seed = kSampleDefaults.seed;
  int pngCompression = app::kDefaultPngCompression;
};

/// The samples over the image (or a blank canvas), the picture padded by the sampling margin,
/// encoded as PNG.
std::string plotPng(const std::string& png, const Image* image, const Cage& cage, const SampleSet& S, int w, int h, double margin,
                    int pngCompression) {
  const int pad = static_cast<int>(std::ceil(std::max(0.0, margin)));
  Image canvas(w + 2 * pad, h + 2 * pad, Rgba{235, 235, 235, 255});
  if (image) {
    const Image& img = *image;
    for (int y = 0; y < img.height; ++y)
      for (int x = 0; x < img.width; ++x)
        for (int c = 0; c < 4; ++c)
          canvas.rgba[4 * (static_cast<std::size_t>(y + pad) * canvas.width + (x + pad)) + c] =
              img.rgba[4 * (static_cast<std::size_t>(y) * img.width + x) + c];
  } else {
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        for (int c = 0; c < 4; ++c) canvas.rgba[4 * (static_cast<std::size_t>(y + pad) * canvas.width + (x + pad)) + c] = 255;
  }
  SampleSet shifted = S;
  shifted.X.rowwise() += Eigen::RowVector2d(pad, pad);
  Cage shiftedCage = cage;
  shiftedCage.C.rowwise() += Eigen::RowVector2d(pad, pad);
  app::drawCage(canvas, shiftedCage, Rgba{60, 60, 60, 255});
  app::drawSamples(canvas, shifted);
  return app::encodeImage(canvas, app::imageExtension(png), pngCompression);
}

void runSample(const SampleArgs& a) {
  const Cage cage = app::loadCage(a.cage);
  std::optional<Image> image;
  if (!a.image.empty()) image = app::loadImage(a.image);
  const auto [w, h] = image ? std::pair{image->width, image->height} : parseSize(a.size, "--size");
  requireFinite(a.spacing, "--spacing");
  requireFinite(a.margin, "--margin");
  app::OutputBatch outputs;
  outputs.reserve(a.output);
  if (!a.png.empty()) {
    app::imageExtension(a.png);  // InputError on an extension kcwarp cannot write
    outputs.reserve(a.png);
  }

  sampling::SamplingOptions o;
  o.spacing = a.spacing;
  o.width = w;
  o.height = h;
  o.margin = a.margin;
  o.seed = a.seed;
  o.kind = parseOption<sampling::SamplerKind>(a.sampler, "--sampler");
  if (!a.structure.empty()) {
    const app::Structure st = app::loadStructure(a.structure);
    app::checkStructure(st, cage, a.spacing, a.structure);
    o.lines = st.lines;
  }
  if (stderrIsTerminal())
    o.progress = [](double f) {
      std::fprintf(stderr, "\rrelaxing samples %3.0f%%", 100.0 * f);
      if (f >= 1.0) std::fprintf(stderr, "\n");
      return true;
    };
  if (!a.png.empty()) {
    const std::int64_t pad = 2 * static_cast<std::int64_t>(std::ceil(std::max(0.0, std::min(sampling::resolvedMargin(o), 1e9))));
    app::checkImageSize(w + pad, h + pad, a.png, "sample plot");
  }
  sampling::SamplingReport rep;
  const SampleSet S = app::asUserInput(a.cage, [&] { return sampling::sample(cage, o, &rep); });
  const Index fixed = rep.controls + rep.edge + rep.line + rep.frame;
  const sampling::PointSetMetrics q = sampling::pointSetMetrics(S.X, a.spacing, sampling::samplingDomain(o), fixed);
  const double sigma = sampling::suggestSigma(S);
  const nlohmann::json extra = {
      {"spacing", a.spacing},
      {"sigma", sigma},
      {"image_size", {w, h}},
      {"counts",
       {{"control", rep.controls}, {"edge", rep.edge}, {"line", rep.line}, {"frame", rep.frame}, {"interior", rep.interior}, {"exterior", rep.exterior}}},
      {"metrics", {{"separation", q.separation}, {"fill", q.fill}, {"nn_mean", q.nnMean}, {"nn_cv", q.nnCv}}},
      {"iterations", rep.iterations}};
  outputs.set(a.output, app::samplesText(S, extra.dump()));
  if (!a.png.empty())
    outputs.set(a.png, plotPng(a.png, image ? &*image : nullptr, cage, S, w, h, sampling::resolvedMargin(o), a.pngCompression));
  outputs.commit();
  std::printf("%ld samples: %ld control, %ld edge, %ld frame, %ld interior, %ld exterior (%d relaxation iterations, %.3f s)\n",
              static_cast<long>(S.size()), static_cast<long>(rep.controls), static_cast<long>(rep.edge),
              static_cast<long>(rep.frame), static_cast<long>(rep.interior), static_cast<long>(rep.exterior), rep.iterations,
              rep.seconds);
  std::printf("free samples: separation %.3f h, fill distance %.3f h, nearest-neighbour CV %.3f; suggested sigma %.4g px\n",
              q.separation, q.fill, q.nnCv, sigma);
}

}  // namespace

void addSampleCommand(CLI::App& app) {
  auto a = std::make_shared<SampleArgs>();
  CLI::App* sub = app.add_subcommand("sample", "Sample a cage and its image domain; write the samples (and a picture)");
  sub->add_option("--cage", a->cage, "Cage file (JSON)")->required();
  auto* image = sub->add_option("--image", a->image, "Image the cage is drawn over");
  auto* size = sub->add_option("--size", a->size, "Domain size W,H in pixels (instead of --image)");
  image->excludes(size);
  sub->add_option("--spacing", a->spacing, "Sample spacing h in pixels")->capture_default_str();
  sub->add_option("--sampler", a->sampler, "blue-noise | grid")->capture_default_str();
  sub->add_option("--margin", a->margin, "Sampled margin around the image in pixels (<0 = automatic)");
  sub->add_option("--seed", a->seed, "Random seed (0..2^64-1)")->check(seedCheck())->capture_default_str();
  sub->add_option("--structure", a->structure, "Structure file (JSON): lines sampled and kept fixed");
  sub->add_option("-o,--output", a->output, "Samples file to write (JSON)")->required();
  sub->add_option("--png", a->png, "Also draw the samples, coloured by kind, into this PNG");
  addPngCompressionOption(sub, a->pngCompression);
  sub->callback([a] {
    if (a->image.empty() && a->size.empty()) throw app::InputError("sample", "give --image I.png or --size W,H");
    runSample(*a);
  });
}

}  // namespace kc::cli
