// The processes of one build: this process alone, or the ranks of an MPI run when libpyramid is
// built with Open MPI (PYRAMID_WITH_MPI) and the program is started by mpirun (doc/planet-scale.md).
// A build's ranks talk only through the few collective steps below, which every rank takes in the
// same order; the tiles travel through part files on the shared filesystem.
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace pyramid {

class Team {
public:
    virtual ~Team() = default;
    virtual int rank() const = 0;
    virtual int size() const = 0;

    // One rank's word at a collective step: whether it failed, and an overflow it found.
    struct Word {
        int32_t failed = 0;
        int32_t hasOverflow = 0;
        int32_t level = 0;
        int32_t unused = 0;
        int64_t residual = 0;
        int64_t position = 0;
        double scale = 0.0;
    };
    // Every rank gives its word; every rank gets all of them, by rank.
    virtual std::vector<Word> exchange(const Word& mine) = 0;
    // Every rank gives a line; rank 0 gets all of them, by rank (the others get nothing).
    virtual std::vector<std::string> gather(const std::string& mine) = 0;
    // Rank 0's text, on every rank.
    virtual std::string broadcast(const std::string& fromRoot) = 0;
};

// The team this process belongs to: the MPI world while a TeamScope is open in an MPI run, else a
// team of one.
Team& worldTeam();

// Joins the MPI world for the program's lifetime when the program was started by mpirun (the
// launcher's environment says so) and libpyramid was built with MPI, through the MPI module
// (team_module.hpp); does nothing otherwise. Throws Error when mpirun started the program but
// the module cannot be loaded.
class TeamScope {
public:
    TeamScope(int& argc, char**& argv);
    ~TeamScope();
    TeamScope(const TeamScope&) = delete;
    TeamScope& operator=(const TeamScope&) = delete;
};

// Whether this build of libpyramid can run under mpirun.
bool teamsSupported();

} // namespace pyramid
