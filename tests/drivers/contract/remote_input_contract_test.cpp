// HAL contract: hal::RemoteInput (remote_input.h), for every backend in the remote input table.
#include <gtest/gtest.h>

#include "contract_support.h"

namespace depthtouch::contract {
namespace {

using std::chrono::milliseconds;

class RemoteInputContractTest : public BackendContractTest<hal::RemoteInput, RemoteInputHarness> {
protected:
    void SetUp() override
    {
        createBackend(remoteInputHarness, "remote input", "Remote", drivers::createRemoteInput);
    }

    std::unique_ptr<hal::RemoteInput> &remote_ = backend_;
};

TEST_P(RemoteInputContractTest, pastDeadlinePollsWithoutWaiting)
{
    const platform::TimePoint now = clock_->clock().now();
    EXPECT_EQ(errcOf(remote_->poll(now - milliseconds(1))), Errc::Timeout);
    if (clock_->simulated()) {
        EXPECT_EQ(clock_->clock().now(), now);
    }
}

TEST_P(RemoteInputContractTest, quietRemoteTimesOutAtTheDeadline)
{
    const hal::Deadline until = clock_->clock().now() + milliseconds(20);
    EXPECT_EQ(errcOf(remote_->poll(until)), Errc::Timeout);
    EXPECT_GE(clock_->clock().now(), until);
}

/// The cases for the backends whose harness can make the remote deliver a key.
class RemoteInputKeyContractTest : public RemoteInputContractTest {};

TEST_P(RemoteInputKeyContractTest, keyArrivesAsPressThenReleaseInTimeOrder)
{
    ASSERT_TRUE(harness_->injectKey);
    const platform::TimePoint at = clock_->clock().now() + milliseconds(30);
    harness_->injectKey(*remote_, hal::Key::PlayPause, at);
    // A poll that ends before the key does not see it.
    EXPECT_EQ(errcOf(remote_->poll(at - milliseconds(10))), Errc::Timeout);

    auto press = remote_->poll(at + milliseconds(500));
    ASSERT_TRUE(press);
    EXPECT_EQ(press->key, hal::Key::PlayPause);
    EXPECT_EQ(press->action, hal::KeyAction::Press);
    EXPECT_GE(press->time, at);
    EXPECT_LE(press->time, clock_->clock().now());

    // WHEN the caller is late  THEN an event already due comes out of a poll with a past deadline
    clock_->pass(std::chrono::seconds(2));
    auto release = remote_->poll(clock_->clock().now() - milliseconds(1));
    ASSERT_TRUE(release);
    EXPECT_EQ(release->key, hal::Key::PlayPause);
    EXPECT_EQ(release->action, hal::KeyAction::Release);
    EXPECT_GE(release->time, press->time);
}

/// The cases for the backends whose harness can unplug the remote.
class RemoteInputUnplugContractTest : public RemoteInputContractTest {};

TEST_P(RemoteInputUnplugContractTest, unpluggedRemoteReportsNoDevice)
{
    ASSERT_TRUE(harness_->unplug);
    harness_->unplug(*remote_);
    EXPECT_EQ(errcOf(remote_->poll(clock_->clock().now() + milliseconds(5))), Errc::NoDevice);
}

DT_CONTRACT_ON_ALL_BACKENDS(RemoteInputContractTest, drivers::remoteInputBackends());
DT_CONTRACT_ON_BACKENDS_WHERE(RemoteInputKeyContractTest, drivers::remoteInputBackends(),
                              remoteInputHarness,
                              [](const RemoteInputHarness &h) { return bool(h.injectKey); });
DT_CONTRACT_ON_BACKENDS_WHERE(RemoteInputUnplugContractTest, drivers::remoteInputBackends(),
                              remoteInputHarness,
                              [](const RemoteInputHarness &h) { return bool(h.unplug); });

} // namespace
} // namespace depthtouch::contract
