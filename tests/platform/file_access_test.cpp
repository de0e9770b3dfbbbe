/// Unit tests of platform/file_access.h on real files, FIFOs and devices in a temporary directory:
/// outputs replace only regular files and new paths, devices are written in place, FIFOs never
/// block, inputs are bounded in size and in waiting.

#include "depthtouch/platform/file_access.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <thread>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include "support/temp_dir.h"

namespace depthtouch::platform {
namespace {

using namespace std::chrono_literals;

class FileAccessTest : public ::testing::Test {
protected:
    [[nodiscard]] std::string path(const char *name) const { return dir_ + "/" + name; }
    static std::string slurp(const std::string &p)
    {
        std::ifstream f(p, std::ios::binary);
        return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
    }
    [[nodiscard]] bool noTemporaryLeft() const
    {
        return std::system(("ls '" + dir_ + "' | grep -q '\\.tmp\\.'").c_str()) != 0;
    }

    testing::TempDir tmp_{"dt-file-access."};
    const std::string dir_ = tmp_.dir().string();
};

TEST_F(FileAccessTest, replacesARegularFileOrCreatesANewOne)
{
    // GIVEN an existing regular file and a new name
    const std::string old = path("old.csv");
    std::ofstream(old) << "previous";
    // WHEN both are written
    ASSERT_TRUE(writeOutputFile(old, "new content\n"));
    ASSERT_TRUE(writeOutputFile(path("new.csv"), "fresh\n"));
    // THEN both hold the new bytes and no temporary file is left
    EXPECT_EQ(slurp(old), "new content\n");
    EXPECT_EQ(slurp(path("new.csv")), "fresh\n");
    EXPECT_TRUE(noTemporaryLeft());
}

TEST_F(FileAccessTest, aCharacterDeviceIsWrittenInPlaceNeverReplaced)
{
    // GIVEN /dev/null (a character device)
    struct stat before {};
    ASSERT_EQ(::stat("/dev/null", &before), 0);
    // WHEN it is the output
    auto plan = planOutput("/dev/null");
    ASSERT_TRUE(plan);
    EXPECT_EQ(plan->mode, OutputMode::InPlace);
    ASSERT_TRUE(writeOutputFile("/dev/null", "x\n"));
    // THEN it is still the same character device
    struct stat after {};
    ASSERT_EQ(::stat("/dev/null", &after), 0);
    EXPECT_TRUE(S_ISCHR(after.st_mode));
    EXPECT_EQ(after.st_ino, before.st_ino);
}

TEST_F(FileAccessTest, aFullDeviceIsLostOutputNotAReplacement)
{
    // GIVEN /dev/full, where every write fails with ENOSPC
    if (pathKind("/dev/full") != PathKind::CharDevice)
        GTEST_SKIP() << "no /dev/full";
    // WHEN written
    auto r = writeOutputFile("/dev/full", std::string(100000, 'x'));
    // THEN the write fails as lost output (Io), and /dev/full is still a device
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().code, Errc::Io);
    EXPECT_EQ(pathKind("/dev/full"), PathKind::CharDevice);
}

TEST_F(FileAccessTest, refusesADirectoryAndAFifoWithoutAReader)
{
    // GIVEN a directory and a FIFO nobody reads
    ASSERT_EQ(::mkdir(path("d").c_str(), 0700), 0);
    ASSERT_EQ(::mkfifo(path("p").c_str(), 0600), 0);
    // WHEN they are outputs
    const auto t0 = std::chrono::steady_clock::now();
    auto d = writeOutputFile(path("d"), "x");
    auto p = writeOutputFile(path("p"), "x");
    // THEN both are refused as bad input at once, and both are still what they were
    ASSERT_FALSE(d);
    ASSERT_FALSE(p);
    EXPECT_EQ(d.error().code, Errc::InvalidArgument);
    EXPECT_EQ(p.error().code, Errc::InvalidArgument);
    EXPECT_STREQ(p.error().what, "is a FIFO with no reader");
    EXPECT_LT(std::chrono::steady_clock::now() - t0, 1s);
    EXPECT_EQ(pathKind(path("d").c_str()), PathKind::Directory);
    EXPECT_EQ(pathKind(path("p").c_str()), PathKind::Fifo);
    EXPECT_TRUE(noTemporaryLeft());
}

TEST_F(FileAccessTest, aSymbolicLinkIsWrittenThroughAndStaysALink)
{
    // GIVEN a link to a regular file
    std::ofstream(path("target.csv")) << "old";
    ASSERT_EQ(::symlink(path("target.csv").c_str(), path("link.csv").c_str()), 0);
    // WHEN the link is the output
    ASSERT_TRUE(writeOutputFile(path("link.csv"), "through\n"));
    // THEN the target holds the bytes and the link is still a link
    EXPECT_EQ(slurp(path("target.csv")), "through\n");
    struct stat st {};
    ASSERT_EQ(::lstat(path("link.csv").c_str(), &st), 0);
    EXPECT_TRUE(S_ISLNK(st.st_mode));
}

TEST_F(FileAccessTest, aMissingDirectoryIsBadInput)
{
    auto r = writeOutputFile(path("no/such/dir/out.csv"), "x");
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().code, Errc::InvalidArgument);
}

