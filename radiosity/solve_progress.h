// What a radiosity solver tells of its work while it solves. The solvers never print: a caller
// that wants to show progress passes a SolveProgress to solve() (or to the progressive solver's
// constructor), and nothing is reported without one.
//
// A solve is a sequence of stages (direct light of the punctual lights, linking, refinement
// rounds, gather sweeps, the final push-pull to the vertices). Each stage is announced with its
// total work when that is known before it starts (elements, links), then advanced, then ended
// with a one-line summary of what it did. ConsoleSolveProgress shows them with core/progress.h.
#pragma once

#include "core/progress.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace penumbra {

class SolveProgress {
  public:
    virtual ~SolveProgress() = default;

    // A stage begins: `name` says what it does ("linking", "gather, round 2"); `total` is its work
    // in units of the stage's own choosing, 0 when it cannot be known in advance. A stage not
    // ended by endStage() is ended by the next beginStage().
    virtual void beginStage(const std::string& name, uint64_t total) = 0;
    // `work` more units of the current stage are done. Safe to call from several threads at once.
    virtual void advance(uint64_t work) = 0;
    // The current stage ends; `summary` gives its figures ("5126123 links", "12 sweeps, residual
    // 3.1e-05"), or is empty.
    virtual void endStage(const std::string& summary) = 0;
};

// Shows each stage on `stream`, labelled "<prefix>: <stage>", as one line with its summary and
// time when it ends. On a terminal, a stage with a known total shows a core/progress.h bar with
// its ETA while it runs, and a stage of unknown length the count of its work so far; the stage's
// line then replaces them. A log gets the lines alone (a bar's
// per-10 % lines would give a solve of twenty stages two hundred lines). Prints nothing when
// quiet.
class ConsoleSolveProgress : public SolveProgress {
  public:
    ConsoleSolveProgress(std::string prefix, bool quiet, std::FILE* stream = stderr);
    ~ConsoleSolveProgress() override;

    void beginStage(const std::string& name, uint64_t total) override;
    void advance(uint64_t work) override;
    void endStage(const std::string& summary) override;

  private:
    std::string prefix_;
    bool quiet_;
    std::FILE* stream_;
    bool terminal_;
    std::string stage_;  // the current stage's name; empty between stages
    std::unique_ptr<Progress> progress_;
    std::chrono::steady_clock::time_point start_;
    // A stage of unknown length: its work so far, shown as a count on a terminal.
    std::atomic<uint64_t> done_{0};
    std::mutex drawing_;
    double nextDraw_ = 0.0;  // seconds into the stage; guarded by drawing_
    bool counting_ = false;  // a count is on the line; guarded by drawing_
};

// Whether work of `total` items, `done` of them run in `elapsed` seconds, will still be running
// `secondsLeft` from now at its mean rate so far. Judged only once a twentieth of the items and a
// quarter of a second have passed (false before): the first items' rate is noisy (threads
// starting, a slow first chunk), and a verdict that comes too early may give up work that would
// have ended in time.
bool projectedToOverrun(double elapsed, size_t done, size_t total, double secondsLeft);

// The same judgement at the pace of the later half of the time so far, and only once a quarter
// of the items are done, for work whose pace grows as it goes: the grey-white room's coarse
// links, in the order the oracle made them, were evaluated at 0.19 M per second in the first
// half second and at 0.56 M after 3 s (2.4 M links: the first twentieth took 0.57 s, the last
// 0.15 s), so that a projection from the start saw 11.5 s of work that took 5.1 s; a projection
// over the later half of the time, judged from a twentieth of the links, still gave up four of
// five such evaluations of the 16-s previews (the fifth ended with 2.8 s to spare).
class RecentPace {
  public:
    explicit RecentPace(size_t total) : total_(total), looks_{{0.0, 0}} {}
    // Starts the pace anew `elapsed` seconds into the work with `done` items done (the work
    // became quicker or slower).
    void restart(double elapsed, size_t done) { looks_.assign(1, {elapsed, done}); }
    // Whether the work, `done` items done `elapsed` seconds into it, will still be running
    // `secondsLeft` from now at the pace since the first look at or after half of the time since
    // the start (projectedToOverrun on that window), false before a quarter of the items since
    // the start are done. To be asked between chunks of the work: each call is a look.
    bool overruns(double elapsed, size_t done, double secondsLeft);

  private:
    static constexpr size_t kShareToJudge = 4;  // a verdict once this share of items is done

    struct Look {
        double seconds;  // into the work
        size_t done;
    };
    size_t total_;
    std::vector<Look> looks_;
};

// Runs body(i) for every i in [0, n) in parallel, in successive chunks of about 1/200 of n, and
// advances `progress` (if any) by each chunk as it ends: a bar that moves without an atomic
// operation per item. A chunk is at least 256 items, so that the wait for its last few is small.
// `stop`, if given, is asked before each chunk with the number of items run so far: once it says
// yes, the rest is not run and the function returns false.
template <typename Body>
bool parallelForWithProgress(size_t n, SolveProgress* progress, const Body& body,
                             const std::function<bool(size_t done)>& stop = nullptr) {
    const size_t chunk = std::max<size_t>(n / 200, 256);
    for (size_t begin = 0; begin < n; begin += chunk) {
        if (stop && stop(begin))
            return false;
        const size_t end = std::min(n, begin + chunk);
        tbb::parallel_for(begin, end, body);
        if (progress)
            progress->advance(end - begin);
    }
    return true;
}

}  // namespace penumbra
