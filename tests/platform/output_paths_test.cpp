/// Unit tests of platform/output_paths.h: outputs compared with inputs and with each
/// other by file identity, not by spelling; output folders checked before a run.

#include "depthtouch/platform/output_paths.h"

#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "support/temp_dir.h"

namespace depthtouch::platform {
namespace {

class OutputPathsTest : public ::testing::Test {
protected:
    void SetUp() override
    {
        std::ofstream(dir_.path("clip.mkv")) << "clip";
        std::ofstream(dir_.path("t.csv")) << "t,x,y,z\n";
        ASSERT_EQ(::mkdir(dir_.path("sub").c_str(), 0755), 0);
        ASSERT_EQ(::symlink(dir_.path("clip.mkv").c_str(), dir_.path("link.mkv").c_str()), 0);
    }
    [[nodiscard]] std::string path(const char *name) const { return dir_.path(name); }

    testing::TempDir dir_{"dt-output-paths."};
};

TEST_F(OutputPathsTest, anOutputThatIsAnInputIsBadInputHoweverSpelled)
{
    // GIVEN outputs that name the input through itself, a link, `..` and `.`
    for (const std::string &out :
         {path("clip.mkv"), path("link.mkv"), path("sub/../clip.mkv"), path("./clip.mkv")}) {
        // WHEN compared with the inputs
        const OutputPathCheck c = checkDistinctPaths(
            {{"the input", path("clip.mkv")}, {"--trajectory", path("t.csv")}}, {{"--out", out}});
        // THEN it is refused as bad input, naming both
        EXPECT_EQ(c.exitCode, kOutputBadInput) << out;
        EXPECT_NE(c.message.find("--out"), std::string::npos) << c.message;
        EXPECT_NE(c.message.find("the input"), std::string::npos) << c.message;
    }
}

TEST_F(OutputPathsTest, twoOutputsThatNameOneNewFileAreBadInput)
{
    // GIVEN two outputs that name the same new file, spelled differently
    const OutputPathCheck c =
        checkDistinctPaths({}, {{"--force-log", path("x.csv")}, {"--stats", path("sub/../x.csv")}});
    // THEN the second is refused, naming the first
    EXPECT_EQ(c.exitCode, kOutputBadInput);
    EXPECT_NE(c.message.find("--stats"), std::string::npos) << c.message;
    EXPECT_NE(c.message.find("--force-log"), std::string::npos) << c.message;
}

TEST_F(OutputPathsTest, distinctFilesDevicesUrlsAndEmptyNamesPass)
{
    // GIVEN distinct outputs, a device named twice, URLs and names that are not files
    const OutputPathCheck c = checkDistinctPaths({{"the input", "udp://127.0.0.1:5000"},
                                                  {"--color", "synthetic:head"},
                                                  {"--depth", ""},
                                                  {"--trajectory", path("t.csv")}},
                                                 {{"--record", path("r.mkv")},
                                                  {"--force-log", "/dev/null"},
                                                  {"--stats", "/dev/null"},
                                                  {"-o", "udp://127.0.0.1:5000"},
                                                  {"--out", path("sub/t.csv")}});
    // THEN nothing is refused
    EXPECT_EQ(c.exitCode, kOutputUsable) << c.message;
}

TEST_F(OutputPathsTest, anOutputFolderMustTakeFiles)
{
    // GIVEN a folder, a new folder under it, a regular file and /proc/self (no file can be made)
    EXPECT_EQ(checkOutputFolder("--out", path("sub")).exitCode, kOutputUsable);
    EXPECT_EQ(checkOutputFolder("--out", path("new/deeper")).exitCode, kOutputUsable);
    EXPECT_EQ(checkOutputFolder("--out", path("t.csv")).exitCode, kOutputBadInput);
    EXPECT_EQ(checkOutputFolder("--out", path("t.csv/below")).exitCode, kOutputBadInput);
    EXPECT_EQ(checkOutputFolder("--snapshot-dir", "/proc/self/snap").exitCode, kOutputBadInput);
    EXPECT_EQ(checkOutputFolder("--out", "").exitCode, kOutputUsable);
    // AND nothing was made
    EXPECT_FALSE(std::ifstream(path("new")).good());
}

} // namespace
} // namespace depthtouch::platform
