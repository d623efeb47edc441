#include "core/progress.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <utility>

namespace penumbra {
namespace {

constexpr int64_t kRedrawIntervalMs = 100;
constexpr int kBarWidth = 30;

// "12.3 s", "4m05s" or "2h03m09s".
std::string formatDuration(double seconds) {
    char text[32];
    if (!(seconds < 60.0)) {
        const long total = std::lround(seconds);
        if (total < 3600) {
            std::snprintf(text, sizeof text, "%ldm%02lds", total / 60, total % 60);
        } else {
            std::snprintf(text, sizeof text, "%ldh%02ldm%02lds", total / 3600, total / 60 % 60,
                          total % 60);
        }
    } else {
        std::snprintf(text, sizeof text, "%.1f s", seconds);
    }
    return text;
}

// Remaining time if the rate so far holds; unknown before any work is done.
std::string eta(double fraction, double elapsed) {
    if (!(fraction > 0.0)) {
        return "ETA ?";
    }
    return "ETA " + formatDuration(elapsed * (1.0 - fraction) / fraction);
}

}  // namespace

Progress::Progress(std::string label, uint64_t totalWork, bool quiet, std::FILE* stream)
    : label_(std::move(label)),
      total_(totalWork),
      quiet_(quiet),
      stream_(stream),
      terminal_(::isatty(::fileno(stream)) == 1),
      start_(Clock::now()) {}

Progress::~Progress() {
    finish();
}

double Progress::fraction(uint64_t done) const {
    return total_ == 0 ? 1.0 : std::min(1.0, double(done) / double(total_));
}

int Progress::completedSteps(uint64_t done, int steps) const {
    // Scale before dividing: 57 / 100 * 100 would give 56.99...
    if (total_ == 0) {
        return steps;
    }
    return int(std::floor(double(std::min(done, total_)) * steps / double(total_)));
}

double Progress::elapsedSeconds() const {
    return std::chrono::duration<double>(Clock::now() - start_).count();
}

void Progress::advance(uint64_t work) {
    const uint64_t done = done_.fetch_add(work, std::memory_order_relaxed) + work;
    if (quiet_) {
        return;
    }
    if (terminal_) {
        // Claim the next redraw slot; threads that lose the race skip drawing.
        const int64_t now =
            std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - start_).count();
        int64_t next = nextDrawMs_.load(std::memory_order_relaxed);
        if (now < next || !nextDrawMs_.compare_exchange_strong(next, now + kRedrawIntervalMs)) {
            return;
        }
        std::lock_guard<std::mutex> lock(mutex_);
        if (!finished_) {
            const uint64_t latest = done_.load(std::memory_order_relaxed);
            const double elapsed = elapsedSeconds();
            drawBar(latest,
                    "  " + formatDuration(elapsed) + " elapsed, " + eta(fraction(latest), elapsed));
        }
        return;
    }
    // Log: one line per 10 % step crossed, the 100 % line being finish()'s.
    const int tenths = std::min(9, completedSteps(done, 10));
    if (tenths <= printedTenths_.load(std::memory_order_relaxed)) {
        return;
    }
    std::lock_guard<std::mutex> lock(mutex_);
    const double elapsed = elapsedSeconds();
    const double f = fraction(done_.load(std::memory_order_relaxed));
    while (!finished_ && printedTenths_.load(std::memory_order_relaxed) < tenths) {
        const int step = printedTenths_.fetch_add(1, std::memory_order_relaxed) + 1;
        std::fprintf(stream_, "%s: %d%% (%s elapsed, %s)\n", label_.c_str(), step * 10,
                     formatDuration(elapsed).c_str(), eta(f, elapsed).c_str());
    }
    std::fflush(stream_);
}

void Progress::drawBar(uint64_t done, const std::string& suffix) {
    const double f = fraction(done);
    const int filled = int(f * kBarWidth);
    const std::string bar =
        std::string(size_t(filled), '#') + std::string(size_t(kBarWidth - filled), '.');
    // Carriage return redraws the line; ESC[K erases what a longer previous line left behind.
    std::fprintf(stream_, "\r%s [%s] %5.1f%%%s\x1b[K", label_.c_str(), bar.c_str(), 100.0 * f,
                 suffix.c_str());
    std::fflush(stream_);
}

void Progress::finish() {
    std::lock_guard<std::mutex> lock(mutex_);
    if (finished_) {
        return;
    }
    finished_ = true;
    if (quiet_) {
        return;
    }
    const uint64_t done = done_.load(std::memory_order_relaxed);
    const std::string time = formatDuration(elapsedSeconds());
    const bool complete = done >= total_;
    if (terminal_) {
        drawBar(done, complete ? "  done in " + time : "  stopped after " + time);
        std::fputc('\n', stream_);
    } else if (complete) {
        std::fprintf(stream_, "%s: 100%% done in %s\n", label_.c_str(), time.c_str());
    } else {
        std::fprintf(stream_, "%s: stopped at %d%% after %s\n", label_.c_str(),
                     completedSteps(done, 100), time.c_str());
    }
    std::fflush(stream_);
}

}  // namespace penumbra
