/// \file
/// \brief The pads' frames to the player's media source: see pad_feed.h.

#include "pad_feed.h"

#include <chrono>
#include <utility>

namespace depthtouch::gst {

namespace {

constexpr std::array<FeedStream, 2> kStreams{FeedStream::Color, FeedStream::Depth};
/// How often a waiting reader looks at interrupt() and cancelRead() (their 100 ms promise).
constexpr std::chrono::milliseconds kPoll{20};

} // namespace

PadFeed::PadFeed(std::size_t capacity) : capacity_(capacity < 1 ? 1 : capacity) {}

void PadFeed::setStream(FeedStream s, const hal::StreamInfo &info)
{
    {
        const std::lock_guard lock(mutex_);
        at(s).info = info;
    }
    changed_.notify_all();
}

PushResult PadFeed::push(FeedStream s, std::vector<std::uint8_t> bytes, hal::Pts pts)
{
    std::unique_lock lock(mutex_);
    Stream &st = at(s);
    changed_.wait(lock, [&] { return closed_ || st.flushing || st.frames.size() < capacity_; });
    if (closed_)
        return PushResult::Closed;
    if (st.flushing)
        return PushResult::Flushing;
    st.ended = false; // frames after an end (a new segment) are read again
    st.frames.emplace_back(std::move(bytes), pts);
    lock.unlock();
    changed_.notify_all();
    return PushResult::Ok;
}

void PadFeed::endOfStream(FeedStream s)
{
    {
        const std::lock_guard lock(mutex_);
        at(s).ended = true;
    }
    changed_.notify_all();
}

bool PadFeed::flushStart(FeedStream s, bool seekFollows)
{
    bool began = true;
    {
        const std::lock_guard lock(mutex_);
        for (const Stream &other : streams_)
            began = began && !other.flushing;
        Stream &st = at(s);
        st.flushing = true;
        st.frames.clear();
        st.ended = false;
        if (began && seekFollows)
            seekPending_ = true;
    }
    changed_.notify_all();
    return began;
}

void PadFeed::flushStop(FeedStream s)
{
    {
        const std::lock_guard lock(mutex_);
        at(s).flushing = false;
    }
    changed_.notify_all();
}

void PadFeed::shutdown()
{
    {
        const std::lock_guard lock(mutex_);
        closed_ = true;
        for (Stream &st : streams_)
            st.frames.clear();
    }
    changed_.notify_all();
}

bool PadFeed::ended()
{
    const std::lock_guard lock(mutex_);
    return closed_ || (streams_[0].ended && streams_[1].ended);
}

// ---- the media source ---------------------------------------------------------------------------

PadMediaSource::PadMediaSource(std::shared_ptr<PadFeed> feed) : feed_(std::move(feed)) {}

void PadMediaSource::interrupt() noexcept
{
    interrupted_.store(true);
}

void PadMediaSource::cancelRead() noexcept
{
    cancelled_.store(true);
}

bool PadMediaSource::stopWaiting() noexcept
{
    return interrupted_.load() || cancelled_.exchange(false);
}

Result<void> PadMediaSource::openDevice(const char *)
{
    PadFeed &f = *feed_;
    std::unique_lock lock(f.mutex_);
    // Each stream described and with its first frame (its tags read), or ended without.
    const auto ready = [&] {
        bool any = false;
        for (FeedStream s : kStreams) {
            const PadFeed::Stream &st = f.at(s);
            if (!st.ended && !(st.info && !st.frames.empty()))
                return false;
            any = any || (st.info && !st.frames.empty());
        }
        return any || f.closed_;
    };
    while (!ready()) {
        if (interrupted_.load())
            return unexpected(Errc::Timeout, "Interrupted while waiting for the pads' caps");
        f.changed_.wait_for(lock, kPoll);
    }
    if (f.closed_)
        return unexpected(Errc::NoDevice, "The element stopped before its first frames");
    info_ = {};
    index_ = {-1, -1};
    for (FeedStream s : kStreams) {
        const PadFeed::Stream &st = f.at(s);
        if (!st.info || st.frames.empty())
            continue;
        hal::StreamInfo si = *st.info;
        si.index = static_cast<int>(info_.streams.size());
        si.kind = s == FeedStream::Depth ? hal::StreamKind::Depth : hal::StreamKind::Color;
        si.title = s == FeedStream::Depth ? "depth" : "color";
        si.titleFrom = "title";
        si.codec = hal::CodecId::RawVideo;
        si.timeBase = hal::Rational{1, 1'000'000'000};
        index_[static_cast<std::size_t>(s)] = si.index;
        info_.streams.push_back(std::move(si));
    }
    info_.seekable = true;  // as the pipeline seeks: seekDevice()
    f.seekPending_ = false; // a fresh open reads on from here
    return ok();
}

void PadMediaSource::closeDevice() noexcept
{
    info_ = {};
    index_ = {-1, -1};
    current_.clear();
    interrupted_.store(false);
    cancelled_.store(false);
}

Result<hal::Packet> PadMediaSource::readPacketDevice()
{
    PadFeed &f = *feed_;
    std::unique_lock lock(f.mutex_);
    for (;;) {
        if (f.closed_)
            return unexpected(Errc::EndOfStream, "The element stopped");
        if (f.seekPending_) { // a flushing seek: the new timeline is read after the player's seek
            if (stopWaiting())
                return unexpected(Errc::Timeout, "Interrupted while waiting for the seek");
            f.changed_.wait_for(lock, kPoll);
            continue;
        }
        // The earliest frame, once every stream read has one or has ended.
        const PadFeed::Stream *earliest = nullptr;
        FeedStream which = FeedStream::Color;
        bool waiting = false;
        bool left = false;
        for (FeedStream s : kStreams) {
            const PadFeed::Stream &st = f.at(s);
            if (index_[static_cast<std::size_t>(s)] < 0)
                continue;
            if (st.frames.empty()) {
                waiting = waiting || !st.ended;
                continue;
            }
            left = true;
            if (earliest == nullptr || st.frames.front().second < earliest->frames.front().second) {
                earliest = &st;
                which = s;
            }
        }
        if (!waiting && !left)
            return unexpected(Errc::EndOfStream, "Both pads ended");
        if (!waiting && earliest != nullptr) {
            PadFeed::Stream &st = f.at(which);
            auto [bytes, pts] = std::move(st.frames.front());
            st.frames.pop_front();
            current_ = std::move(bytes);
            lock.unlock();
            f.changed_.notify_all(); // room for the pad's next frame
            hal::Packet p;
            p.streamIndex = index_[static_cast<std::size_t>(which)];
            p.data = current_.data();
            p.size = current_.size();
            p.pts = pts;
            p.dts = pts;
            p.keyframe = true;
            return p;
        }
        // Not cancelRead(): only a flushing seek's wait gives way to the player's seek. A seek
        // the pipeline did not make (the control socket's) fails at seekDevice() and the
        // frames go on; a read it cancelled would have ended the input.
        if (interrupted_.load())
            return unexpected(Errc::Timeout, "Interrupted while waiting for the pads' frames");
        f.changed_.wait_for(lock, kPoll);
    }
}

Result<void> PadMediaSource::seekDevice(hal::Pts)
{
    PadFeed &f = *feed_;
    cancelled_.store(false); // what a cancelled read was cancelled for (as the FFmpeg source's)
    {
        const std::lock_guard lock(f.mutex_);
        if (!f.seekPending_)
            return unexpected(Errc::NotSupported,
                              "The pads' frames are sought by the pipeline (a flushing seek)");
        f.seekPending_ = false;
    }
    f.changed_.notify_all();
    return ok();
}

} // namespace depthtouch::gst
