#pragma once
/// \file
/// \brief Where the real-data tests find the shared RGB-D captures (../shared/data beside the
/// source tree, or the folder in DT_SHARED_DATA), and DT_NEED_SHARED_DATA, which skips a test when
/// a file of them is absent, or fails it when DT_REQUIRE_SHARED_DATA=1 (CI, where the data must be
/// there). Header-only.

#include <cstdlib>
#include <filesystem>
#include <string>
#include <string_view>

#include <gtest/gtest.h>

namespace depthtouch::testing {

/// \return the folder of the shared RGB-D captures: $DT_SHARED_DATA when it names an existing
/// folder, else $DT_SOURCE_DIR/../shared/data (CTest sets both), else ../shared/data beside the
/// source tree the test was built from; empty when none exists.
inline std::string sharedDataDir()
{
    namespace fs = std::filesystem;
    std::error_code ec;
    if (const char *env = std::getenv("DT_SHARED_DATA"); env != nullptr && *env != '\0')
        return fs::is_directory(env, ec) ? std::string(env) : std::string();
    if (const char *src = std::getenv("DT_SOURCE_DIR"); src != nullptr && *src != '\0') {
        const std::string dir = std::string(src) + "/../shared/data";
        if (fs::is_directory(dir, ec))
            return dir;
    }
#ifdef DT_SOURCE_DIR
    if (const std::string dir = DT_SOURCE_DIR "/../shared/data"; fs::is_directory(dir, ec))
        return dir;
#endif
    return {};
}

/// \return the path of \a relative (a file or folder, e.g. "rgbd-7scenes-redkitchen") under the
/// shared data folder, whether or not it exists; empty when there is no shared data folder.
inline std::string sharedDataPath(std::string_view relative)
{
    const std::string dir = sharedDataDir();
    return dir.empty() ? std::string() : dir + "/" + std::string(relative);
}

/// \return true when the environment has DT_REQUIRE_SHARED_DATA set to anything but "" or "0": a
/// real-data test whose data is missing then fails instead of skipping.
inline bool sharedDataRequired()
{
    const char *v = std::getenv("DT_REQUIRE_SHARED_DATA");
    return v != nullptr && *v != '\0' && std::string_view(v) != "0";
}

/// \return why \a relative cannot be read from the shared data (a message naming the folder that
/// was looked in), or an empty string when it exists.
inline std::string missingSharedData(std::string_view relative)
{
    const std::string path = sharedDataPath(relative);
    std::error_code ec;
    if (!path.empty() && std::filesystem::exists(path, ec))
        return {};
    const char *env = std::getenv("DT_SHARED_DATA");
    const std::string where = env != nullptr && *env != '\0' ? std::string("DT_SHARED_DATA=") + env
                              : path.empty()
                                  ? std::string("no ../shared/data beside the source tree")
                                  : path;
    return "real RGB-D data missing: " + std::string(relative) + " (" + where +
           "; set DT_SHARED_DATA to the shared data folder)";
}

} // namespace depthtouch::testing

/// In a test body or SetUp(): unless \a relative (under the shared data folder) exists, skips the
/// test with a message naming what is missing, or fails it when DT_REQUIRE_SHARED_DATA=1.
#define DT_NEED_SHARED_DATA(relative)                                                              \
    do {                                                                                           \
        const std::string dtMissingSharedData_ =                                                   \
            ::depthtouch::testing::missingSharedData(relative);                                    \
        if (!dtMissingSharedData_.empty()) {                                                       \
            if (::depthtouch::testing::sharedDataRequired())                                       \
                FAIL() << dtMissingSharedData_ << " (DT_REQUIRE_SHARED_DATA is set: required)";    \
            GTEST_SKIP() << dtMissingSharedData_;                                                  \
        }                                                                                          \
    } while (0)
