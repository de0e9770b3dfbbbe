// LibusbTransport against a libusb stand-in (libusb_standin.h) playing the USB side: enumeration
// (found, absent, no permission, busy, listing failed), open and close, FTDI control requests,
// synchronous bulk transfers with short reads and timeouts, the asynchronous servo exchange, and a
// device unplugged mid-stream; then the whole Falcon driver over it.
#include <array>
#include <cstring>
#include <memory>
#include <string_view>
#include <vector>

#include <gtest/gtest.h>

#include "libusb_standin.h"
#include "depthtouch/drivers/usb/falcon_haptic_device.h"
#include "depthtouch/drivers/usb/libusb_transport.h"
#include "depthtouch/platform/clock.h"

namespace depthtouch::drivers {
namespace {

using std::chrono::milliseconds;
using testing::LibusbStandin;
using Bytes = std::vector<std::uint8_t>;

template <class R> Errc codeOf(const R &r)
{
    EXPECT_FALSE(r) << "expected an error";
    return r ? Errc::InvalidState : r.error().code;
}

bool mentions(const Error &e, std::string_view word)
{
    return std::string_view(e.what).find(word) != std::string_view::npos;
}

class LibusbStandinTest : public ::testing::Test {
protected:
    void SetUp() override
    {
        bus_.devices = {{0x1d6b, 0x0002, 0}, {kFalconVendorId, kFalconProductId, 0}};
    }
    void openOrFail() { ASSERT_TRUE(usb_.open(kFalconVendorId, kFalconProductId)); }
    /// Everything the transport took from libusb was given back.
    void expectReleased() const
    {
        EXPECT_EQ(bus_.exits, bus_.inits);
        EXPECT_EQ(bus_.closes, bus_.opens);
        EXPECT_EQ(bus_.releases, bus_.claims);
        EXPECT_EQ(bus_.frees, bus_.allocs);
    }

