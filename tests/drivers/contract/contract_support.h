#pragma once
/// \file
/// \brief Shared pieces of the HAL contract suites: the per-backend harnesses (how to drive and
/// fault a backend from a test), the clock, allocation counting and small helpers.
///
/// Each suite is value-parameterised over the backend names of its table in drivers/backends.cpp,
/// so a backend added there runs the suite too. A backend without a harness entry here is skipped
/// with a message; a backend whose factory reports NoDevice (hardware absent) is skipped.

#include <cstddef>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <gtest/gtest.h>

#include "depthtouch/drivers/backends.h"
#include "depthtouch/platform/clock.h"
#include "support/allocation_counter.h"
#include "support/expectations.h"

namespace depthtouch::contract {

/// How the suites drive one haptic device backend.
struct HapticHarness {
    std::string options;
    bool simulatedTime = true; ///< Run on a platform::ManualClock (else the steady clock).
    bool hasDevice = true;     ///< After open() the device is connected (false for `none`).
    /// Optional fault hooks and observers; a test that needs a missing one is skipped.
    std::function<void(hal::HapticDevice &)> unplug;
    std::function<void(hal::HapticDevice &)> replug;
    std::function<hal::Vec3(const hal::HapticDevice &)> outputForce;
    /// Moves the handle through and beyond the workspace, starting at the given time.
    std::function<void(hal::HapticDevice &, platform::TimePoint)> sweep;
};

struct MediaSourceHarness {
    std::string options;
    std::string url;         ///< A clip with one color and one depth stream, several keyframes.
    std::string badUrl;      ///< Something open() must refuse.
    int framesPerStream = 0; ///< Frames in each stream of url; 0 when unknown.
};

struct VideoDecoderHarness {
    std::string options;
    bool simulatedTime = true;
    std::string sourceBackend; ///< Media source backend whose packets this decoder decodes.
    std::string sourceOptions;
    std::string url; ///< At least 30 frames per stream.
};

struct DisplayHarness {
    std::string options;
    bool simulatedTime = true;
    bool honoursSize = true; ///< open() gives the requested size.
    std::function<void(hal::Display &)> lose;
    std::function<void(hal::Display &)> restore;
};

struct RemoteInputHarness {
    std::string options;
    bool simulatedTime = true;
    /// Makes the remote deliver a press and a release of the key at the time; empty when
    /// impossible.
    std::function<void(hal::RemoteInput &, hal::Key, platform::TimePoint)> injectKey;
    std::function<void(hal::RemoteInput &)> unplug;
    /// Optional: creates the backend on a fake device side instead of through the table (the
    /// backend's own factory would look for real hardware).
    std::function<Result<std::unique_ptr<hal::RemoteInput>>(const hal::BackendConfig &)> create =
        nullptr;
};

struct DepthCameraHarness {
    std::string options;
    bool simulatedTime = true;
    std::function<void(hal::DepthCamera &)> unplug;
    std::function<void(hal::DepthCamera &)> replug;
};

/// \return the harness of backend \a name, or nullptr.
const HapticHarness *hapticHarness(std::string_view name);
const MediaSourceHarness *mediaSourceHarness(std::string_view name);
const VideoDecoderHarness *videoDecoderHarness(std::string_view name);
const DisplayHarness *displayHarness(std::string_view name);
const RemoteInputHarness *remoteInputHarness(std::string_view name);
const DepthCameraHarness *depthCameraHarness(std::string_view name);

/// \return the names of \a table, for INSTANTIATE_TEST_SUITE_P.
template <class I> std::vector<std::string> namesOf(hal::BackendTable<I> table)
{
    std::vector<std::string> out;
    for (const hal::Backend<I> &b : table)
        out.emplace_back(b.name);
    return out;
}

/// \return the names of \a table for the cases that apply only to backends whose harness meets
/// \a applies (it has a device, it can simulate an unplug, ...), so that such a case is not
/// instantiated, rather than skipped, where it does not apply. A backend without a harness is kept:
/// its cases skip with a message, like every case of a backend that needs hardware absent here.
template <class I, class H, class P>
std::vector<std::string> namesWhere(hal::BackendTable<I> table,
                                    const H *(*harnessOf)(std::string_view), P applies)
{
    std::vector<std::string> out;
    for (const hal::Backend<I> &b : table) {
        const H *harness = harnessOf(b.name);
        if (harness == nullptr || applies(*harness))
            out.emplace_back(b.name);
    }
    return out;
}

/// gtest parameter name of a backend: its name with other characters than [A-Za-z0-9] replaced by
/// '_'.
std::string backendParamName(const ::testing::TestParamInfo<std::string> &info);

using testing::errcOf;

/// \brief The clock a contract test runs on: a ManualClock (AutoAdvance, starting at 10 s) for
/// simulated backends, the steady clock for real ones.
class TestClock {
public:
    explicit TestClock(bool simulated)
        : manual_(simulated ? std::make_unique<platform::ManualClock>(
                                  platform::ManualClock::Mode::AutoAdvance,
                                  platform::TimePoint(std::chrono::seconds(10)))
                            : nullptr)
    {
    }
    platform::Clock &clock() noexcept
    {
        return manual_ ? static_cast<platform::Clock &>(*manual_)
                       : platform::SteadyClock::instance();
    }
    /// Lets time pass: advances a ManualClock, sleeps on the steady clock.
    void pass(platform::Duration d) noexcept
    {
        if (manual_)
            manual_->advance(d);
        else
            platform::SteadyClock::instance().sleepFor(d);
    }
    [[nodiscard]] bool simulated() const noexcept { return manual_ != nullptr; }

private:
    std::unique_ptr<platform::ManualClock> manual_;
};

/// \brief The fixture of a contract suite over the backends of the HAL interface \a I, whose
/// harnesses are of type \a H; the test parameter is the backend's name.
///
/// createBackend() finds the backend's harness, puts the backend on a TestClock when the harness
/// has `simulatedTime`, fills cfg_ and creates the backend into backend_: through the harness's own
/// `create` where it has one that is set, else through the table's factory. Thread-bound: the
/// test's thread.
template <class I, class H>
class BackendContractTest : public ::testing::TestWithParam<std::string> {
protected:
    /// A table's factory (drivers::createDisplay, ...).
    using TableFactory = Result<std::unique_ptr<I>> (*)(std::string_view,
                                                        const hal::BackendConfig &,
                                                        hal::SelectionReport *);

