#pragma once
/// \file
/// \brief Test helpers of the receiver without FFmpeg: a temporary directory, a MediaSource
/// decorator that injects timestamp and size faults, and what a test records of each paired frame.

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "depthtouch/hal/media_source.h"
#include "depthtouch/receiver/receiver.h"
#include "support/allocation_counter.h"
#include "support/temp_dir.h"

namespace depthtouch::receivertest {

using TempDir = testing::TempDir;


/// \brief Wraps a MediaSource and lets a test edit what it reports.
class FaultySource final : public hal::MediaSource {
public:
    using InfoEdit = std::function<void(hal::MediaInfo &)>;
    /// Edits packet number \a ordinal (file order); return false to drop the packet.
    using PacketEdit = std::function<bool(hal::Packet &, std::uint64_t ordinal)>;

    FaultySource(std::unique_ptr<hal::MediaSource> inner, InfoEdit editInfo, PacketEdit editPacket);

    [[nodiscard]] State state() const noexcept override { return inner_->state(); }
    [[nodiscard]] Result<void> open(const char *url) override;
    void close() noexcept override { inner_->close(); }
    [[nodiscard]] const hal::MediaInfo &info() const noexcept override { return info_; }
    [[nodiscard]] Result<hal::Packet> readPacket() override;
    [[nodiscard]] Result<void> seek(hal::Pts position) override { return inner_->seek(position); }

private:
    std::unique_ptr<hal::MediaSource> inner_;
    InfoEdit editInfo_;
    PacketEdit editPacket_;
    hal::MediaInfo info_;
    std::uint64_t ordinal_ = 0;
};

/// What a test checks of one paired frame (the frame itself is dropped at once).
struct Record {
    std::uint64_t index = 0;
    hal::Pts pts = hal::kNoPts;
    hal::Pts colorPts = hal::kNoPts;
    hal::Pts depthPts = hal::kNoPts;
    hal::Pts nextPts = hal::kNoPts;
    bool hasColor = false;
    bool hasDepth = false;
    bool hasNext = false;
    bool depthMissing = false;
    bool depthDuplicated = false;
    bool concealed = false;
    int depthSample = -1; ///< Depth sample (0, 0) of frame i.
};
/// \return the record of \a f.
Record recordOf(const receiver::PairedFrame &f);

/// Every paired frame of \a r (bounded: fails the test instead of looping forever).
std::vector<Record> drain(receiver::Receiver &r, std::size_t limit = 100'000);

/// Every paired frame of \a r as \a record makes it, \a record(frame) → R (bounded as drain()).
template <class R, class F>
std::vector<R> drainAs(receiver::Receiver &r, std::size_t limit, F record)
{
    std::vector<R> out;
    for (std::size_t i = 0; i < limit; ++i) {
        receiver::PairedFrame f;
        auto n = r.next(f);
        if (!n) {
            ADD_FAILURE() << "next() failed: " << n.error().what;
            return out;
        }
        if (!*n)
            return out;
        out.push_back(record(f));
    }
    ADD_FAILURE() << "receiver did not end after " << limit << " frames";
    return out;
}

/// Opens \a url on \a rig (a test rig: open(url) → Result<std::unique_ptr<Receiver>>) into \a out,
/// reads \a count frames and drops them, then seeks to \a position; fails at the first step that
/// fails.
template <class Rig>
::testing::AssertionResult openReadAndSeek(Rig &rig, const std::string &url, int count,
                                           hal::Pts position,
                                           std::unique_ptr<receiver::Receiver> &out)
{
    auto r = rig.open(url);
    if (!r)
        return ::testing::AssertionFailure() << "open(" << url << ") failed: " << r.error().what;
    out = std::move(*r);
    receiver::PairedFrame f;
    for (int i = 0; i < count; ++i) {
        if (!out->next(f))
            return ::testing::AssertionFailure() << "next() failed at frame " << i;
    }
    if (!out->seek(position))
        return ::testing::AssertionFailure() << "seek() failed";
    return ::testing::AssertionSuccess();
}

/// openReadAndSeek() of the seek tests' clip (50 frames at 25 fps, a keyframe every 10 frames):
/// reads 5 frames, then seeks to 1 s (frame 25, decoded from keyframe 20).
template <class Rig>
::testing::AssertionResult openReadAndSeekTo1s(Rig &rig, std::unique_ptr<receiver::Receiver> &out)
{
    return openReadAndSeek(rig, "mock://clip?frames=50&fps=25&gop=10", 5,
                           std::chrono::milliseconds(1000), out);
}

/// \return whether one of the notes of \a owner (a ReceiverInfo, a StreamRoles: anything with a
/// `notes` vector of strings) contains \a text.
template <class T> bool hasNoteWith(const T &owner, const std::string &text)
{
    for (const auto &n : owner.notes)
        if (n.find(text) != std::string::npos)
            return true;
    return false;
}

/// What drainCountingAllocations() saw.
struct CountedDrain {
    std::size_t frames = 0;      ///< Frames read after the warm-up frame.
    std::size_t allocations = 0; ///< operator new calls on this thread while they were read.
};

/// Reads one warm-up frame of \a r (a test failure if there is none), then every further frame to
/// the end with heap allocations counted, handing each to \a onFrame(frame). A test program that
/// calls it links dt_test_allocation_counter.
template <class F> CountedDrain drainCountingAllocations(receiver::Receiver &r, F onFrame)
{
    CountedDrain out;
    receiver::PairedFrame f;
    const auto warm = r.next(f);
    EXPECT_TRUE(warm) << "warm-up frame";
    if (!warm)
        return out;
    testing::AllocationCounter count;
    for (;;) {
        auto n = r.next(f);
        if (!n || !*n)
            break;
        ++out.frames;
        onFrame(f);
    }
    out.allocations = count.count();
    return out;
}

/// Plays a consumer that keeps every frame: takes frames from \a r into \a held until next()
/// fails, at most \a limit calls. The end of the input before that is a test failure.
/// \return the code of the failed next(); InvalidArgument when none failed.
Errc holdUntilRefused(receiver::Receiver &r, std::vector<receiver::PairedFrame> &held,
                      std::size_t limit);

/// Frames a holding consumer may keep (ReceiverConfig::consumerFrames, holdEveryFrame()).
constexpr int kHeldConsumerFrames = 2;

/// A consumer that kept every frame of its receiver (holdEveryFrame()).
struct HoldingConsumer {
    std::unique_ptr<receiver::Receiver> receiver; ///< Null when open() failed.
    std::vector<receiver::PairedFrame> held;
    Errc refusal = Errc::InvalidArgument; ///< What holdUntilRefused() returned.

    /// Drops every held frame. \return how many there were.
    std::size_t letGo()
    {
        const std::size_t n = held.size();
        held.clear();
        return n;
    }
};

/// Opens \a url on \a rig (a test rig: open(url, cfg) → Result<std::unique_ptr<Receiver>>) for a
/// consumer that may hold kHeldConsumerFrames frames, with a pairing window of 2, then holds frames
/// until next() refuses, at most \a limit calls (holdUntilRefused()). A failed open leaves
/// `receiver` null.
template <class Rig>
HoldingConsumer holdEveryFrame(Rig &rig, const std::string &url, std::size_t limit)
{
    receiver::ReceiverConfig cfg;
    cfg.consumerFrames = kHeldConsumerFrames;
    cfg.pairingWindow = 2;
    HoldingConsumer out;
    auto r = rig.open(url, cfg);
    if (!r)
        return out;
    out.receiver = std::move(*r);
    out.refusal = holdUntilRefused(*out.receiver, out.held, limit);
    return out;
}

} // namespace depthtouch::receivertest
