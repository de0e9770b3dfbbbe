/// Unit tests of platform/report_file.h: the bench output folder and its checked text files.

#include "depthtouch/platform/report_file.h"

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <gtest/gtest.h>

#include "support/temp_dir.h"

namespace depthtouch::platform {
namespace {

std::string slurp(const std::string &path)
{
    std::ifstream f(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

/// A scratch folder per test (tmp_, path()).
class ReportFileTest : public testing::TempDirTest {
protected:
    ReportFileTest() : TempDirTest("dt-report-file-") {}

    /// \return the path of out.csv in the scratch folder, written with \a text first.
    std::string fileHolding(const std::string &text) const
    {
        const std::string file = path("out.csv");
        std::ofstream(file) << text;
        return file;
    }
};

TEST_F(ReportFileTest, createsTheFolderAndItsParentsAndAcceptsAnExistingOne)
{
    // GIVEN a temporary folder
    const std::string dir = path("a/b/c");
    // WHEN a nested report folder is created twice
    // THEN both calls succeed and the folder exists
    EXPECT_EQ(createReportFolder(dir), "");
    EXPECT_EQ(createReportFolder(dir), "");
    EXPECT_TRUE(std::filesystem::is_directory(dir));
}

TEST_F(ReportFileTest, aFolderUnderARegularFileGivesTheSystemsReason)
{
    // GIVEN a regular file
    std::ofstream(path("file")) << "x";
    // WHEN a folder is asked for below it
    // THEN the reason is returned
    EXPECT_NE(createReportFolder(path("file/sub")), "");
}

TEST_F(ReportFileTest, writesThePrintedTextAndClosesOnce)
{
    // GIVEN a file in a temporary folder
    const std::string path = fileHolding("old content that is replaced");
    ReportFile f(path);
    ASSERT_TRUE(f.isOpen());
    // WHEN lines are printed and the file is closed
    f.print("a,b\n");
    f.print("%d,%.2f,%s\n", 7, 0.5, "x");
    // THEN the file holds exactly them, and a second close reports nothing written
    EXPECT_TRUE(f.close());
    EXPECT_FALSE(f.isOpen());
    EXPECT_FALSE(f.close());
    EXPECT_EQ(slurp(path), "a,b\n7,0.50,x\n");
}

TEST_F(ReportFileTest, aFileThatDoesNotOpenIsReportedAtClose)
{
    // GIVEN a path in a folder that does not exist
    ReportFile f(path("missing/out.csv"));
    // WHEN it is written to and closed
    EXPECT_FALSE(f.isOpen());
    f.print("ignored\n");
    // THEN close reports the failure
    EXPECT_FALSE(f.close());
}

TEST_F(ReportFileTest, aFailedWriteIsReportedAtClose)
{
    // GIVEN /dev/full, which refuses every write with ENOSPC
    ReportFile f("/dev/full");
    ASSERT_TRUE(f.isOpen());
    // WHEN more than a stdio buffer is printed
    for (int i = 0; i < 4096; ++i)
        f.print("%s\n", "0123456789abcdef");
    // THEN close reports that not every byte reached the file
    EXPECT_FALSE(f.close());
}

TEST_F(ReportFileTest, aReportFileIsUnderItsNameOnlyOnceWrittenWhole)
{
    // GIVEN a file being printed to
    const std::string path = fileHolding("previous");
    ReportFile f(path);
    ASSERT_TRUE(f.isOpen());
    f.print("a,b\n");
    // WHEN it is not closed yet THEN the name keeps its old bytes
    EXPECT_EQ(slurp(path), "previous");
    // AND closed, the new text is there and nothing else is in the folder
    EXPECT_TRUE(f.close());
    EXPECT_EQ(slurp(path), "a,b\n");
    EXPECT_EQ(std::distance(std::filesystem::directory_iterator(tmp_.dir()),
                            std::filesystem::directory_iterator()),
              1);
}

TEST_F(ReportFileTest, aTextReportFileIsWrittenWholeOrSaysWhy)
{
    // GIVEN a text report streamed into a folder, and one into /dev/full
    std::string error;
    {
        TextReportFile f(path("chart.gp"), error);
        f << "plot " << 1.5 << "\n";
        // WHEN it goes out of scope THEN it is written whole
    }
    EXPECT_EQ(slurp(path("chart.gp")), "plot 1.5\n");
    EXPECT_TRUE(error.empty()) << error;
    TextReportFile full("/dev/full", error);
    for (int i = 0; i < 4096; ++i)
        full << "0123456789abcdef\n";
    // WHEN it is closed THEN the failure is said once, with the path
    EXPECT_FALSE(full.close());
    EXPECT_NE(error.find("/dev/full"), std::string::npos) << error;
    EXPECT_FALSE(full.close());
}

} // namespace
} // namespace depthtouch::platform
