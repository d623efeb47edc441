#include "radiosity/solve_progress.h"

#include "core/stats.h"

#include <unistd.h>

#include <utility>

namespace penumbra {

ConsoleSolveProgress::ConsoleSolveProgress(std::string prefix, bool quiet, std::FILE* stream)
    : prefix_(std::move(prefix)),
      quiet_(quiet),
      stream_(stream),
      terminal_(::isatty(::fileno(stream)) == 1) {}

ConsoleSolveProgress::~ConsoleSolveProgress() {
    if (!stage_.empty())
        endStage("");
}

void ConsoleSolveProgress::beginStage(const std::string& name, uint64_t total) {
    if (!stage_.empty())
        endStage("");
    stage_ = name.empty() ? "stage" : name;
    start_ = std::chrono::steady_clock::now();
    done_ = 0;
    nextDraw_ = 0.0;
    counting_ = false;
    // Progress is thread-safe. A stage of unknown length has no bar; nor has a stage in a log,
    // where a solve of twenty stages would otherwise take two hundred lines.
    if (total > 0 && terminal_ && !quiet_)
        progress_ = std::make_unique<Progress>(prefix_ + ": " + stage_, total, quiet_, stream_);
}

void ConsoleSolveProgress::advance(uint64_t work) {
    if (progress_) {
        progress_->advance(work);
        return;
    }
    // A stage of unknown length on a terminal: a count of its work so far, redrawn at most 10
    // times a second by whichever thread finds the line free.
    const uint64_t done = done_.fetch_add(work, std::memory_order_relaxed) + work;
    if (!terminal_ || quiet_ || stage_.empty())
        return;
    const double elapsed = secondsSince(start_);
    std::unique_lock<std::mutex> lock(drawing_, std::try_to_lock);
    if (!lock.owns_lock() || elapsed < nextDraw_)
        return;
    nextDraw_ = elapsed + 0.1;
    std::fprintf(stream_, "\r%s: %s: %llu so far, %.1f s\x1b[K", prefix_.c_str(), stage_.c_str(),
                 static_cast<unsigned long long>(done), elapsed);
    std::fflush(stream_);
    counting_ = true;
}

void ConsoleSolveProgress::endStage(const std::string& summary) {
    if (stage_.empty())
        return;
    // The bar's final line ("done in ...") is overwritten by the figures: ESC[A moves back up to
    // it and ESC[K erases what is left of it.
    if (progress_) {
        progress_->finish();
        progress_.reset();
        std::fputs("\x1b[A\r\x1b[K", stream_);
    } else if (counting_) {
        std::fputs("\r\x1b[K", stream_);  // the count's line, without a newline yet
    }
    if (!quiet_) {
        std::fprintf(stream_, "%s: %s: %s%s%.2f s\n", prefix_.c_str(), stage_.c_str(),
                     summary.c_str(), summary.empty() ? "" : ", ", secondsSince(start_));
        std::fflush(stream_);
    }
    stage_.clear();
}

bool projectedToOverrun(double elapsed, size_t done, size_t total, double secondsLeft) {
    constexpr size_t kShareToJudge = 20;  // one item in this many
    constexpr double kSecondsToJudge = 0.25;
    if (done == 0 || done >= total || done * kShareToJudge < total || elapsed < kSecondsToJudge)
        return false;
    const double remaining =
        elapsed * static_cast<double>(total - done) / static_cast<double>(done);
    return remaining > secondsLeft;
}

bool RecentPace::overruns(double elapsed, size_t done, double secondsLeft) {
    looks_.push_back({elapsed, done});
    const auto [start, doneAtStart] = looks_.front();
    if ((done - doneAtStart) * kShareToJudge < total_ - doneAtStart)
        return false;
    const auto from =
        std::lower_bound(looks_.begin(), looks_.end(), start + 0.5 * (elapsed - start),
                         [](const Look& l, double t) { return l.seconds < t; });
    return projectedToOverrun(elapsed - from->seconds, done - from->done, total_ - from->done,
                              secondsLeft);
}

}  // namespace penumbra
