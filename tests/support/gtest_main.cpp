/// \file
/// \brief The main() of every GoogleTest program (dt_add_gtest links it instead of gtest_main).
///
/// Exit codes, read by CTest (SKIP_RETURN_CODE 77):
///  - 1 when a case failed (or GoogleTest itself reported an error);
///  - 77 when no case failed but at least one was skipped (GTEST_SKIP), or when the filter left no
///    case to run, so that CTest shows the program as skipped rather than passed;
///  - 0 when every case that was selected ran and passed.
/// Each skipped case is named on one line of its own with its reason (the GTEST_SKIP message):
/// `[  SKIP    ] Suite.name: reason`.

#include <cstdio>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace {

/// The first skip message among \a result's parts, with line breaks made spaces; empty when none.
std::string skipMessage(const ::testing::TestResult &result)
{
    for (int i = 0; i < result.total_part_count(); ++i) {
        const ::testing::TestPartResult &part = result.GetTestPartResult(i);
        if (!part.skipped())
            continue;
        std::string message = part.message();
        for (char &c : message) {
            if (c == '\n' || c == '\r')
                c = ' ';
        }
        return message;
    }
    return {};
}

/// The skipped cases of the run, each with its reason.
std::vector<std::string> skippedCases(const ::testing::UnitTest &unit)
{
    std::vector<std::string> lines;
    for (int s = 0; s < unit.total_test_suite_count(); ++s) {
        const ::testing::TestSuite &suite = *unit.GetTestSuite(s);
        for (int t = 0; t < suite.total_test_count(); ++t) {
            const ::testing::TestInfo &info = *suite.GetTestInfo(t);
            if (!info.should_run() || !info.result()->Skipped())
                continue;
            // A skip in SetUpTestSuite() or a global environment is recorded on the suite or on the
            // whole program, not on the case.
            std::string reason = skipMessage(*info.result());
            if (reason.empty())
                reason = skipMessage(suite.ad_hoc_test_result());
            if (reason.empty())
                reason = skipMessage(unit.ad_hoc_test_result());
            if (reason.empty())
                reason = "(no message)";
            lines.push_back(std::string(info.test_suite_name()) + "." + info.name() + ": " +
                            reason);
        }
    }
    return lines;
}

} // namespace

int main(int argc, char **argv)
{
    ::testing::InitGoogleTest(&argc, argv);
    const int rc = RUN_ALL_TESTS();
    const ::testing::UnitTest &unit = *::testing::UnitTest::GetInstance();
    if (rc != 0 || unit.Failed())
        return 1;
    const std::vector<std::string> skipped = skippedCases(unit);
    for (const std::string &line : skipped)
        std::printf("[  SKIP    ] %s\n", line.c_str());
    if (!skipped.empty()) {
        std::printf("%zu of %d cases skipped: exit code 77 (skipped)\n", skipped.size(),
                    unit.test_to_run_count());
        std::fflush(stdout);
        return 77;
    }
    if (unit.test_to_run_count() == 0) {
        std::printf("no case selected to run: exit code 77 (skipped)\n");
        std::fflush(stdout);
        return 77;
    }
    return 0;
}
