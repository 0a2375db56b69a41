// `btf`: inspect, convert, compress, sample, render and fit measured materials, and measure how
// libbtf's methods compare (`btf bench`).
#include <cstdint>
#include <cstdio>
#include <exception>

#include "bench_command.h"
#include "btf/core/error.h"
#include "btf/core/terminal.h"
#include "btf/io/atomic_file.h"
#include "btf/io/image.h"
#include "commands.h"

int main(int argc, char** argv) {
  CLI::App app{"btf: measured BRDF/BTF toolkit", "btf"};
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
  // `btf --help` lists the verbs by task. Each group is filled in the order its verbs register.
  const auto add = [&app](const char* group, void (*register_verb)(CLI::App&)) {
    register_verb(app);
    app.get_subcommands({}).back()->group(group);
  };
  add("Inspect", btf::cli::registerInfoCommand);
  add("Inspect", btf::cli::registerEvalCommand);
  add("Inspect", btf::cli::registerPlotCommand);
  add("Inspect", btf::cli::registerCompareCommand);
  add("Convert and compress", btf::cli::registerConvertCommand);
  add("Convert and compress", btf::cli::registerCompressCommand);
  add("Convert and compress", btf::cli::registerDecompressCommand);
  add("Convert and compress", btf::cli::registerMergeCommand);
  add("Convert and compress", btf::cli::registerExportCommand);
  add("Sample and render", btf::cli::registerSampleCommand);
  add("Sample and render", btf::cli::registerRenderCommand);
  add("Fit and select", btf::cli::registerFitCommand);
  add("Fit and select", btf::cli::registerFitSceneCommand);
  add("Experiments", btf::cli::registerBenchCommand);
  btf::installTerminalHooks();
  btf::removeTemporariesOnSignals();  // an interrupted write leaves no partial file
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
