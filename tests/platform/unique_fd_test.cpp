#include "depthtouch/platform/unique_fd.h"

#include <cerrno>
#include <fcntl.h>
#include <unistd.h>
#include <utility>

#include <gtest/gtest.h>

namespace depthtouch::platform {
namespace {

bool isOpen(int fd)
{
    return fcntl(fd, F_GETFD) != -1;
}

struct Pipe {
    int readFd = -1;
    int writeFd = -1;
    Pipe()
    {
        int fds[2];
        if (pipe2(fds, O_CLOEXEC) == 0) {
            readFd = fds[0];
            writeFd = fds[1];
        }
    }
};

TEST(UniqueFdTest, closesOnDestruction)
{
    // GIVEN a UniqueFd owning one end of a pipe
    Pipe p;
    ASSERT_GE(p.readFd, 0);
    {
        UniqueFd fd(p.readFd);
        EXPECT_TRUE(fd.isValid());
        EXPECT_EQ(fd.get(), p.readFd);
        EXPECT_TRUE(isOpen(p.readFd));
    }
    // THEN leaving the scope closed it
    EXPECT_FALSE(isOpen(p.readFd));
    close(p.writeFd);
}

TEST(UniqueFdTest, releaseGivesUpOwnership)
{
    // GIVEN a UniqueFd
    Pipe p;
    int released = -1;
    {
        UniqueFd fd(p.readFd);
        // WHEN released
        released = fd.release();
        EXPECT_FALSE(fd.isValid());
        EXPECT_EQ(fd.get(), -1);
    }
    // THEN the descriptor stays open and belongs to the caller
    EXPECT_EQ(released, p.readFd);
    EXPECT_TRUE(isOpen(p.readFd));
    close(p.readFd);
    close(p.writeFd);
}

TEST(UniqueFdTest, moveTransfersOwnership)
{
    // GIVEN two UniqueFds
    Pipe p;
    UniqueFd a(p.readFd);
    UniqueFd b(p.writeFd);
    // WHEN b is move-assigned from a
    b = std::move(a);
    // THEN b's old descriptor is closed and b owns a's
    EXPECT_FALSE(a.isValid()); // NOLINT(bugprone-use-after-move): checking the moved-from state
    EXPECT_EQ(b.get(), p.readFd);
    EXPECT_FALSE(isOpen(p.writeFd));
    EXPECT_TRUE(isOpen(p.readFd));
    UniqueFd c(std::move(b));
    EXPECT_EQ(c.get(), p.readFd);
    EXPECT_FALSE(static_cast<bool>(b)); // NOLINT(bugprone-use-after-move)
}

TEST(UniqueFdTest, resetClosesAndPreservesErrno)
{
    // GIVEN a UniqueFd and an errno set by an earlier failure
    Pipe p;
    UniqueFd fd(p.readFd);
    errno = ENODEV;
    // WHEN reset to another descriptor
    fd.reset(p.writeFd);
    // THEN the old one is closed, the new one owned, errno untouched
    EXPECT_EQ(errno, ENODEV);
    EXPECT_FALSE(isOpen(p.readFd));
    EXPECT_EQ(fd.get(), p.writeFd);
    // AND resetting to the same descriptor keeps it open
    fd.reset(p.writeFd);
    EXPECT_TRUE(isOpen(p.writeFd));
    fd.reset();
    EXPECT_FALSE(isOpen(p.writeFd));
}

TEST(UniqueFdTest, swapExchanges)
{
    // GIVEN two UniqueFds
    Pipe p;
    UniqueFd a(p.readFd);
    UniqueFd b(p.writeFd);
    // WHEN swapped
    swap(a, b);
    // THEN each owns the other's descriptor
    EXPECT_EQ(a.get(), p.writeFd);
    EXPECT_EQ(b.get(), p.readFd);
}

} // namespace
} // namespace depthtouch::platform
