#include "test_support.h"

#include <filesystem>

#include <gtest/gtest.h>

namespace depthtouch::receivertest {

FaultySource::FaultySource(std::unique_ptr<hal::MediaSource> inner, InfoEdit editInfo,
                           PacketEdit editPacket)
    : inner_(std::move(inner)), editInfo_(std::move(editInfo)), editPacket_(std::move(editPacket))
{
}

Result<void> FaultySource::open(const char *url)
{
    DT_TRY(inner_->open(url));
    info_ = inner_->info();
    if (editInfo_)
        editInfo_(info_);
    ordinal_ = 0;
    return ok();
}

Result<hal::Packet> FaultySource::readPacket()
{
    for (;;) {
        auto p = inner_->readPacket();
        if (!p || !editPacket_)
            return p;
        hal::Packet pkt = *p;
        if (editPacket_(pkt, ordinal_++))
            return pkt;
    }
}

Record recordOf(const receiver::PairedFrame &f)
{
    Record r;
    r.index = f.index;
    r.pts = f.pts;
    r.hasColor = static_cast<bool>(f.color);
    r.hasDepth = static_cast<bool>(f.depth);
    r.hasNext = static_cast<bool>(f.depthNext);
    if (f.color)
        r.colorPts = f.color->pts;
    const receiver::StoredDepthPair p = f.depthPair();
    r.depthPts = p.currentPts;
    r.nextPts = p.nextPts;
    if (p.current != nullptr)
        r.depthSample = p.current->image.planes[0].data[0];
    r.depthMissing = f.depthMissing;
    r.depthDuplicated = f.depthDuplicated;
    r.concealed = f.concealed;
    return r;
}

std::vector<Record> drain(receiver::Receiver &r, std::size_t limit)
{
    return drainAs<Record>(r, limit, recordOf);
}

Errc holdUntilRefused(receiver::Receiver &r, std::vector<receiver::PairedFrame> &held,
                      std::size_t limit)
{
    for (std::size_t i = 0; i < limit; ++i) {
        receiver::PairedFrame f;
        auto n = r.next(f);
        if (!n)
            return n.error().code;
        if (!*n) {
            ADD_FAILURE() << "the input ended while every frame was held";
            break;
        }
        held.push_back(std::move(f));
    }
    return Errc::InvalidArgument;
}

} // namespace depthtouch::receivertest
