#include "depthtouch/platform/result.h"

#include <cerrno>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>

#include <gtest/gtest.h>

namespace depthtouch {
namespace {

Result<int> parsePositive(int v)
{
    if (v <= 0)
        return unexpected(Errc::InvalidArgument, "Value must be positive");
    return v;
}

Result<int> doubled(int v)
{
    DT_TRY(parsePositive(v));
    return 2 * v;
}

Result<void> check(int v)
{
    DT_TRY(parsePositive(v));
    return ok();
}

Result<void> failing()
{
    return unexpected(Errc::Io, "Failed to read header", EIO);
}

Result<int> afterVoid(bool fail, int &reached)
{
    DT_TRY(fail ? failing() : ok());
    ++reached;
    return 7;
}

TEST(ResultTest, valueHoldsTheValue)
{
    // GIVEN a Result built from a value
    const Result<int> r = 42;
    // THEN it reports success and holds the value
    ASSERT_TRUE(r.has_value());
    EXPECT_TRUE(static_cast<bool>(r));
    EXPECT_EQ(r.value(), 42);
    EXPECT_EQ(*r, 42);
    EXPECT_EQ(r.value_or(5), 42);
}

TEST(ResultTest, errorHoldsCodeErrnoAndMessage)
{
    // GIVEN a Result built from an error
    const Result<int> r = unexpected(Errc::NoDevice, "Failed to open device", ENODEV);
    // THEN it reports failure with the code, errno and static message
    ASSERT_FALSE(r.has_value());
    EXPECT_FALSE(static_cast<bool>(r));
    EXPECT_EQ(r.error().code, Errc::NoDevice);
    EXPECT_EQ(r.error().sysErrno, ENODEV);
    EXPECT_STREQ(r.error().what, "Failed to open device");
    EXPECT_EQ(r.value_or(5), 5);
}

TEST(ResultTest, errorWithNullMessageBecomesEmptyString)
{
    // GIVEN an Error made with a null message
    const Error e(Errc::Busy, nullptr);
    // THEN what is an empty string, safe to print
    ASSERT_NE(e.what, nullptr);
    EXPECT_STREQ(e.what, "");
}

TEST(ResultTest, voidResultSuccessAndFailure)
{
    // GIVEN a successful and a failed Result<void>
    const Result<void> good = ok();
    const Result<void> bad = failing();
    // THEN only the failure carries an error
    EXPECT_TRUE(good.has_value());
    ASSERT_FALSE(bad.has_value());
    EXPECT_EQ(bad.error().code, Errc::Io);
    EXPECT_EQ(bad.error().sysErrno, EIO);
}

TEST(ResultTest, tryPropagatesTheFirstError)
{
    // WHEN a function uses DT_TRY on a failing call
    const Result<int> bad = doubled(-1);
    const Result<void> badVoid = check(0);
    // THEN it returns that error unchanged
    ASSERT_FALSE(bad.has_value());
    EXPECT_EQ(bad.error().code, Errc::InvalidArgument);
    EXPECT_STREQ(bad.error().what, "Value must be positive");
    ASSERT_FALSE(badVoid.has_value());
    EXPECT_EQ(badVoid.error().code, Errc::InvalidArgument);
}

TEST(ResultTest, tryContinuesOnSuccess)
{
    // WHEN DT_TRY sees a success
    const Result<int> good = doubled(21);
    int reached = 0;
    const Result<int> afterOk = afterVoid(false, reached);
    // THEN the function carries on
    ASSERT_TRUE(good.has_value());
    EXPECT_EQ(*good, 42);
    ASSERT_TRUE(afterOk.has_value());
    EXPECT_EQ(reached, 1);
}

TEST(ResultTest, tryPropagatesVoidErrorIntoValueResult)
{
    // GIVEN a function returning Result<int> that DT_TRYs a failing Result<void>
    int reached = 0;
    const Result<int> r = afterVoid(true, reached);
    // THEN the error comes out and the rest of the function did not run
    ASSERT_FALSE(r.has_value());
    EXPECT_EQ(r.error().code, Errc::Io);
    EXPECT_EQ(reached, 0);
}

TEST(ResultTest, formatIncludesCodeAndStrerror)
{
    // GIVEN an error with an errno value
    const Error e(Errc::Io, "Failed to open file", ENOENT);
    char buf[256];
    // WHEN formatted
    const char *text = e.format(buf, sizeof(buf));
    // THEN the line holds the message, the code name and strerror
    EXPECT_EQ(text, buf);
    EXPECT_STREQ(buf,
                 (std::string("Failed to open file (Io, ") + std::strerror(ENOENT) + ")").c_str());
}

TEST(ResultTest, formatWithoutErrnoShowsCodeOnly)
{
    // GIVEN an error without errno
    const Error e(Errc::Timeout, "Frame did not arrive");
    char buf[128];
    // THEN only the code name is appended
    EXPECT_STREQ(e.format(buf, sizeof(buf)), "Frame did not arrive (Timeout)");
}

TEST(ResultTest, formatTruncatesAndTerminates)
{
    // GIVEN a buffer too small for the line
    const Error e(Errc::Io, "Failed to open file", ENOENT);
    char buf[8];
    std::memset(buf, 'x', sizeof(buf));
    // WHEN formatted
    e.format(buf, sizeof(buf));
    // THEN it is cut and NUL-terminated
    EXPECT_EQ(std::strlen(buf), sizeof(buf) - 1);
    EXPECT_STREQ(buf, "Failed ");
}

TEST(ResultTest, everyCodeHasAName)
{
    // GIVEN every Errc value
    const Errc codes[] = {Errc::InvalidArgument,
                          Errc::InvalidState,
                          Errc::NotSupported,
                          Errc::NoDevice,
                          Errc::Busy,
                          Errc::Timeout,
                          Errc::Io,
                          Errc::OutOfResources,
                          Errc::EndOfStream,
                          Errc::PermissionDenied};
    // THEN each has its own name
    for (Errc c : codes)
        EXPECT_STRNE(errcName(c), "Unknown");
    EXPECT_STREQ(errcName(Errc::PermissionDenied), "PermissionDenied");
    EXPECT_STREQ(errcName(Errc::OutOfResources), "OutOfResources");
}

TEST(ResultTest, moveOnlyValueIsMovedOut)
{
    // GIVEN a Result holding a move-only value
    Result<std::unique_ptr<int>> r = std::make_unique<int>(5);
    ASSERT_TRUE(r.has_value());
    // WHEN the Result is moved, then its value is moved out
    Result<std::unique_ptr<int>> moved = std::move(r);
    std::unique_ptr<int> p = std::move(moved).value();
    // THEN the pointer arrives intact
    ASSERT_NE(p, nullptr);
    EXPECT_EQ(*p, 5);
}

TEST(ResultTest, moveOnlyErrorPath)
{
    // GIVEN a failing function returning a move-only type
    auto make = [](bool fail) -> Result<std::unique_ptr<int>> {
        if (fail)
            return unexpected(Errc::OutOfResources, "Pool exhausted");
        return std::make_unique<int>(1);
    };
    // THEN the error arrives and the success path still works
    const auto bad = make(true);
    ASSERT_FALSE(bad.has_value());
    EXPECT_EQ(bad.error().code, Errc::OutOfResources);
    auto good = make(false);
    ASSERT_TRUE(good.has_value());
    EXPECT_EQ(**good, 1);
}

TEST(ResultTest, copyAndAssignSwitchBetweenValueAndError)
{
    // GIVEN a value Result and an error Result of a type that owns memory
    Result<std::string> value = std::string(100, 'a');
    Result<std::string> error = unexpected(Errc::Busy, "Queue full");
    // WHEN each is assigned the other's state (copy and move)
    Result<std::string> copy = value;
    value = error;
    error = std::move(copy);
    // THEN the states swapped without leaks or double frees (checked under ASan)
    ASSERT_FALSE(value.has_value());
    EXPECT_EQ(value.error().code, Errc::Busy);
    ASSERT_TRUE(error.has_value());
    EXPECT_EQ(*error, std::string(100, 'a'));
    EXPECT_EQ(error->size(), 100u);
}

/// Copies throw when asked to; moves never do; a destroyed object reads as -1.
struct ThrowingCopy {
    static inline bool throwOnCopy = false;
    int v = 0;
    explicit ThrowingCopy(int x) : v(x) {}
    ThrowingCopy(const ThrowingCopy &o) : v(o.v)
    {
        if (throwOnCopy)
            throw std::runtime_error("copy refused");
    }
    ThrowingCopy(ThrowingCopy &&o) noexcept = default;
    ThrowingCopy &operator=(const ThrowingCopy &) = default;
    ThrowingCopy &operator=(ThrowingCopy &&) noexcept = default;
    ~ThrowingCopy() { v = -1; } // a destroyed value reads as -1
};

TEST(ResultTest, copyAssignThatThrowsLeavesTheTargetUnchanged)
{
    // GIVEN two value Results of a type whose copy can throw
    Result<ThrowingCopy> target = ThrowingCopy(1);
    const Result<ThrowingCopy> source = ThrowingCopy(2);
    // WHEN the copy throws during assignment
    ThrowingCopy::throwOnCopy = true;
    EXPECT_THROW(target = source, std::runtime_error);
    ThrowingCopy::throwOnCopy = false;
    // THEN the target still holds its old value (strong guarantee)
    ASSERT_TRUE(target.has_value());
    EXPECT_EQ(target->v, 1);
}

#ifndef NDEBUG
TEST(ResultDeathTest, valueOnErrorAborts)
{
    // GIVEN a failed Result
    const Result<int> r = unexpected(Errc::Io, "x");
    // THEN reading its value is caught as a programming bug (in builds without NDEBUG)
    EXPECT_DEATH((void)r.value(), "assertion `ok_' failed");
}
#endif

} // namespace
} // namespace depthtouch
