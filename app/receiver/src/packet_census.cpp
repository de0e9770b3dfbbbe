/// \file
/// \brief The census of a 3D video for `depthtouch probe`: see packet_census.h.

#include "depthtouch/receiver/packet_census.h"

#include <algorithm>
#include <utility>

#include "depthtouch/scene/depth_frame.h"

namespace depthtouch::receiver {

namespace {

/// One frame period of rate \a r, ns (0 for an unknown rate).
hal::Pts packetPeriod(const hal::Rational &r)
{
    return r.num > 0 && r.den > 0
               ? hal::Pts(static_cast<std::int64_t>(1e9 * static_cast<double>(r.den) / r.num + 0.5))
               : hal::Pts{0};
}

} // namespace

PairingCensus pairPackets(const hal::MediaInfo &info, const StreamRoles &roles,
                          std::vector<StreamCount> &counts)
{
    PairingCensus out;
    const bool hasColor = roles.color >= 0;
    const bool hasDepth = roles.depth >= 0;
    if (!hasColor && !hasDepth)
        return out;
    const PairerConfig pc = PairerConfig::forStreams(
        hasColor, hasDepth,
        hasColor ? packetPeriod(info.streams[static_cast<std::size_t>(roles.color)].frameRate)
                 : hal::Pts{0},
        hasDepth ? packetPeriod(info.streams[static_cast<std::size_t>(roles.depth)].frameRate)
                 : hal::Pts{0});
    PtsPairer<int> pairer(pc);
    std::vector<hal::Pts> empty;
    std::vector<hal::Pts> &c = pc.color ? counts[static_cast<std::size_t>(roles.color)].pts : empty;
    std::vector<hal::Pts> &d = pc.depth ? counts[static_cast<std::size_t>(roles.depth)].pts : empty;
    std::sort(c.begin(), c.end());
    std::sort(d.begin(), d.end());
    std::size_t ci = 0;
    std::size_t di = 0;
    PtsPairer<int>::Output o;
    const auto drainOutputs = [&] {
        while (pairer.pull(o)) {
            if (o.hasColor) {
                ++out.colorFrames;
                if (!o.depthMissing && !o.depthDuplicated && o.hasDepth)
                    ++out.colorWithPartner;
            }
        }
    };
    while (ci < c.size() || di < d.size()) {
        const bool color = di >= d.size() || (ci < c.size() && c[ci] <= d[di]);
        PtsPairer<int>::Item item;
        item.pts = color ? c[ci++] : d[di++];
        (void)pairer.push(color ? PairStream::Color : PairStream::Depth, std::move(item));
        drainOutputs();
    }
    pairer.endOfStream(PairStream::Color);
    pairer.endOfStream(PairStream::Depth);
    drainOutputs();
    out.stats = pairer.stats();
    return out;
}

DemuxCensus countPackets(hal::MediaSource &src, std::size_t streams)
{
    DemuxCensus out;
    out.counts.resize(streams);
    for (;;) {
        auto p = src.readPacket();
        if (!p) {
            if (p.error().code != Errc::EndOfStream)
                out.readError = p.error().what;
            break;
        }
        ++out.packets;
        if (p->streamIndex < 0 || static_cast<std::size_t>(p->streamIndex) >= out.counts.size())
            continue;
        StreamCount &sc = out.counts[static_cast<std::size_t>(p->streamIndex)];
        ++sc.packets;
        sc.keyframes += p->keyframe ? 1u : 0u;
        sc.pts.push_back(p->pts);
    }
    src.close();
    return out;
}

std::vector<hal::Pts> streamSpans(const hal::MediaInfo &info,
                                  const std::vector<StreamCount> &counts)
{
    std::vector<hal::Pts> spans(counts.size(), hal::Pts{0});
    for (std::size_t i = 0; i < counts.size(); ++i) {
        const auto &v = counts[i].pts;
        if (!v.empty()) {
            const auto [lo, hi] = std::minmax_element(v.begin(), v.end());
            spans[i] = *hi - *lo + packetPeriod(info.streams[i].frameRate);
        }
    }
    return spans;
}

void HoleCount::add(const StoredFrame &d)
{
    if (d.sequence == lastSequence || d.image.planes[0].data == nullptr)
        return;
    lastSequence = d.sequence;
    scene::DepthFrameView v;
    v.data = d.image.planes[0].data;
    v.width = d.image.width;
    v.height = d.image.height;
    v.strideBytes = static_cast<std::size_t>(d.image.planes[0].strideBytes);
    v.format = d.image.format == hal::PixelFormat::Gray16 ? scene::SampleFormat::Gray16
                                                          : scene::SampleFormat::Gray8;
    v.holeBelow = d.holeBelow;
    samples += static_cast<std::uint64_t>(v.width) * static_cast<std::uint64_t>(v.height);
    if (v.holeBelow == 0)
        return;
    for (int y = 0; y < v.height; ++y)
        for (int x = 0; x < v.width; ++x)
            holes += v.measured(x, y) ? 0u : 1u;
}

HoleCount decodeToEnd(Receiver &r)
{
    PairedFrame f;
    HoleCount holes;
    for (;;) {
        auto n = r.next(f);
        if (!n || !*n)
            break;
        if (f.depth)
            holes.add(*f.depth);
    }
    return holes;
}

} // namespace depthtouch::receiver
