#pragma once
/// \file
/// \brief TempDir: a fresh folder under the system's temporary directory, removed with its contents
/// when the object goes, and TempDirTest, a fixture with one per test (test support). Header-only.

#include <filesystem>
#include <random>
#include <string>
#include <system_error>

#include <gtest/gtest.h>

namespace depthtouch::testing {

/// A directory removed with its contents on destruction. A creation failure is a test failure
/// (ADD_FAILURE) and leaves dir() empty.
class TempDir {
public:
    /// \param prefix start of the folder name, e.g. "dt-receiver-test-".
    explicit TempDir(const std::string &prefix = "dt-test-")
    {
        std::random_device rd;
        const auto base = std::filesystem::temp_directory_path();
        for (int i = 0; i < 100; ++i) {
            auto candidate = base / (prefix + std::to_string(rd()));
            std::error_code ec;
            if (std::filesystem::create_directory(candidate, ec)) {
                dir_ = candidate;
                return;
            }
        }
        ADD_FAILURE() << "Cannot create a temporary directory";
    }
    ~TempDir()
    {
        std::error_code ec;
        if (!dir_.empty())
            std::filesystem::remove_all(dir_, ec);
    }
    TempDir(const TempDir &) = delete;
    TempDir &operator=(const TempDir &) = delete;

    /// \return the folder.
    [[nodiscard]] const std::filesystem::path &dir() const noexcept { return dir_; }
    /// \return the path of \a name inside the folder.
    [[nodiscard]] std::string path(const std::string &name) const { return (dir_ / name).string(); }

private:
    std::filesystem::path dir_;
};

/// \brief A GoogleTest fixture with a scratch folder per test (tmp_), removed at its end.
class TempDirTest : public ::testing::Test {
protected:
    /// \param prefix start of the folder's name (TempDir).
    explicit TempDirTest(const std::string &prefix = "dt-test-") : tmp_(prefix) {}
    /// \return the path of \a name inside the scratch folder.
    [[nodiscard]] std::string path(const std::string &name) const { return tmp_.path(name); }

    TempDir tmp_;
};

} // namespace depthtouch::testing
