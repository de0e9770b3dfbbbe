#include <algorithm>
#include <cstring>
#include <string>
#include <utility>

#include "depthtouch/platform/log.h"
#include "receiver_impl.h"

DT_LOG_CATEGORY(Receiver)

// The receiver's decoding: reading packets into the decoders, taking decoded frames into the
// stores, pausing and ending streams, and the pairer's output as PairedFrames.

namespace depthtouch::receiver {

Take Receiver::Impl::takeFrame(Stream &s)
{
    if (!s.pending) {
        if (s.drained || (!s.eosQueued && s.decoder->state() != hal::VideoDecoder::State::Running))
            return Take::Nothing;
        auto f = s.decoder->dequeueFrame(hal::Deadline{}); // a past deadline: poll
        if (!f) {
            switch (f.error().code) {
            case Errc::EndOfStream:
                s.drained = true;
                pairer->endOfStream(s.which);
                return Take::Progress;
            case Errc::Io:
            case Errc::InvalidArgument:
                ++stats.decodeErrors;
                DT_LOG(Receiver, Debug, "%s decoder dropped a packet: %s",
                       s.which == PairStream::Depth ? "Depth" : "Color", f.error().what);
                return Take::Progress;
            case Errc::Busy: // its frames are held: here only when kept zero-copy
                s.decoderBusy = s.zeroCopy;
                return s.zeroCopy ? Take::DecoderBusy : Take::Nothing;
            default: // Timeout: nothing ready
                return Take::Nothing;
            }
        }
        s.decoderBusy = false;
        s.pending = std::move(*f);
        ++(s.which == PairStream::Depth ? stats.depthFrames : stats.colorFrames);
    }
    const hal::Frame &fr = *s.pending;
    if (skipBefore != hal::kNoPts && fr.pts != hal::kNoPts && fr.pts < skipBefore) {
        s.pending.reset(); // before the seek target
        return Take::Progress;
    }
    StoredFrame *w = nullptr;
    FrameHandle h = s.store.acquire(w);
    if (!h)
        return Take::Busy;
    const hal::ImageView &src = fr.image;
    hal::ImageView &dst = w->image;
    // A colour frame lent as dma-bufs is kept, not copied: the renderer imports it.
    const bool zeroCopy = !fr.dmabuf.empty() && s.which == PairStream::Color;
    if (src.width != dst.width || src.height != dst.height ||
        (src.format != dst.format && !zeroCopy)) {
        ++stats.frameSizeChanges;
        DT_LOG(Receiver, Warning, "Dropped a %s frame of %dx%d %s: the stream is %dx%d %s",
               s.which == PairStream::Depth ? "depth" : "color", src.width, src.height,
               hal::pixelFormatName(src.format), dst.width, dst.height,
               hal::pixelFormatName(dst.format));
        s.pending.reset();
        return Take::Progress;
    }
    if (!zeroCopy && src.empty()) { // dma-buf only, but not a colour frame: no CPU pixels
        ++stats.decodeErrors;
        DT_LOG_ONCE(Receiver, Warning, "Dropped %s frames without CPU planes",
                    s.which == PairStream::Depth ? "depth" : "color");
        s.pending.reset();
        return Take::Progress;
    }
    if (zeroCopy) {
        if (!s.zeroCopy) {
            const int pool = s.decoder->capabilities().poolFrames;
            DT_LOG(Receiver, Info, "Color frames are kept as the decoder's dma-bufs (no copy)");
            if (pool < s.store.size())
                DT_LOG(Receiver, Warning,
                       "The color decoder lends %d frames, fewer than the %d the receiver may "
                       "hold: playback may wait for frames (raise the decoder's pool)",
                       pool, s.store.size());
        }
        s.zeroCopy = true;
        ++stats.colorFramesZeroCopy;
        dst = src;
        w->dmabuf = fr.dmabuf;
        w->decoded = std::move(s.pending); // fr stays valid: w->decoded holds it
    } else {
        for (int p = 0; p < hal::planeCount(dst.format); ++p) {
            const hal::PlaneLayout l = hal::planeLayout(dst.format, dst.width, dst.height, p);
            const auto rowBytes = static_cast<std::size_t>(l.rowBytes);
            for (int y = 0; y < l.rows; ++y)
                std::memcpy(dst.row(p, y), src.row(p, y), rowBytes);
        }
    }
    w->kind = s.which == PairStream::Depth ? hal::StreamKind::Depth : hal::StreamKind::Color;
    w->pts = fr.pts;
    w->corrupt = fr.corrupt;
    w->sequence = s.sequence++;
    s.pending.reset();
    DT_ASSERT(pairer->canPush(s.which));
    Pairer::Item item;
    item.pts = w->pts;
    item.corrupt = w->corrupt;
    item.payload = std::move(h);
    const PushOutcome o = pairer->push(s.which, std::move(item));
    if (o != PushOutcome::Accepted)
        DT_LOG(Receiver, Debug, "Dropped a %s frame: %s PTS",
               s.which == PairStream::Depth ? "depth" : "color",
               o == PushOutcome::Duplicate ? "duplicate" : "non-monotonic");
    return Take::Progress;
}

void Receiver::Impl::drainLaggingStream()
{
    // One stream's frames wait while the other's stopped coming (a shorter stream, or a long gap):
    // drain the quiet stream's decoder so the frames it still holds (reordering delay) pair before
    // the pairing window forces decisions without them. Packets that come later resume it.
    if (!streams[0].used || !streams[1].used || inputEnded)
        return;
    const auto window = static_cast<std::size_t>(cfg.pairingWindow);
    Stream *quiet = nullptr;
    if (pairer->waiting(PairStream::Color) >= window)
        quiet = &streams[1];
    else if (pairer->waiting(PairStream::Depth) >= window &&
             pairer->waiting(PairStream::Color) == 0)
        quiet = &streams[0];
    // A decoder waiting for its zero-copy frames to come back is blocked, not quiet.
    if (quiet == nullptr || quiet->eosQueued || quiet->decoderBusy)
        return;
    if (quiet->decoder->queuePacket(hal::Packet::endOfStream(quiet->info.index))) {
        quiet->eosQueued = true;
        quiet->paused = true;
        DT_LOG(Receiver, Debug, "The %s stream paused or ended: draining its decoder",
               quiet->which == PairStream::Depth ? "depth" : "color");
    }
}

void Receiver::Impl::endInput()
{
    inputEnded = true;
    havePacket = false;
    for (Stream &s : streams) {
        s.paused = false;
        if (!s.used || s.eosQueued)
            continue;
        if (s.decoder->queuePacket(hal::Packet::endOfStream(s.info.index))) {
            s.eosQueued = true;
        } else { // cannot drain: what it holds is lost
            s.eosQueued = true;
            s.drained = true;
            pairer->endOfStream(s.which);
        }
    }
}

bool Receiver::Impl::readAndQueue()
{
    if (!havePacket) {
        auto p = source->readPacket();
        if (!p) {
            if (p.error().code != Errc::EndOfStream) {
                ++stats.readErrors;
                char buf[160];
                DT_LOG(Receiver, Warning, "Failed to read the input (%s): ending it here",
                       p.error().format(buf, sizeof buf));
            }
            endInput();
            return true;
        }
        ++stats.packetsRead;
        if (streamOf(p->streamIndex) == nullptr) {
            ++stats.packetsIgnored;
            return true;
        }
        packet = *p;
        havePacket = true;
    }
    Stream &s = *streamOf(packet.streamIndex);
    if (s.paused) { // it had only paused: decode again (from its next keyframe)
        (void)s.decoder->flush();
        s.paused = s.eosQueued = s.drained = false;
        pairer->resume(s.which);
        ++stats.streamsResumed;
        DT_LOG(Receiver, Warning, "The %s stream resumes after a pause",
               s.which == PairStream::Depth ? "depth" : "color");
    }
    auto q = s.decoder->queuePacket(packet);
    if (q) {
        havePacket = false;
        return true;
    }
    if (q.error().code == Errc::Busy)
        return false; // the decoder must output first
    ++stats.decodeErrors;
    havePacket = false;
    DT_LOG(Receiver, Debug, "Decoder refused a packet: %s", q.error().what);
    return true;
}

void Receiver::Impl::toPaired(Pairer::Output &o, PairedFrame &out)
{
    out.color = o.hasColor ? std::move(o.color.payload) : FrameHandle{};
    out.depth = o.hasDepth ? std::move(o.depth.payload) : FrameHandle{};
    out.depthNext = o.hasNext ? std::move(o.depthNext.payload) : FrameHandle{};
    out.pts = o.pts;
    out.index = o.index;
    out.depthMissing = o.depthMissing;
    out.depthDuplicated = o.depthDuplicated;
    out.concealed = o.concealed;
    out.generation = 0;
    ++stats.framesOutput;
    if (o.concealed)
        ++stats.framesConcealed;
}

} // namespace depthtouch::receiver
