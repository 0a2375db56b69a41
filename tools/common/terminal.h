// Terminal output of the command-line tools: a progress bar on stderr when it is a terminal,
// silence when it is not; warnings always go to stderr.
#pragma once

namespace btf::tools {

// Installs libbtf's log and progress hooks for a terminal program.
void installTerminalHooks();

}  // namespace btf::tools
