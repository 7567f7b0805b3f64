// The temporaries a process has on disk, and the names that mark them as ours.
//
// Every temporary an output goes through (an AtomicFile's `OUT.tmp-<pid>-<hex>`, a
// StagingDirectory's `.staging-<pid>-<hex>/`, the output directories a run created) is in a
// process-wide registry while it exists. A program that is told to stop (a signal) calls
// removeTemporariesForExit() and ends: nothing a run made is left behind.
//
// Commits (the renames that put outputs in place) run under the registry's lock, and so does
// the removal: a commit in progress either finishes or rolls back before anything is removed,
// and none starts afterwards. The outputs are all old or all new, never a mix.
//
// The names carry the process id, so that a later run can tell a temporary whose process is
// gone (killed, crashed, the machine lost power) from one of a run still going:
// sweepStaleTemporaries() removes the former, and touches nothing else.
#pragma once
#include <mutex>
#include <string>

namespace pyramid {

enum class TemporaryKind {
    File,           // removed with unlink
    Tree,           // a directory removed with everything in it
    EmptyDirectory, // a directory removed only if empty (one the run created for its outputs)
};

// Holds the registry's lock (recursive: a commit may create or register temporaries while it
// holds it). Commits hold it from their first rename to their last.
std::unique_lock<std::recursive_mutex> lockTemporaries();

// Adds or removes a path. Register a name before creating it, under the lock, so that no
// moment exists when it is on disk but unknown.
void registerTemporary(const std::string& path, TemporaryKind kind);
void unregisterTemporary(const std::string& path);

// On a signal: takes the lock (waiting for a commit in progress to end), removes every
// registered temporary (files and trees first, retried while other threads may still be
// creating files in a tree, then the empty directories, deepest first), and keeps the lock
// for good, so that no commit starts afterwards. The caller then ends the process.
void removeTemporariesForExit();

// "<pid>-<8 hex digits>": the unique part of a temporary's name.
std::string temporaryTag();
// PATH.tmp-<pid>-<hex>: where an output is written before it is renamed onto PATH; with a
// `suffix` (".tif"), PATH.tmp-<pid>-<hex>.tif, for a writer that chooses the format by it.
std::string temporaryFileName(const std::string& path, const std::string& suffix = "");
// .staging-<pid>-<hex>: a staging directory's name.
std::string stagingDirectoryName();

// `path` as a user knows it: without the staging directory a file is written in
// ("out/.staging-12-ab34cd56/dxt/RGB.dat" -> "out/dxt/RGB.dat").
std::string outputName(const std::string& path);
// Whether `path` lies inside a staging directory (one of its components is a staging
// directory's name).
bool insideStagingDirectory(const std::string& path);

// Removes, in `directory`, the temporaries of runs that are gone: regular files named
// `NAME.tmp-<pid>-<hex>` (or `NAME.tmp-<pid>-<hex>.EXT`) and directories named `.staging-<pid>`
// or `.staging-<pid>-<hex>` whose process no longer exists (kill(pid, 0) fails with ESRCH). A
// staging directory that holds an interrupted commit's journal is rolled back first
// (staging_directory.hpp). Anything else, and the temporaries of live processes, is left alone.
// Returns how many were removed. Errors (an unreadable directory) are ignored: the sweep is
// housekeeping.
int sweepStaleTemporaries(const std::string& directory);

// The system's words for an errno value, in lower case: "no space left on device".
std::string systemWords(int error);

} // namespace pyramid
