// Progress on stderr (cli_common.hpp, Progress): --progress, a bar, lines or JSON lines, and a
// library's progress callbacks shown that way.
#include "cli/cli_common.hpp"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>

#include <CLI/CLI.hpp>

#include "cli/progress_line.hpp"

namespace pyramid::cli {

std::atomic<bool> barLineOpen{false}; // progress_line.hpp

ProgressMode& progressMode() {
    static ProgressMode mode = ProgressMode::Auto;
    return mode;
}

void addProgressOption(CLI::App& app) {
    app.add_option_function<std::string>(
           "--progress",
           [](const std::string& text) {
               static const std::map<std::string, ProgressMode> modes = {{"auto", ProgressMode::Auto},
                                                                        {"bar", ProgressMode::Bar},
                                                                        {"lines", ProgressMode::Lines},
                                                                        {"json", ProgressMode::Json},
                                                                        {"none", ProgressMode::None}};
               const auto it = modes.find(text);
               if (it == modes.end()) {
                   throw CLI::ValidationError("--progress", "'" + text + "' is not auto, bar, lines, json or none");
               }
               progressMode() = it->second;
           },
           "Progress on stderr: auto (bar on a terminal, else lines), bar, lines (every 5 %), json (JSON "
           "lines), none")
        ->type_name("MODE");
}

Progress::Progress(std::string label, int64_t total, bool quiet, OffTerminal offTerminal)
    : label_(std::move(label)),
      total_(total > 0 ? total : 1),
      quiet_(quiet || progressMode() == ProgressMode::None ||
             (progressMode() == ProgressMode::Auto && offTerminal == OffTerminal::Silent && isatty(2) == 0)),
      mode_(progressMode() == ProgressMode::Auto ? (isatty(2) != 0 ? ProgressMode::Bar : ProgressMode::Lines)
                                                 : progressMode()),
      start_(std::chrono::steady_clock::now()) {}

Progress::~Progress() { finish(); }

void Progress::advance(int64_t n) {
    const int64_t done = done_.fetch_add(n) + n;
    if (!quiet_) {
        draw(done, false);
    }
}

void Progress::finish() {
    if (quiet_ || finished_) {
        return;
    }
    draw(done_.load(), true);
    finished_ = true;
}

namespace {

// "0:42", "12:05", "3:02:17".
std::string clockText(double seconds) {
    const auto s = static_cast<long long>(std::llround(std::max(0.0, seconds)));
    char text[32];
    if (s >= 3600) {
        std::snprintf(text, sizeof text, "%lld:%02lld:%02lld", s / 3600, s / 60 % 60, s % 60);
    } else {
        std::snprintf(text, sizeof text, "%lld:%02lld", s / 60, s % 60);
    }
    return text;
}

} // namespace

void Progress::draw(int64_t counted, bool final) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (finished_) {
        return;
    }
    // The count as it stands now, read under the lock: threads that counted in one order may
    // draw in another, and the lines must still rise.
    const int64_t done = std::max(counted, done_.load());
    const auto now = std::chrono::steady_clock::now();
    const double percent = 100.0 * static_cast<double>(done) / static_cast<double>(total_);
    const double elapsed = std::chrono::duration<double>(now - start_).count();
    const double rate = elapsed > 0.0 ? static_cast<double>(done) / elapsed : 0.0;
    // A rate only once it means something (not from the first item's microseconds).
    const bool timed = rate > 0.0 && done > 0 && elapsed >= 0.25;
    const bool complete = final || done >= total_;
    const double eta = timed ? static_cast<double>(total_ - done) / rate : 0.0;
    const auto line = [&] {
        char text[64];
        std::snprintf(text, sizeof text, "%3d%% (%lld/%lld)", static_cast<int>(percent), static_cast<long long>(done),
                      static_cast<long long>(total_));
        std::string s = label_ + ": " + text;
        if (timed) {
            std::snprintf(text, sizeof text, " %.0f/s", rate);
            s += text;
            s += complete ? ", " + clockText(elapsed) : ", " + clockText(eta) + " left";
        }
        return s;
    };
    switch (mode_) {
    case ProgressMode::Bar: {
        if (!final && now - last_ < std::chrono::milliseconds(200)) {
            return;
        }
        last_ = now;
        // Padded so that a shorter line covers a longer one.
        std::fprintf(stderr, "\r%-78s%s", line().c_str(), final ? "\n" : "");
        barLineOpen = !final;
        break;
    }
    case ProgressMode::Lines: {
        const int step = static_cast<int>(percent) / 5;
        if (step == lastStep_) {
            return; // this line is already on screen (and the final one too)
        }
        lastStep_ = step;
        std::fprintf(stderr, "%s\n", line().c_str());
        break;
    }
    case ProgressMode::Json: {
        const int step = static_cast<int>(percent);
        if ((!final && step == lastStep_ && now - last_ < std::chrono::seconds(1)) || done == lastDone_) {
            return; // (a final line already out as the last one)
        }
        lastDone_ = done;
        lastStep_ = step;
        last_ = now;
        const nlohmann::ordered_json j = {{"progress", label_},
                                  {"done", done},
                                  {"total", total_},
                                  {"percent", std::round(percent * 10.0) / 10.0},
                                  {"rate", timed ? nlohmann::ordered_json(std::round(rate * 10.0) / 10.0)
                                                 : nlohmann::ordered_json()},
                                  {"eta_seconds", timed ? nlohmann::ordered_json(std::round(eta * 10.0) / 10.0)
                                                        : nlohmann::ordered_json()}};
        std::fprintf(stderr, "%s\n", j.dump().c_str());
        break;
    }
    case ProgressMode::Auto:
    case ProgressMode::None:
        return;
    }
    std::fflush(stderr);
}

std::function<void(int64_t, int64_t)> progressCallback(const std::string& label, bool quiet,
                                                      Progress::OffTerminal offTerminal) {
    struct State {
        std::unique_ptr<Progress> progress;
        int64_t shown = 0;
    };
    auto state = std::make_shared<State>();
    return [state, label, quiet, offTerminal](int64_t done, int64_t total) {
        if (!state->progress) {
            state->progress = std::make_unique<Progress>(label, total, quiet, offTerminal);
        }
        state->progress->advance(done - state->shown);
        state->shown = done;
        if (done >= total) {
            state->progress->finish();
        }
    };
}

std::function<void(int64_t, int64_t)> mergeProgress(const std::string& program, bool show) {
    return progressCallback(program + " (merging)", !show);
}

} // namespace pyramid::cli
