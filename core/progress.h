// Progress reporting for long work (rendering, radiosity steps, photon shooting).
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <mutex>
#include <string>

namespace penumbra {

// Thread-safe: any thread may call advance(). Counting is a relaxed atomic add; the thread whose
// advance crosses a reporting threshold prints, under a mutex.
//   terminal (isatty): one line, redrawn at most 10 times a second, with a bar, the percentage,
//                      the elapsed time and an ETA;
//   otherwise (a log): a plain line at every 10 % up to 90 %, so logs stay short;
//   quiet:             nothing.
// finish() (or the destructor) prints the final state with the total time: "done in ..." when
// all the work was done, "stopped at N% after ..." otherwise. A non-terminal log of a completed
// task thus has exactly 10 lines.
class Progress {
  public:
    Progress(std::string label, uint64_t totalWork, bool quiet, std::FILE* stream = stderr);
    ~Progress();
    Progress(const Progress&) = delete;
    Progress& operator=(const Progress&) = delete;

    void advance(uint64_t work = 1);
    // Prints the final line once; later calls (and advance) print nothing.
    void finish();

    uint64_t done() const { return done_.load(std::memory_order_relaxed); }
    uint64_t total() const { return total_; }

  private:
    using Clock = std::chrono::steady_clock;

    double fraction(uint64_t done) const;
    // Whole steps of 1/steps of the total work done.
    int completedSteps(uint64_t done, int steps) const;
    double elapsedSeconds() const;
    void drawBar(uint64_t done, const std::string& suffix);  // terminal; caller holds mutex_

    std::string label_;
    uint64_t total_;
    bool quiet_;
    std::FILE* stream_;
    bool terminal_;
    Clock::time_point start_;

    std::atomic<uint64_t> done_{0};
    std::atomic<int64_t> nextDrawMs_{0};  // terminal: earliest time of the next redraw
    std::atomic<int> printedTenths_{0};   // log: the last 10 % step printed
    std::mutex mutex_;
    bool finished_ = false;  // guarded by mutex_
};

}  // namespace penumbra
