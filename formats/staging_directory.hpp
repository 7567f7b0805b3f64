// A set of outputs that appear together (the files of an ortho pyramid, the six faces of a
// planet): they are written into a hidden staging directory inside the destination directory,
// `.staging-<pid>-<hex>/` (registered while it exists: formats/temporaries.hpp), each
// atomically as usual (but for the flush of its directory entry, which only the entry in the
// destination needs: step 5), and commit() puts the whole set in place, or none of it. Destroyed
// before commit(), the staging directory and everything in it are removed, so a run that
// fails at its fifth face leaves none of the first four behind, and so are the destination
// directory and its parents when this object created them and they are empty.
//
// commit(), under the registry's lock (a signal's cleanup waits for it to end):
//   1. a destination that exists and is not a file (a directory) fails the commit here, with
//      nothing moved (the staged files are on disk already: an AtomicFile's commit fsyncs
//      its file before renaming it into the staging tree, and every output goes through one);
//   2. each existing destination file is hard-linked into `.staging-…/.old/` (a backup that
//      costs no space; the destination itself is untouched);
//   3. the journal `.staging-…/.commit` (which destinations had an old file) is written,
//      fsync'd and renamed into place;
//   4. each staged file is renamed onto its destination (each rename is atomic: a destination
//      holds its old file or its new one); if one fails, the ones already moved are put back
//      (old files renamed back from `.old/`, new ones without an old one removed) and the
//      commit fails naming the file;
//   5. the destination directories are fsync'd;
//   6. the journal is removed (the set is committed from here on) and the staging directory
//      with it.
// What a crash (power loss, SIGKILL) at each step leaves: before 3 ends, the old outputs
// untouched and a stale staging directory; during 4 or 5, some outputs new and some old, and
// the journal, until the next run into the same directory finds the staging directory stale
// and rolls the set back to the old files (sweepStaleTemporaries, recover()); after 6 begins,
// the new outputs (and perhaps a stale staging directory, which the next run removes).
#pragma once
#include <string>
#include <vector>

#include "formats/output_paths.hpp"

namespace pyramid {

class StagingDirectory {
public:
    // Creates `destination` if needed and a fresh staging directory inside it. Throws Error
    // ("DIR: cannot create ...") when it cannot.
    explicit StagingDirectory(const std::string& destination);
    ~StagingDirectory();
    StagingDirectory(const StagingDirectory&) = delete;
    StagingDirectory& operator=(const StagingDirectory&) = delete;

    // Where to write the output whose final path is destination/relative.
    std::string path(const std::string& relative) const;
    const std::string& stagingPath() const { return staging_; }
    // Puts every regular file of the staging tree on the same relative path in the
    // destination, replacing what is there, all or nothing (the steps above); throws Error
    // naming the file that could not be put in place, with the old files back.
    void commit();

    // Rolls back the commit a stale staging directory's journal says was interrupted (step 4
    // or 5 above). True when the staging directory may now be removed: no journal, or every
    // old file back in place.
    static bool recover(const std::string& staging, const std::string& destination);

    // Tests only: makes the commit's rename number `index` (0-based, in the order of the
    // files' relative paths) fail as if the file system refused it; -1 turns this off.
    static void failRenameForTesting(int index);

private:
    std::string destination_;
    std::string staging_;
    OutputParents created_; // the directories made for the destination, kept by commit()
    bool keep_ = false; // a failed rollback: the old files are still in .old/
};

} // namespace pyramid