    /// Call from SetUp(), then return from it while backend_ is null (the test skipped or failed).
    /// \param harnessOf the suite's harness lookup; no harness skips the test with a message naming
    ///                  \a kind ("display", ...).
    /// \param absent    the device's name in the message of the skip when the factory reports
    ///                  NoDevice (hardware absent); nullptr: NoDevice fails the test like any
    ///                  error.
    /// \param factory   the table's factory, called with the backend's name alone.
    void createBackend(const H *(*harnessOf)(std::string_view), const char *kind,
                       const char *absent, TableFactory factory)
    {
        harness_ = harnessOf(GetParam());
        if (harness_ == nullptr)
            GTEST_SKIP() << "No contract harness for " << kind << " backend " << GetParam();
        if constexpr (requires { harness_->simulatedTime; }) {
            clock_ = std::make_unique<TestClock>(harness_->simulatedTime);
            cfg_.clock = &clock_->clock();
        }
        cfg_.options = hal::OptionList(harness_->options);
        Result<std::unique_ptr<I>> created = [&] {
            if constexpr (requires { harness_->create; }) {
                if (harness_->create)
                    return harness_->create(cfg_);
            }
            return factory(GetParam(), cfg_, nullptr);
        }();
        if (absent != nullptr && !created && created.error().code == Errc::NoDevice)
            GTEST_SKIP() << absent << " " << GetParam() << " absent";
        ASSERT_TRUE(created) << created.error().what;
        backend_ = std::move(*created);
    }

    const H *harness_ = nullptr;
    std::unique_ptr<TestClock> clock_; ///< Null for harnesses without `simulatedTime`.
    hal::BackendConfig cfg_;
    std::unique_ptr<I> backend_;
};

/// \brief A BackendContractTest whose TearDown() closes the backend, when one was created.
template <class I, class H> class ClosingContractTest : public BackendContractTest<I, H> {
protected:
    void TearDown() override
    {
        if (this->backend_)
            this->backend_->close();
    }
};

/// Instantiates the contract suite \a suite over every backend of \a table (a BackendTable).
#define DT_CONTRACT_ON_ALL_BACKENDS(suite, table)                                                  \
    INSTANTIATE_TEST_SUITE_P(Backends, suite, ::testing::ValuesIn(namesOf(table)),                 \
                             backendParamName);                                                    \
    GTEST_ALLOW_UNINSTANTIATED_PARAMETERIZED_TEST(suite)

/// Instantiates \a suite over the backends of \a table whose harness (from \a harnessOf) meets the
/// predicate \a applies, and those without a harness (see namesWhere()).
#define DT_CONTRACT_ON_BACKENDS_WHERE(suite, table, harnessOf, applies)                            \
    INSTANTIATE_TEST_SUITE_P(Backends, suite,                                                      \
                             ::testing::ValuesIn(namesWhere(table, harnessOf, applies)),           \
                             backendParamName);                                                    \
    GTEST_ALLOW_UNINSTANTIATED_PARAMETERIZED_TEST(suite)

/// Counts the calling thread's heap allocations (tests/support, linked in by CMake).
using testing::AllocationCounter;

} // namespace depthtouch::contract
