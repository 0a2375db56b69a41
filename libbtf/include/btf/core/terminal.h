// libbtf's log and progress hooks (progress.h) for a terminal program: a progress bar on stderr
// when it is a terminal, silence when it is not; warnings always go to stderr. What `btf` and
// `btf-datagen` install at start.
#pragma once

namespace btf {

// Installs libbtf's log and progress hooks for a terminal program.
void installTerminalHooks();

}  // namespace btf
