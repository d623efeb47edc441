// The figures a component reports (a solver, a photon map, a pass) and small helpers for them:
// elapsed time, peak memory, and numbers formatted for the log and the EXR metadata.
#pragma once

#include <chrono>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <sys/resource.h>

namespace penumbra {

// Named figures (counters, timings, resolved parameters), in the order they were added.
using PassStats = std::vector<std::pair<std::string, std::string>>;

inline double secondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// The process's peak resident set so far, MiB (Linux reports ru_maxrss in KiB).
inline double peakMemoryMiB() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return static_cast<double>(usage.ru_maxrss) / 1024.0;
}

// Four significant digits: enough for timings and counters' ratios, short in a log line.
inline std::string formatStat(double value) {
    std::ostringstream out;
    out.precision(4);
    out << value;
    return out.str();
}

}  // namespace penumbra