TEST_F(FileAccessTest, readIsBoundedInSize)
{
    // GIVEN a 1000-byte file and /dev/zero (endless)
    std::ofstream(path("f")) << std::string(1000, 'a');
    // WHEN read with limits
    auto small = readFileBounded(path("f"), 999);
    auto fits = readFileBounded(path("f"), 1000);
    auto zero = readFileBounded("/dev/zero", 1 << 20);
    // THEN only what fits is read; the endless device stops at the limit
    ASSERT_FALSE(small);
    EXPECT_EQ(small.error().code, Errc::InvalidArgument);
    ASSERT_TRUE(fits);
    EXPECT_EQ(fits->size(), 1000u);
    ASSERT_FALSE(zero);
    EXPECT_STREQ(zero.error().what, "is larger than the limit");
    auto dir = readFileBounded(dir_, 100);
    ASSERT_FALSE(dir);
    EXPECT_STREQ(dir.error().what, "is a directory");
}

TEST_F(FileAccessTest, aFifoWithoutAWriterTimesOutInsteadOfBlocking)
{
    // GIVEN a FIFO nobody writes
    ASSERT_EQ(::mkfifo(path("p").c_str(), 0600), 0);
    // WHEN it is read with a 200 ms wait
    const auto t0 = std::chrono::steady_clock::now();
    auto r = readFileBounded(path("p"), 1000, 200ms);
    // THEN it gives up in about that time
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().code, Errc::Timeout);
    EXPECT_LT(std::chrono::steady_clock::now() - t0, 2s);
}

TEST_F(FileAccessTest, aFifoWithAWriterIsReadToItsEnd)
{
    // GIVEN a FIFO whose writer comes after 100 ms and writes in two pieces
    ASSERT_EQ(::mkfifo(path("p").c_str(), 0600), 0);
    std::thread writer([p = path("p")] {
        std::this_thread::sleep_for(100ms);
        const int fd = ::open(p.c_str(), O_WRONLY);
        if (fd < 0)
            return;
        (void)!::write(fd, "t,x,y,z\n", 8);
        std::this_thread::sleep_for(50ms);
        (void)!::write(fd, "0,0,0,0\n", 8);
        ::close(fd);
    });
    // WHEN it is read
    auto r = readFileBounded(path("p"), 1000, 5s);
    writer.join();
    // THEN all of it arrives
    ASSERT_TRUE(r) << r.error().what;
    EXPECT_EQ(std::string(r->begin(), r->end()), "t,x,y,z\n0,0,0,0\n");
}

TEST_F(FileAccessTest, anOutputFileAppearsUnderItsNameOnlyWhenCommitted)
{
    // GIVEN an existing file and an output streamed over it
    const std::string out = path("log.csv");
    std::ofstream(out) << "previous";
    auto f = OutputFile::open(out);
    ASSERT_TRUE(f);
    std::fputs("t,x\n0,1\n", f->stream());
    std::fflush(f->stream());
    // WHEN it is still being written THEN the final name keeps its old bytes
    EXPECT_EQ(slurp(out), "previous");
    EXPECT_FALSE(f->tempPath().empty());
    // WHEN it is committed THEN the new bytes are under the name and no temporary is left
    ASSERT_TRUE(f->commit());
    EXPECT_EQ(slurp(out), "t,x\n0,1\n");
    EXPECT_TRUE(noTemporaryLeft());
}

