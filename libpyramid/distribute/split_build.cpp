#include "libpyramid/distribute/split_build.hpp"

#include <exception>
#include <filesystem>
#include <memory>

#include "formats/output_paths.hpp"
#include "formats/staging_directory.hpp"

namespace pyramid {

std::string runPart(int index, int count, const std::string& base, const std::string& format, const nlohmann::json& job,
                    const PartEncode& encode) {
    if (count < 1 || index < 0 || index >= count) {
        failOption("part", "must be I/N with 0 <= I < N, not " + std::to_string(index) + "/" + std::to_string(count));
    }
    OutputParents parents; // an output directory not made yet, removed again if the part fails
    prepareOutputFile(partFileName(base, index, count), parents);
    PartOutput out(partFileName(base, index, count), format, index, count, job);
    PartContext share;
    share.index = index;
    share.count = count;
    share.out = &out;
    encode(share);
    out.commit();
    parents.keep();
    return out.path();
}

namespace {

// Where the team's failure stops a rank inside the encoding.
struct FailureSeen {};

} // namespace

void runTeam(Team& team, const std::string& directory, const std::string& partName, const std::string& format,
             const nlohmann::json& job, const std::function<void()>& prepare, const PartEncode& encode,
             const std::function<void(const std::vector<std::string>&)>& merge) {
    const int rank = team.rank(), size = team.size();
    std::exception_ptr error; // this rank's own failure
    std::string message;
    const auto failHere = [&] {
        error = std::current_exception();
        try {
            std::rethrow_exception(error);
        } catch (const std::exception& e) {
            message = e.what();
        } catch (...) {
            message = "unknown error";
        }
    };

    // Rank 0 checks the outputs and makes the parts' directory; every rank learns where it is.
    std::unique_ptr<StagingDirectory> parts;
    std::string said;
    if (rank == 0) {
        try {
            prepare();
            parts = std::make_unique<StagingDirectory>(directory);
            said = "ok\n" + parts->stagingPath();
        } catch (...) {
            failHere();
            said = "error\n" + message;
        }
    }
    said = team.broadcast(said);
    if (said.rfind("ok\n", 0) != 0) {
        if (rank == 0) {
            std::rethrow_exception(error);
        }
        throw TeamFailed();
    }
    const std::string partsDirectory = said.substr(3);

    // Every rank encodes its share; the encoder's agreements are collective steps, and a failure
    // takes the place of a rank's next step, so every rank sees it at the same step.
    bool seen = false;
    try {
        PartOutput out((std::filesystem::path(partsDirectory) / partFileName(partName, rank, size)).string(), format,
                       rank, size, job);
        PartContext share;
        share.index = rank;
        share.count = size;
        share.out = &out;
        share.agree = [&](const std::optional<ResidualOverflow>& mine) -> std::optional<ResidualOverflow> {
            Team::Word word;
            if (mine) {
                word.hasOverflow = 1;
                word.level = mine->level;
                word.residual = mine->residual;
                word.position = mine->position;
                word.scale = mine->scale;
            }
            std::optional<ResidualOverflow> first;
            for (const Team::Word& w : team.exchange(word)) {
                if (w.failed) {
                    seen = true;
                }
                if (w.hasOverflow && (!first || w.position < first->position)) {
                    first = ResidualOverflow{w.scale, w.residual, w.level, w.position};
                }
            }
            if (seen) {
                throw FailureSeen{};
            }
            return first;
        };
        encode(share);
        out.commit();
    } catch (const FailureSeen&) {
    } catch (...) {
        failHere();
    }
    if (!seen) {
        Team::Word word;
        word.failed = error ? 1 : 0;
        for (const Team::Word& w : team.exchange(word)) {
            seen = seen || w.failed;
        }
    }
    if (seen) {
        const std::vector<std::string> lines = team.gather(error ? message : std::string());
        if (rank != 0) {
            throw TeamFailed();
        }
        if (error) {
            std::rethrow_exception(error);
        }
        for (int r = 0; r < size; ++r) {
            if (!lines[static_cast<size_t>(r)].empty()) {
                fail("rank " + std::to_string(r), lines[static_cast<size_t>(r)]);
            }
        }
        fail("rank ?", "failed without a message");
    }

    // Rank 0 merges; the others wait for its word.
    said.clear();
    if (rank == 0) {
        try {
            std::vector<std::string> files;
            for (int r = 0; r < size; ++r) {
                files.push_back((std::filesystem::path(partsDirectory) / partFileName(partName, r, size)).string());
            }
            merge(files);
            said = "ok";
        } catch (...) {
            failHere();
            said = "error";
        }
        parts.reset(); // the parts go
    }
    said = team.broadcast(said);
    if (said != "ok") {
        if (rank == 0) {
            std::rethrow_exception(error);
        }
        throw TeamFailed();
    }
}

} // namespace pyramid
