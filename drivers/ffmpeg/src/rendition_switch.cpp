/// \file
/// \brief Changing rendition while reading (see rendition_switch.h).

#include "rendition_switch.h"

#include <algorithm>
#include <climits>

#include "depthtouch/platform/log.h"
#include "rendition_match.h"

extern "C" {
#include <libavformat/avformat.h>
#include <libavutil/mathematics.h>
}

DT_LOG_CATEGORY(Ffmpeg)

namespace depthtouch::drivers::ffmpeg {

namespace {

constexpr AVRational kMicroseconds{1, AV_TIME_BASE};
constexpr std::int64_t kNone = INT64_MIN;
/// Packets read past the first key frame at K before the switch goes ahead without the video
/// streams that did not reach K (a stream with no key frame there: it joins at its next one).
constexpr int kMaxPlannedPackets = 2000;

std::int64_t microseconds(std::int64_t ts, AVRational tb) noexcept
{
    return ts == AV_NOPTS_VALUE ? kNone : av_rescale_q(ts, tb, kMicroseconds);
}

} // namespace

void RenditionSwitch::start(const AVFormatContext &ctx, int kept,
                            const std::vector<int> &videoDelivered,
                            const std::vector<hal::RenditionInfo> &rungs)
{
    current_ = -1;
    if (kept < 0 || ctx.nb_programs < 2 || rungs.size() != ctx.nb_programs ||
        ctx.duration == AV_NOPTS_VALUE || ctx.duration <= 0)
        return;
    kept_ = current_ = kept;
    tracks_.assign(ctx.nb_streams, Track{});
    for (int i : videoDelivered)
        if (i >= 0 && static_cast<unsigned>(i) < ctx.nb_streams)
            tracks_[static_cast<std::size_t>(i)].video = true;
    sizes_ = rungs;
    rungs_.clear();
    refusals_.assign(rungs.size(), std::string());
    for (std::size_t p = 0; p < rungs.size(); ++p) {
        refusals_[p] = renditionMismatch(ctx, kept, static_cast<int>(p));
        rungs_.push_back(Rung{rungs[p].bitRate, refusals_[p].empty()});
    }
    mapProgram(ctx, kept);
}

std::size_t RenditionSwitch::choose(double now)
{
    const double bps = throughput_.bitsPerSecond();
    const auto current = static_cast<std::size_t>(current_);
    const std::size_t to = RenditionPolicy::choose(rungs_, current, bps, now - lastSwitch_);
    // The rung the rule would take were every rung usable: when it is not, say why, once.
    std::vector<Rung> all = rungs_;
    for (Rung &r : all)
        r.usable = true;
    const std::size_t wanted = RenditionPolicy::choose(all, current, bps, now - lastSwitch_);
    if (wanted != to && !refusals_[wanted].empty()) {
        const hal::RenditionInfo &b = sizes_[wanted];
        const hal::RenditionInfo &k = sizes_[static_cast<std::size_t>(kept_)];
        DT_LOG(Ffmpeg, Warning,
               "Rendition %dx%d refused: %s (the decoders were opened for %dx%d's); playing "
               "%dx%d",
               b.width, b.height, refusals_[wanted].c_str(), k.width, k.height, sizes_[to].width,
               sizes_[to].height);
        refusals_[wanted].clear(); // said once
    }
    return to;
}

void RenditionSwitch::mapProgram(const AVFormatContext &ctx, int program)
{
    identityOf_.assign(ctx.nb_streams, -1);
    const AVProgram &kept = *ctx.programs[kept_];
    const AVProgram &p = *ctx.programs[program];
    for (unsigned k = 0; k < kept.nb_stream_indexes; ++k) {
        const unsigned i = kept.stream_index[k];
        if (i >= ctx.nb_streams)
            continue;
        const AVMediaType type = ctx.streams[i]->codecpar->codec_type;
        int ordinal = 0; // of its kind, before it in the kept program
        for (unsigned j = 0; j < k; ++j)
            if (kept.stream_index[j] < ctx.nb_streams &&
                ctx.streams[kept.stream_index[j]]->codecpar->codec_type == type)
                ++ordinal;
        const int mine = streamOfKind(ctx, p, type, ordinal);
        if (mine >= 0)
            identityOf_[static_cast<std::size_t>(mine)] = static_cast<int>(i);
    }
}

int RenditionSwitch::identity(int avIndex) const noexcept
{
    if (current_ < 0)
        return avIndex;
    if (avIndex < 0 || static_cast<std::size_t>(avIndex) >= identityOf_.size())
        return -1;
    return identityOf_[static_cast<std::size_t>(avIndex)];
}

void RenditionSwitch::plan(int to) noexcept
{
    target_ = to;
    phase_ = Phase::Planned;
    keyPts_ = kNone;
    packetsPlanned_ = 0;
    bool known = true;
    for (Track &t : tracks_) {
        t.reached = false;
        if (t.video && (t.keyInterval <= 0 || t.lastKeyDts == kNone))
            known = false;
    }
    if (!known || rungs_[static_cast<std::size_t>(to)].bitRate >=
                      rungs_[static_cast<std::size_t>(current_)].bitRate)
        return;
    for (Track &t : tracks_)
        if (t.video) {
            t.reached = true;
            t.keyDts = t.lastKeyDts + t.keyInterval;
        }
    phase_ = Phase::Due;
}

RenditionSwitch::Verdict RenditionSwitch::judge(const AVFormatContext &ctx, const AVPacket &p,
                                                double waited, double now) noexcept
{
    const int id = identity(p.stream_index);
    if (id < 0)
        return Verdict::Drop;
    if (lastSwitch_ < 0.0)
        lastSwitch_ = now;
    now_ = now;
    if (throughput_.add(static_cast<std::size_t>(std::max(p.size, 0)), waited, now) &&
        phase_ == Phase::Steady) {
        const std::size_t to = choose(now);
        if (static_cast<int>(to) != current_)
            plan(static_cast<int>(to));
    }
    Track &t = tracks_[static_cast<std::size_t>(id)];
    const AVRational tb = ctx.streams[p.stream_index]->time_base;
    const std::int64_t pts = microseconds(p.pts != AV_NOPTS_VALUE ? p.pts : p.dts, tb);
    const std::int64_t dts = microseconds(p.dts != AV_NOPTS_VALUE ? p.dts : p.pts, tb);
    const bool key = (p.flags & AV_PKT_FLAG_KEY) != 0;
    Verdict v = Verdict::Deliver;
    if (phase_ == Phase::Planned) {
        v = judgePlanned(t, key, pts, dts);
    } else if (phase_ == Phase::Due) {
        v = t.video && dts != kNone && dts < t.keyDts ? Verdict::Deliver : Verdict::Drop;
    } else if (phase_ == Phase::Joining) {
        const bool after = pts == kNone || t.last == kNone || pts > t.last;
        if (!after || (t.video && !t.joined && !key))
            v = Verdict::Drop;
        else if (t.video)
            t.joined = true;
        if (std::none_of(tracks_.begin(), tracks_.end(),
                         [](const Track &x) { return x.video && !x.joined; }))
            phase_ = Phase::Steady;
    }
    if (v == Verdict::Deliver && pts != kNone)
        t.last = pts;
    if (v == Verdict::Deliver && key && t.video && dts != kNone) {
        if (t.lastKeyDts != kNone && dts > t.lastKeyDts)
            t.keyInterval = dts - t.lastKeyDts;
        t.lastKeyDts = dts;
    }
    return v;
}

RenditionSwitch::Verdict RenditionSwitch::judgePlanned(Track &t, bool key, std::int64_t pts,
                                                       std::int64_t dts) noexcept
{
    if (keyPts_ != kNone && ++packetsPlanned_ > kMaxPlannedPackets) {
        phase_ = Phase::Due;
        return Verdict::Drop;
    }
    if (!t.video)
        return keyPts_ != kNone && pts != kNone && pts >= keyPts_ ? Verdict::Drop
                                                                  : Verdict::Deliver;
    if (t.reached)
        return Verdict::Drop;
    if (!key)
        return Verdict::Deliver;
    t.reached = true;
    t.keyDts = dts;
    if (keyPts_ == kNone)
        keyPts_ = pts;
    if (std::none_of(tracks_.begin(), tracks_.end(),
                     [](const Track &x) { return x.video && !x.reached; }))
        phase_ = Phase::Due;
    return Verdict::Drop;
}

void RenditionSwitch::keepProgram(AVFormatContext &ctx, int program) const noexcept
{
    for (unsigned i = 0; i < ctx.nb_streams; ++i)
        ctx.streams[i]->discard = AVDISCARD_ALL;
    const AVProgram &p = *ctx.programs[program];
    for (unsigned k = 0; k < p.nb_stream_indexes; ++k)
        if (p.stream_index[k] < ctx.nb_streams)
            ctx.streams[p.stream_index[k]]->discard = AVDISCARD_DEFAULT;
}

Result<void> RenditionSwitch::perform(AVFormatContext &ctx)
{
    // The stream whose key frame at K decodes first: the demuxer drops what comes before it.
    int first = -1;
    for (std::size_t i = 0; i < tracks_.size(); ++i)
        if (tracks_[i].reached &&
            (first < 0 || tracks_[i].keyDts < tracks_[static_cast<std::size_t>(first)].keyDts))
            first = static_cast<int>(i);
    const int from = current_;
    const auto seekTo = [&](int program) {
        mapProgram(ctx, program);
        int st = -1;
        for (std::size_t i = 0; i < identityOf_.size() && first >= 0; ++i)
            if (identityOf_[i] == first)
                st = static_cast<int>(i);
        if (st < 0)
            return AVERROR_STREAM_NOT_FOUND;
        keepProgram(ctx, program);
        const std::int64_t dts = tracks_[static_cast<std::size_t>(first)].keyDts;
        return av_seek_frame(&ctx, st, av_rescale_q(dts, kMicroseconds, ctx.streams[st]->time_base),
                             0);
    };
    phase_ = Phase::Joining;
    for (Track &t : tracks_)
        t.joined = false;
    lastSwitch_ = now_;
    const double kbps = throughput_.bitsPerSecond() / 1000.0;
    const hal::RenditionInfo &a = sizes_[static_cast<std::size_t>(from)];
    const hal::RenditionInfo &b = sizes_[static_cast<std::size_t>(target_)];
    const std::int64_t at = first < 0 ? 0 : tracks_[static_cast<std::size_t>(first)].keyDts;
    if (seekTo(target_) >= 0) {
        current_ = target_;
        const std::int64_t start = ctx.start_time == AV_NOPTS_VALUE ? 0 : ctx.start_time;
        DT_LOG(Ffmpeg, Info, "Rendition %dx%d -> %dx%d at %.3f s (throughput %.0f kbit/s)", a.width,
               a.height, b.width, b.height, static_cast<double>(at - start) / 1e6, kbps);
        return ok();
    }
    DT_LOG(Ffmpeg, Warning, "Rendition %dx%d could not be sought to: staying at %dx%d", b.width,
           b.height, a.width, a.height);
    if (seekTo(from) >= 0)
        return ok();
    current_ = -1;
    return unexpected(Errc::Io, "Failed to seek back to the rendition played");
}

void RenditionSwitch::onSeek() noexcept
{
    phase_ = Phase::Steady;
    for (Track &t : tracks_) {
        t.last = kNone;
        t.lastKeyDts = kNone;
        t.keyInterval = 0;
    }
}

} // namespace depthtouch::drivers::ffmpeg