    LibusbStandin bus_;
    LibusbTransport usb_{LibusbStandin::api()};
};

// --- Enumeration and open -----------------------------------------------------------------------

TEST_F(LibusbStandinTest, probeFindsTheDeviceAmongOthers)
{
    auto found = LibusbTransport::probe(kFalconVendorId, kFalconProductId, LibusbStandin::api());
    ASSERT_TRUE(found);
    EXPECT_TRUE(*found);
    bus_.devices.pop_back();
    found = LibusbTransport::probe(kFalconVendorId, kFalconProductId, LibusbStandin::api());
    ASSERT_TRUE(found);
    EXPECT_FALSE(*found);
    EXPECT_EQ(bus_.opens, 0); // probing opens nothing
    expectReleased();
}

TEST_F(LibusbStandinTest, probeWithoutUsbIsNoDeviceAndAFailedListingIsAnError)
{
    bus_.initResult = LIBUSB_ERROR_OTHER;
    auto found = LibusbTransport::probe(kFalconVendorId, kFalconProductId, LibusbStandin::api());
    ASSERT_TRUE(found);
    EXPECT_FALSE(*found);
    bus_.initResult = 0;
    bus_.listResult = LIBUSB_ERROR_NO_MEM;
    EXPECT_EQ(
        codeOf(LibusbTransport::probe(kFalconVendorId, kFalconProductId, LibusbStandin::api())),
        Errc::Io);
    expectReleased();
}

TEST_F(LibusbStandinTest, openClaimsTheInterfaceAndCloseGivesEverythingBack)
{
    openOrFail();
    EXPECT_TRUE(usb_.present());
    EXPECT_EQ(bus_.claims, 1);
    EXPECT_EQ(bus_.allocs, 2); // the OUT and IN transfers of exchange()
    EXPECT_EQ(codeOf(usb_.open(kFalconVendorId, kFalconProductId)), Errc::InvalidState);
    usb_.close();
    EXPECT_FALSE(usb_.present());
    expectReleased();
    usb_.close(); // again: a no-op
    expectReleased();
}

TEST_F(LibusbStandinTest, absentDeviceIsNoDevice)
{
    bus_.devices.pop_back();
    auto r = usb_.open(kFalconVendorId, kFalconProductId);
    EXPECT_EQ(codeOf(r), Errc::NoDevice);
    EXPECT_FALSE(usb_.present());
    expectReleased();
}

TEST_F(LibusbStandinTest, noPermissionIsPermissionDeniedNamingTheUdevRule)
{
    bus_.devices.back().openResult = LIBUSB_ERROR_ACCESS;
    auto r = usb_.open(kFalconVendorId, kFalconProductId);
    ASSERT_EQ(codeOf(r), Errc::PermissionDenied);
    EXPECT_TRUE(mentions(r.error(), "udev")) << r.error().what;
    EXPECT_FALSE(usb_.present());
    expectReleased();
}

TEST_F(LibusbStandinTest, interfaceClaimedByAnotherProgramIsBusy)
{
    bus_.claimResult = LIBUSB_ERROR_BUSY;
    EXPECT_EQ(codeOf(usb_.open(kFalconVendorId, kFalconProductId)), Errc::Busy);
    EXPECT_FALSE(usb_.present());
    EXPECT_EQ(bus_.opens, 1);
    expectReleased();
}

TEST_F(LibusbStandinTest, listingFailureAtOpenIsIo)
{
    bus_.listResult = LIBUSB_ERROR_IO;
    EXPECT_EQ(codeOf(usb_.open(kFalconVendorId, kFalconProductId)), Errc::Io);
    expectReleased();
}

// --- Control and synchronous bulk transfers ------------------------------------------------------

TEST_F(LibusbStandinTest, controlSendsAVendorRequestToTheDevice)
{
    openOrFail();
    ASSERT_TRUE(usb_.control(FtdiRequest::BaudRate, kFtdiBaud1456312));
    ASSERT_EQ(bus_.controls.size(), 1u);
    const LibusbStandin::ControlCall &c = bus_.controls[0];
    // bmRequestType: vendor (0x40), recipient device (0), host to device (0)
    EXPECT_EQ(c.requestType, 0x40);
    EXPECT_EQ(c.request, 0x03);
    EXPECT_EQ(c.value, kFtdiBaud1456312);
    EXPECT_EQ(c.index, 0);
    EXPECT_EQ(c.length, 0);
    // A refused request is Io and the device stays present
    bus_.controlResult = LIBUSB_ERROR_PIPE;
    EXPECT_EQ(codeOf(usb_.control(FtdiRequest::LatencyTimer, 1)), Errc::Io);
    EXPECT_TRUE(usb_.present());
}

TEST_F(LibusbStandinTest, shortWriteReportsTheBytesTakenAndATimeoutIsTimeout)
{
    openOrFail();
    const Bytes data(16, 0x41);
    bus_.bulkOutAccepts = 10;
    auto n = usb_.write(data.data(), data.size(), milliseconds(5));
    ASSERT_TRUE(n);
    EXPECT_EQ(*n, 10u);
    bus_.bulkOutResult = LIBUSB_ERROR_TIMEOUT;
    EXPECT_EQ(codeOf(usb_.write(data.data(), data.size(), milliseconds(5))), Errc::Timeout);
    EXPECT_TRUE(usb_.present());
}

TEST_F(LibusbStandinTest, readStripsTheStatusBytesAndGathersShortReads)
{
    openOrFail();
    // GIVEN answers of 5, 0 and 11 payload bytes (each USB packet led by two status bytes), then
    // 124 bytes sent as two full 64-byte USB packets and a status-only one
    bus_.syncIn.push_back({0, LibusbStandin::withStatus({1, 2, 3, 4, 5})});
    bus_.syncIn.push_back({0, LibusbStandin::withStatus({})});
    bus_.syncIn.push_back({0, LibusbStandin::withStatus({6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16})});
    std::array<std::uint8_t, 16> got{};
    auto n = usb_.read(got.data(), got.size(), milliseconds(500));
    ASSERT_TRUE(n);
    ASSERT_EQ(*n, 16u);
    for (std::size_t i = 0; i < 16; ++i)
        EXPECT_EQ(got[i], i + 1);
    Bytes big;
    for (int packet = 0; packet < 2; ++packet) {
        const Bytes payload(62, static_cast<std::uint8_t>(0xa0 + packet));
        const Bytes p = LibusbStandin::withStatus(payload);
        big.insert(big.end(), p.begin(), p.end());
    }
    const Bytes tail = LibusbStandin::withStatus({});
    big.insert(big.end(), tail.begin(), tail.end());
    bus_.syncIn.push_back({0, big});
    std::array<std::uint8_t, 124> all{};
    n = usb_.read(all.data(), all.size(), milliseconds(500));
    ASSERT_TRUE(n);
    ASSERT_EQ(*n, 124u);
    EXPECT_EQ(all[61], 0xa0);
    EXPECT_EQ(all[62], 0xa1);
    EXPECT_EQ(all[123], 0xa1);
}

TEST_F(LibusbStandinTest, readThatTimesOutReturnsWhatCame)
{
    openOrFail();
    bus_.syncIn.push_back({0, LibusbStandin::withStatus({9, 8, 7})});
    std::array<std::uint8_t, 16> got{};
    auto n = usb_.read(got.data(), got.size(), milliseconds(20));
    ASSERT_TRUE(n);
    EXPECT_EQ(*n, 3u);
    EXPECT_EQ(got[0], 9);
    EXPECT_TRUE(usb_.present());
}

TEST_F(LibusbStandinTest, unplugDuringSynchronousTransfersIsNoDevice)
{
    openOrFail();
    bus_.syncIn.push_back({0, LibusbStandin::withStatus({1, 2})});
    bus_.syncIn.push_back({LIBUSB_ERROR_NO_DEVICE, {}});
    std::array<std::uint8_t, 16> got{};
    EXPECT_EQ(codeOf(usb_.read(got.data(), got.size(), milliseconds(500))), Errc::NoDevice);
    EXPECT_FALSE(usb_.present());
    // AND every later call says so without touching the bus
    bus_.unplug();
    const std::size_t controls = bus_.controls.size();
    EXPECT_EQ(codeOf(usb_.control(FtdiRequest::LatencyTimer, 1)), Errc::NoDevice);
    EXPECT_EQ(codeOf(usb_.write(got.data(), 4, milliseconds(5))), Errc::NoDevice);
    EXPECT_EQ(bus_.controls.size(), controls);
    usb_.close();
    expectReleased();
}

TEST_F(LibusbStandinTest, unplugDuringAControlRequestIsNoDevice)
{
    openOrFail();
    bus_.unplug();
    EXPECT_EQ(codeOf(usb_.control(FtdiRequest::ModemControl, kFtdiDtrHigh)), Errc::NoDevice);
    EXPECT_FALSE(usb_.present());
}

// --- The asynchronous servo exchange
// --------------------------------------------------------------

/// A 16-byte command packet as the driver sends it.
Bytes packetOf(std::uint8_t fill)
{
    Bytes p(16, fill);
    p.front() = '<';
    p.back() = '>';
    return p;
}

TEST_F(LibusbStandinTest, exchangeSendsTheCommandAndReturnsTheAnswerWithoutStatusBytes)
{
    openOrFail();
    bus_.device = [](const Bytes &) { return packetOf('B'); };
    const Bytes out = packetOf('A');
    std::array<std::uint8_t, 64> in{};
    auto n = usb_.exchange(out.data(), out.size(), in.data(), in.size(), milliseconds(50));
    ASSERT_TRUE(n) << n.error().what;
    ASSERT_EQ(*n, 16u);
    EXPECT_EQ(Bytes(in.begin(), in.begin() + 16), packetOf('B'));
    ASSERT_EQ(bus_.written.size(), 1u);
    EXPECT_EQ(bus_.written[0], out);
    // AND the next exchange reuses the transfers allocated at open()
    n = usb_.exchange(out.data(), out.size(), in.data(), in.size(), milliseconds(50));
    ASSERT_TRUE(n);
    EXPECT_EQ(bus_.allocs, 2);
    EXPECT_EQ(bus_.written.size(), 2u);
}

TEST_F(LibusbStandinTest, statusOnlyAnswersAreSkippedAndAShortAnswerIsReturnedAsItCame)
{
    openOrFail();
    // GIVEN the FTDI chip's status-only packet, then 6 bytes of an answer
    bus_.asyncIn.push_back({LIBUSB_TRANSFER_COMPLETED, LibusbStandin::withStatus({})});
    bus_.asyncIn.push_back(
        {LIBUSB_TRANSFER_COMPLETED, LibusbStandin::withStatus({'<', 'A', 'B', 'C', 'D', 'E'})});
    const Bytes out = packetOf('A');
    std::array<std::uint8_t, 64> in{};
    auto n = usb_.exchange(out.data(), out.size(), in.data(), in.size(), milliseconds(50));
    ASSERT_TRUE(n);
    EXPECT_EQ(*n, 6u);
    EXPECT_EQ(in[5], 'E');
    EXPECT_EQ(bus_.inSubmits, 2); // posted again after the status-only packet
    // AND an answer longer than the caller's buffer is cut to it
    bus_.asyncIn.push_back({LIBUSB_TRANSFER_COMPLETED, LibusbStandin::withStatus(packetOf('C'))});
    n = usb_.exchange(out.data(), out.size(), in.data(), 4, milliseconds(50));
    ASSERT_TRUE(n);
    EXPECT_EQ(*n, 4u);
}

TEST_F(LibusbStandinTest, silenceTimesOutKeepsTheReceivePostedAndTheNextCallGetsTheAnswer)
{
    openOrFail();
    bus_.outCompletes = false; // the OUT transfer is still on its way at the next call
    const Bytes out = packetOf('A');
    std::array<std::uint8_t, 64> in{};
    EXPECT_EQ(codeOf(usb_.exchange(out.data(), out.size(), in.data(), in.size(), milliseconds(3))),
              Errc::Timeout);
    EXPECT_TRUE(usb_.present());
    // WHEN the answer arrives before the next call
    bus_.asyncIn.push_back({LIBUSB_TRANSFER_COMPLETED, LibusbStandin::withStatus(packetOf('B'))});
    auto n = usb_.exchange(out.data(), out.size(), in.data(), in.size(), milliseconds(50));
    ASSERT_TRUE(n);
    EXPECT_EQ(*n, 16u);
    // THEN neither transfer was posted twice: the busy send was skipped, the receive kept
    EXPECT_EQ(bus_.inSubmits, 1);
    EXPECT_EQ(bus_.outSubmits, 1);
}

TEST_F(LibusbStandinTest, failedTransfersAndEventHandlingAreIoAndTheNextCallRecovers)
{
    openOrFail();
    const Bytes out = packetOf('A');
    std::array<std::uint8_t, 64> in{};
    bus_.asyncIn.push_back({LIBUSB_TRANSFER_ERROR, {}});
    EXPECT_EQ(codeOf(usb_.exchange(out.data(), out.size(), in.data(), in.size(), milliseconds(50))),
              Errc::Io);
    bus_.handleEventsResult = LIBUSB_ERROR_IO;
    EXPECT_EQ(codeOf(usb_.exchange(out.data(), out.size(), in.data(), in.size(), milliseconds(50))),
              Errc::Io);
    bus_.handleEventsResult = 0;
    bus_.submitResult = LIBUSB_ERROR_IO;
    usb_.close(); // drops the posted transfers
    openOrFail();
    EXPECT_EQ(codeOf(usb_.exchange(out.data(), out.size(), in.data(), in.size(), milliseconds(50))),
              Errc::Io);
    bus_.submitResult = 0;
    bus_.asyncIn.push_back({LIBUSB_TRANSFER_COMPLETED, LibusbStandin::withStatus(packetOf('B'))});
    EXPECT_TRUE(usb_.exchange(out.data(), out.size(), in.data(), in.size(), milliseconds(50)));
    EXPECT_TRUE(usb_.present());
}

TEST_F(LibusbStandinTest, unplugMidStreamIsNoDeviceAndCloseDoesNotWait)
{
    openOrFail();
    bus_.device = [](const Bytes &) { return packetOf('B'); };
    const Bytes out = packetOf('A');
    std::array<std::uint8_t, 64> in{};
    for (int i = 0; i < 10; ++i)
        ASSERT_TRUE(usb_.exchange(out.data(), out.size(), in.data(), in.size(), milliseconds(50)));
    // WHEN the device goes while a send and a receive are posted (it stops answering, then is gone)
    bus_.device = nullptr;
    bus_.outCompletes = false;
    EXPECT_EQ(codeOf(usb_.exchange(out.data(), out.size(), in.data(), in.size(), milliseconds(2))),
              Errc::Timeout);
    bus_.unplug();
    auto r = usb_.exchange(out.data(), out.size(), in.data(), in.size(), milliseconds(50));
    // THEN the posted transfers completing with NO_DEVICE end the exchange as NoDevice, at once
    ASSERT_EQ(codeOf(r), Errc::NoDevice);
    EXPECT_TRUE(mentions(r.error(), "unplugged")) << r.error().what;
    EXPECT_FALSE(usb_.present());
    // AND later exchanges fail the same way without submitting anything
    const int submits = bus_.inSubmits + bus_.outSubmits;
    EXPECT_EQ(codeOf(usb_.exchange(out.data(), out.size(), in.data(), in.size(), milliseconds(50))),
              Errc::NoDevice);
    EXPECT_EQ(bus_.inSubmits + bus_.outSubmits, submits);
    // AND close() gives everything back after at most a few rounds of event handling
    const int events = bus_.eventCalls;
    usb_.close();
    EXPECT_LE(bus_.eventCalls - events, 2);
    expectReleased();
}

TEST_F(LibusbStandinTest, submitRefusedForAnUnpluggedDeviceIsNoDevice)
{
    openOrFail();
    bus_.unplug();
    const Bytes out = packetOf('A');
    std::array<std::uint8_t, 64> in{};
    EXPECT_EQ(codeOf(usb_.exchange(out.data(), out.size(), in.data(), in.size(), milliseconds(50))),
              Errc::NoDevice);
    EXPECT_FALSE(usb_.present());
    usb_.close();
    expectReleased();
}

// --- The Falcon driver over the stand-in ---------------------------------------------------------

/// A Falcon whose firmware runs, homed, at encoder counts (0, 0, 0): answers each 16-byte command
/// with a status packet.
Bytes falconStatus(const Bytes &command)
{
    if (command.size() != 16 || command.front() != '<')
        return {};
    Bytes st(16, 0x41);
    st.front() = '<';
    st[13] = 0x41 + 0x70; // motors 0..2 homed
    st.back() = '>';
    return st;
}

TEST(LibusbFalconTest, theDriverRunsOverLibusbAndReportsAnUnplugWithoutHanging)
{
    LibusbStandin bus;
    bus.devices = {{kFalconVendorId, kFalconProductId, 0}};
    bus.device = &falconStatus;
    platform::ManualClock clock;
    FalconSettings settings;
    settings.homingPackets = 2;
    FalconHapticDevice dev(clock, std::make_unique<LibusbTransport>(LibusbStandin::api()),
                           settings);
    ASSERT_TRUE(dev.open());
    EXPECT_TRUE(dev.homed());
    // The firmware's serial setup went out first: latency 1 ms, then its baud rate
    ASSERT_GE(bus.controls.size(), 2u);
    EXPECT_EQ(bus.controls[0].request, static_cast<std::uint8_t>(FtdiRequest::LatencyTimer));
    EXPECT_EQ(bus.controls[0].value, 1);
    EXPECT_EQ(bus.controls[1].request, static_cast<std::uint8_t>(FtdiRequest::BaudRate));
    hal::HapticState s;
    ASSERT_TRUE(dev.read(s));
    ASSERT_TRUE(dev.commandForce({0.0, 0.0, 1.0}));
    ASSERT_TRUE(dev.read(s));
    // The command packet on the wire carries non-zero motor commands
    const Bytes &last = bus.written.back();
    ASSERT_EQ(last.size(), 16u);
    EXPECT_NE(Bytes(last.begin() + 1, last.begin() + 13), Bytes(12, 0x41));
    // WHEN the Falcon is unplugged mid-stream
    bus.unplug();
    hal::HapticState t;
    auto r = dev.read(t);
    // THEN the read says NoDevice, the device is disconnected and outputs no force
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().code, Errc::NoDevice);
    EXPECT_EQ(dev.state(), hal::HapticDevice::State::Disconnected);
    EXPECT_EQ(dev.outputForce(), hal::Vec3{});
    EXPECT_EQ(codeOf(dev.commandForce({0.0, 0.0, 1.0})), Errc::NoDevice);
    dev.close();
    EXPECT_EQ(dev.state(), hal::HapticDevice::State::Closed);
    EXPECT_EQ(bus.frees, bus.allocs);
    EXPECT_EQ(bus.exits, bus.inits);
}

} // namespace
} // namespace depthtouch::drivers
