// libpyramid_mpi.so: the ranks of an MPI run as a Team (distribute/team_module.hpp). Only the
// C API of MPI is used.
#include <mpi.h>

#include <algorithm>
#include <cstring>
#include <memory>

#include "libpyramid/distribute/team_module.hpp"

namespace pyramid {

namespace {

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

Team* join(int* argc, char*** argv) {
    int provided = 0;
    MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided);
    world = std::make_unique<World>();
    return world.get();
}

void leave() {
    world.reset();
    MPI_Finalize();
}

} // namespace

} // namespace pyramid

extern "C" __attribute__((visibility("default"))) const pyramid::TeamModule* pyramid_team_module() {
    static const pyramid::TeamModule module{pyramid::kTeamModuleAbi, &pyramid::join, &pyramid::leave};
    return &module;
}
