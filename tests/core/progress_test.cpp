// Progress reporting to a log (not a terminal): one line per 10 %, then the final line.
#include "core/progress.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <string>
#include <thread>
#include <vector>

namespace penumbra {
namespace {

// Runs `work` with a Progress writing to a temporary file and returns the lines written.
template <typename Work>
std::vector<std::string> logLines(uint64_t total, bool quiet, Work work) {
    std::FILE* file = std::tmpfile();
    EXPECT_NE(file, nullptr);
    {
        Progress progress("render", total, quiet, file);
        work(progress);
    }
    std::rewind(file);
    std::vector<std::string> lines;
    std::string line;
    for (int c; (c = std::fgetc(file)) != EOF;) {
        if (c == '\n') {
            lines.push_back(line);
            line.clear();
        } else {
            line.push_back(char(c));
        }
    }
    std::fclose(file);
    EXPECT_TRUE(line.empty()) << "unterminated last line: " << line;
    return lines;
}

TEST(Progress, LogGetsOneLinePerTenPercentAndAFinalLine) {
    const auto lines = logLines(200, false, [](Progress& p) {
        for (int i = 0; i < 200; ++i) {
            p.advance();
        }
        p.finish();
    });
    ASSERT_EQ(lines.size(), 10u);
    for (int i = 0; i < 9; ++i) {
        EXPECT_EQ(lines[size_t(i)].rfind("render: " + std::to_string(10 * (i + 1)) + "% (", 0), 0u)
            << lines[size_t(i)];
        EXPECT_NE(lines[size_t(i)].find("ETA"), std::string::npos) << lines[size_t(i)];
    }
    EXPECT_EQ(lines[9].rfind("render: 100% done in ", 0), 0u) << lines[9];
}

TEST(Progress, OneLargeStepStillPrintsEveryTenPercent) {
    const auto lines = logLines(1000, false, [](Progress& p) { p.advance(1000); });
    EXPECT_EQ(lines.size(), 10u);
}

TEST(Progress, ConcurrentAdvancesPrintEachStepOnce) {
    constexpr int kThreads = 8, kSteps = 5000;
    Progress* shared = nullptr;
    const auto lines = logLines(kThreads * kSteps, false, [&](Progress& p) {
        shared = &p;
        std::vector<std::thread> threads;
        for (int t = 0; t < kThreads; ++t) {
            threads.emplace_back([&] {
                for (int i = 0; i < kSteps; ++i) {
                    shared->advance();
                }
            });
        }
        for (std::thread& thread : threads) {
            thread.join();
        }
        EXPECT_EQ(p.done(), uint64_t(kThreads) * kSteps);
    });
    ASSERT_EQ(lines.size(), 10u);
    for (int i = 0; i < 9; ++i) {
        EXPECT_NE(lines[size_t(i)].find(std::to_string(10 * (i + 1)) + "%"), std::string::npos);
    }
}

TEST(Progress, UnfinishedWorkIsReportedAsStopped) {
    const auto lines = logLines(100, false, [](Progress& p) { p.advance(57); });
    ASSERT_EQ(lines.size(), 6u);
    EXPECT_EQ(lines.back().rfind("render: stopped at 57% after ", 0), 0u) << lines.back();
}

TEST(Progress, QuietPrintsNothing) {
    EXPECT_TRUE(logLines(10, true, [](Progress& p) {
                    p.advance(10);
                    p.finish();
                }).empty());
}

}  // namespace
}  // namespace penumbra