TEST_F(FileAccessTest, anAbortedOutputFileLeavesNothingUnderItsName)
{
    // GIVEN a new output with rows written
    const std::string out = path("cut.csv");
    {
        auto f = OutputFile::open(out);
        ASSERT_TRUE(f);
        std::fputs("t,x\n0,1\n", f->stream());
        // WHEN it is dropped without commit()
    }
    // THEN neither the final name nor a temporary file exists
    EXPECT_EQ(pathKind(out.c_str()), PathKind::Missing);
    EXPECT_TRUE(noTemporaryLeft());
}

TEST_F(FileAccessTest, anOutputFileOnAFullDeviceFailsAtCommit)
{
    if (pathKind("/dev/full") != PathKind::CharDevice)
        GTEST_SKIP() << "no /dev/full";
    // GIVEN /dev/full written as a stream (more than a stdio buffer)
    auto f = OutputFile::open("/dev/full");
    ASSERT_TRUE(f);
    for (int i = 0; i < 4096; ++i)
        std::fputs("0123456789abcdef\n", f->stream());
    // WHEN it is committed THEN the output is lost (Io)
    auto r = f->commit();
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().code, Errc::Io);
}

TEST_F(FileAccessTest, identityIsTheFileNotItsSpelling)
{
    // GIVEN a file, a link to it, a hard link and a path through `..`
    const std::string file = path("clip.mkv");
    std::ofstream(file) << "clip";
    ASSERT_EQ(::mkdir(path("sub").c_str(), 0755), 0);
    ASSERT_EQ(::symlink(file.c_str(), path("link.mkv").c_str()), 0);
    ASSERT_EQ(::link(file.c_str(), path("hard.mkv").c_str()), 0);
    const auto id = fileIdentity(file);
    ASSERT_TRUE(id);
    EXPECT_TRUE(id->regular);
    // THEN every spelling has the same identity, another file does not
    EXPECT_EQ(fileIdentity(path("link.mkv")), id);
    EXPECT_EQ(fileIdentity(path("hard.mkv")), id);
    EXPECT_EQ(fileIdentity(path("sub/../clip.mkv")), id);
    EXPECT_EQ(fileIdentity(dir_ + "/./clip.mkv"), id);
    EXPECT_NE(fileIdentity(path("sub")), id);
    // AND a new path is its folder and name, however the folder is spelled
    const auto fresh = fileIdentity(path("new.csv"));
    ASSERT_TRUE(fresh);
    EXPECT_EQ(fresh->name, "new.csv");
    EXPECT_EQ(fileIdentity(path("sub/../new.csv")), fresh);
    EXPECT_NE(fileIdentity(path("sub/new.csv")), fresh);
    // AND a dangling link is the path it points to
    ASSERT_EQ(::symlink(path("new.csv").c_str(), path("dangling.csv").c_str()), 0);
    EXPECT_EQ(fileIdentity(path("dangling.csv")), fresh);
    // AND a path in no folder has none
    EXPECT_FALSE(fileIdentity(path("missing/x.csv")));
    EXPECT_FALSE(fileIdentity(""));
}

TEST_F(FileAccessTest, aFolderIsWritableOnlyWhenAFileCanBeMadeThere)
{
    // GIVEN this folder, a regular file and /proc/self (where nothing can be made, even by root)
    EXPECT_TRUE(checkFolderWritable(dir_));
    EXPECT_TRUE(noTemporaryLeft());
    std::ofstream(path("file")) << "x";
    auto notFolder = checkFolderWritable(path("file"));
    ASSERT_FALSE(notFolder);
    EXPECT_EQ(notFolder.error().code, Errc::InvalidArgument);
    EXPECT_FALSE(checkFolderWritable(path("missing")));
    if (pathKind("/proc/self") == PathKind::Directory) {
        EXPECT_FALSE(checkFolderWritable("/proc/self"));
    }
    // AND nothing is left behind
    EXPECT_EQ(std::system(("ls -a '" + dir_ + "' | grep -q dt-write-check").c_str()) != 0, true);
}

} // namespace
} // namespace depthtouch::platform
