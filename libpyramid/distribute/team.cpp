#include "libpyramid/distribute/team.hpp"

#include <cstdlib>

#include "formats/error.hpp"
#include "libpyramid/distribute/team_module.hpp"
#include "libpyramid/support/module_loader.hpp"

#ifndef PYRAMID_MPI_MODULE_BUILD_PATH
#define PYRAMID_MPI_MODULE_BUILD_PATH ""
#endif

namespace pyramid {

namespace {

class Alone final : public Team {
public:
    int rank() const override { return 0; }
    int size() const override { return 1; }
    std::vector<Word> exchange(const Word& mine) override { return {mine}; }
    std::vector<std::string> gather(const std::string& mine) override { return {mine}; }
    std::string broadcast(const std::string& fromRoot) override { return fromRoot; }
};

#ifdef PYRAMID_WITH_MPI
const TeamModule* joined = nullptr; // the module, once the world is joined
Team* world = nullptr;

// mpirun (Open MPI, or a PMI launcher) tells its processes their place in the environment.
bool launchedByMpirun() {
    for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK"}) {
        if (std::getenv(name)) {
            return true;
        }
    }
    return false;
}

// The MPI module; throws when it cannot be loaded (a rank that ran alone would write the whole
// build beside the others).
const TeamModule& loadTeamModule() {
    using Entry = const TeamModule* (*)();
    // Global: Open MPI's own components, loaded by MPI_Init, find its libraries' symbols there.
    const LoadedModule loaded = loadModule({"libpyramid_mpi.so", "PYRAMID_MPI_MODULE", PYRAMID_MPI_MODULE_BUILD_PATH},
                                           "pyramid_team_module", true, [](void* entry) {
                                               const TeamModule* m = reinterpret_cast<Entry>(entry)();
                                               return m && m->abi == kTeamModuleAbi;
                                           });
    if (!loaded.entry) {
        throw Error("started by mpirun, but the MPI module cannot be loaded (" + loaded.why +
                    "; set PYRAMID_MPI_MODULE to its path)");
    }
    return *reinterpret_cast<Entry>(loaded.entry)();
}
#endif

} // namespace

Team& worldTeam() {
#ifdef PYRAMID_WITH_MPI
    if (world) {
        return *world;
    }
#endif
    static Alone alone;
    return alone;
}

TeamScope::TeamScope([[maybe_unused]] int& argc, [[maybe_unused]] char**& argv) {
#ifdef PYRAMID_WITH_MPI
    if (launchedByMpirun()) {
        const TeamModule& m = loadTeamModule();
        world = m.join(&argc, &argv);
        joined = &m;
    }
#endif
}

TeamScope::~TeamScope() {
#ifdef PYRAMID_WITH_MPI
    if (joined) {
        world = nullptr;
        joined->leave();
        joined = nullptr;
    }
#endif
}

bool teamsSupported() {
#ifdef PYRAMID_WITH_MPI
    return true;
#else
    return false;
#endif
}

} // namespace pyramid
