#include "libpyramid/distribute/team.hpp"

#include <cstdlib>
#include <algorithm>
#include <cstring>

#ifdef PYRAMID_WITH_MPI
#include <mpi.h>
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
class World final : public Team {
public:
    World() {
        MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
        MPI_Comm_size(MPI_COMM_WORLD, &size_);
    }
    int rank() const override { return rank_; }
    int size() const override { return size_; }
    std::vector<Word> exchange(const Word& mine) override {
        std::vector<Word> all(static_cast<size_t>(size_));
        MPI_Allgather(&mine, sizeof(Word), MPI_BYTE, all.data(), sizeof(Word), MPI_BYTE, MPI_COMM_WORLD);
        return all;
    }
    std::vector<std::string> gather(const std::string& mine) override {
        std::vector<char> line(kLine, '\0');
        std::memcpy(line.data(), mine.data(), std::min(mine.size(), kLine - 1));
        std::vector<char> all(rank_ == 0 ? kLine * static_cast<size_t>(size_) : 0);
        MPI_Gather(line.data(), static_cast<int>(kLine), MPI_CHAR, all.data(), static_cast<int>(kLine), MPI_CHAR, 0,
                   MPI_COMM_WORLD);
        std::vector<std::string> lines;
        for (int r = 0; rank_ == 0 && r < size_; ++r) {
            lines.emplace_back(all.data() + static_cast<size_t>(r) * kLine);
        }
        return lines;
    }
    std::string broadcast(const std::string& fromRoot) override {
        std::vector<char> line(kLine, '\0');
        if (rank_ == 0) {
            std::memcpy(line.data(), fromRoot.data(), std::min(fromRoot.size(), kLine - 1));
        }
        MPI_Bcast(line.data(), static_cast<int>(kLine), MPI_CHAR, 0, MPI_COMM_WORLD);
        return std::string(line.data());
    }

private:
    static constexpr size_t kLine = 4096;
    int rank_ = 0, size_ = 1;
};

std::unique_ptr<World> world;

// mpirun (Open MPI, or a PMI launcher) tells its processes their place in the environment.
bool launchedByMpirun() {
    for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK"}) {
        if (std::getenv(name)) {
            return true;
        }
    }
    return false;
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
        int provided = 0;
        MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
        world = std::make_unique<World>();
    }
#endif
}

TeamScope::~TeamScope() {
#ifdef PYRAMID_WITH_MPI
    if (world) {
        world.reset();
        MPI_Finalize();
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
