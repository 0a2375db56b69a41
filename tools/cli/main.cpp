// `btf`: inspect, evaluate, convert, plot, sample and benchmark measured materials.
#include <cstdint>
#include <cstdio>
#include <exception>

#include "btf/core/error.h"
#include "btf/io/image.h"
#include "commands.h"
#include "terminal.h"

int main(int argc, char** argv) {
  CLI::App app{"btf: measured BRDF/BTF toolkit (inspect, evaluate, convert, plot, sample, compress, bench)", "btf"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "btf 0.1.0");
  // Before the subcommand (`btf --max-image-pixels 300000000 render ...`): applied as it is parsed.
  app.add_option_function<std::uint64_t>(
         "--max-image-pixels",
         [](std::uint64_t pixels) {
           btf::ImageSizeLimits limits = btf::imageSizeLimits();
           limits.max_pixels = pixels;
           btf::setImageSizeLimits(limits);
         },
         "Largest image (width x height) any reader accepts; a header claiming more is refused as corrupt "
         "(default 67108864, 8192 x 8192)")
      ->check(CLI::PositiveNumber);
  btf::cli::registerInfoCommand(app);
  btf::cli::registerEvalCommand(app);
  btf::cli::registerConvertCommand(app);
  btf::cli::registerPlotCommand(app);
  btf::cli::registerSampleCommand(app);
  btf::cli::registerBenchCommand(app);
  btf::cli::registerCompressCommands(app);
  btf::cli::registerCompareCommand(app);
  btf::cli::registerRenderCommand(app);
  btf::cli::registerFitCommand(app);
  btf::cli::registerFitSceneCommand(app);
  btf::tools::installTerminalHooks();
  btf::decodeExrInCallingThreads();  // BTF folders are read many images at a time (btf/io/image.h)
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "btf: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
