// Whether a progress bar's line is on stderr without its line end (Progress, ProgressMode::Bar,
// cli_progress.cpp): a message printed then (a stop on a signal, cli_program.cpp) starts on a
// line of its own.
#pragma once
#include <atomic>

namespace pyramid::cli {

extern std::atomic<bool> barLineOpen;

} // namespace pyramid::cli
