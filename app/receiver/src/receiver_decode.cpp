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
    // A paired frame waiting for its material keeps the pairer's queues from draining: leave the
    // frames of a full one in its decoder (the material track's queue is never full).
    if (!s.material && !pairer->canPush(s.which))
        return Take::Nothing;
    if (!s.pending) {
        if (s.drained || (!s.eosQueued && s.decoder->state() != hal::VideoDecoder::State::Running))
            return Take::Nothing;
        auto f = s.decoder->dequeueFrame(hal::Deadline{}); // a past deadline: poll
        if (!f) {
            switch (f.error().code) {
            case Errc::EndOfStream:
                s.drained = true;
                endStream(s);
                return Take::Progress;
            case Errc::Io:
            case Errc::InvalidArgument:
                ++stats.decodeErrors;
                DT_LOG(Receiver, Debug, "The %s decoder dropped a packet: %s", s.name,
                       f.error().what);
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
        ++(s.material                     ? stats.materialFrames
           : s.which == PairStream::Depth ? stats.depthFrames
                                          : stats.colorFrames);
    }
    const hal::Frame &fr = *s.pending;
    // Material frames before the seek target are kept: the newest of them holds at the target.
    if (!s.material && skipBefore != hal::kNoPts && fr.pts != hal::kNoPts && fr.pts < skipBefore) {
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
    const bool zeroCopy = !fr.dmabuf.empty() && s.which == PairStream::Color && !s.material;
    if (src.width != dst.width || src.height != dst.height ||
        (src.format != dst.format && !zeroCopy)) {
        ++stats.frameSizeChanges;
        DT_LOG(Receiver, Warning, "Dropped a %s frame of %dx%d %s: the stream is %dx%d %s", s.name,
               src.width, src.height, hal::pixelFormatName(src.format), dst.width, dst.height,
               hal::pixelFormatName(dst.format));
        s.pending.reset();
        return Take::Progress;
    }
    if (!zeroCopy && src.empty()) { // dma-buf only, but not a colour frame: no CPU pixels
        ++stats.decodeErrors;
        DT_LOG_ONCE(Receiver, Warning, "Dropped %s frames without CPU planes", s.name);
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
    // Material frames are RGB24 codes, decoded as a colour stream (hal has no material kind).
    w->kind = s.which == PairStream::Depth && !s.material ? hal::StreamKind::Depth
                                                          : hal::StreamKind::Color;
    w->holeBelow = w->kind == hal::StreamKind::Depth ? info.depthHoleBelow : 0u;
    w->pts = fr.pts;
    w->corrupt = fr.corrupt;
    w->sequence = s.sequence++;
    s.pending.reset();
    pushFrame(s, std::move(h), *w);
    return Take::Progress;
}

void Receiver::Impl::pushFrame(Stream &s, FrameHandle &&h, const StoredFrame &f)
{
    if (s.material) {
        if (f.corrupt) {
            // Concealed codes are not a material: a damaged lossless track would be felt as
            // stiffness 0 (nothing under the finger). The previous material frame holds.
            if (stats.materialDamaged++ == 0)
                DT_LOG(Receiver, Warning,
                       "The material track is damaged (frame at %.3f s): its damaged frames are "
                       "skipped and the previous material holds",
                       f.pts == hal::kNoPts ? -1.0 : platform::toSeconds(f.pts));
            return;
        }
        // On the depth stream's re-based timeline (the material frames follow its splices).
        const hal::Pts pts =
            f.pts == hal::kNoPts ? f.pts : f.pts + pairer->offset(PairStream::Depth);
        if (!materials->push(pts, std::move(h)))
            DT_LOG(Receiver, Debug, "Dropped a material frame: PTS not after the previous one");
        return;
    }
    DT_ASSERT(pairer->canPush(s.which));
    Pairer::Item item;
    item.pts = f.pts;
    item.corrupt = f.corrupt;
    item.payload = std::move(h);
    const PushOutcome o = pairer->push(s.which, std::move(item));
    if (o != PushOutcome::Accepted)
        DT_LOG(Receiver, Debug, "Dropped a %s frame: %s PTS", s.name,
               o == PushOutcome::Duplicate ? "duplicate"
               : o == PushOutcome::Jump    ? "jumping"
                                           : "non-monotonic");
}

void Receiver::Impl::endStream(Stream &s)
{
    if (s.material)
        materials->endOfStream();
    else
        pairer->endOfStream(s.which);
}

bool Receiver::Impl::materialReady() const noexcept
{
    if (!materials || !havePending || !pending.hasDepth)
        return true;
    return materials->ready(pending.depth.pts) &&
           (!pending.hasNext || materials->ready(pending.depthNext.pts));
}

void Receiver::Impl::drainLaggingMaterial()
{
    // The paired frame waits for a material frame that has not come while the pairing window
    // filled: a still material (no more packets) or a lagging track. Drain its decoder so what it
    // holds comes out and the track counts as ended; packets that come later resume it.
    Stream &m = streams[2];
    if (!m.used || inputEnded || m.eosQueued || m.decoderBusy || materialReady())
        return;
    // The pending frame's depth frames i and i+1 wait in the pairer too: the material lags by
    // about window frames when either queue is one short of full (window + 2), which leaves a
    // frame of room for the decoders while the material decoder drains.
    const auto lagging = static_cast<std::size_t>(cfg.pairingWindow) + 1;
    if (pairer->waiting(PairStream::Color) < lagging &&
        pairer->waiting(PairStream::Depth) < lagging)
        return;
    if (m.decoder->queuePacket(hal::Packet::endOfStream(m.info.index))) {
        m.eosQueued = true;
        m.paused = true;
        DT_LOG(Receiver, Debug,
               "The material stream paused or holds a still: draining its decoder");
    } else { // cannot drain: decide without what it holds
        m.eosQueued = m.paused = m.drained = true;
        endStream(m);
    }
}

void Receiver::Impl::drainLaggingStream()
{
    // One stream's packets stopped while the other's went on (a shorter stream, or a long gap):
    // drain the quiet stream's decoder so the frames it still holds (reordering delay) pair before
    // the pairing window forces decisions without them. Packets that come later resume it, with a
    // flush: it decodes again from its next key frame.
    if (havePending) { // waiting for material, not for color or depth
        drainLaggingMaterial();
        return;
    }
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
    // Lagging frames alone do not make a stream quiet: its packets must have stopped. A damaged
    // stream whose packets still come gives fewer frames than packets (libavcodec keeps back the
    // pictures it cannot place after a loss, and refuses the undecodable ones); draining it would
    // end its decoding state, and its resume's flush would then hold every frame until the next
    // key frame (seconds: 250 frames in a file), where ffmpeg, not flushed, decodes on. Its frames
    // come again by themselves. A stream still sending has a packet among any window / 2 + 1 of
    // the other's: with the default window of 8, at the other's frame rate three of its packets
    // may be lost in a row, at half that rate one.
    if (quiet->partnerPackets <= window / 2)
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
            endStream(s);
        }
    }
}

bool Receiver::Impl::readAndQueue()
{
    if (!havePacket) {
        auto p = source->readPacket();
        if (!p) {
            // Timeout: a stop or a seek cancelled the read (the input then ends here, and a seek
            // restarts it); not a fault of the input.
            if (p.error().code != Errc::EndOfStream && p.error().code != Errc::Timeout) {
                ++stats.readErrors;
                char buf[160];
                DT_LOG(Receiver, Warning, "Failed to read the input (%s): ending it here",
                       p.error().format(buf, sizeof buf));
            }
            endInput();
            return true;
        }
        ++stats.packetsRead;
        if (p->audio) { // a live input's sound, for the audio thread
            if (audioSink != nullptr)
                audioSink->push(*p);
            return true;
        }
        if (streamOf(p->streamIndex) == nullptr) {
            ++stats.packetsIgnored;
            return true;
        }
        packet = *p;
        havePacket = true;
        if (Stream &s = *streamOf(packet.streamIndex); !s.material) {
            s.partnerPackets = 0;
            ++streams[s.which == PairStream::Depth ? 0 : 1].partnerPackets;
        }
    }
    Stream &s = *streamOf(packet.streamIndex);
    if (s.paused) { // it had only paused: decode again (from its next keyframe)
        (void)s.decoder->flush();
        s.paused = s.eosQueued = s.drained = false;
        if (s.material)
            materials->resume();
        else
            pairer->resume(s.which);
        ++stats.streamsResumed;
        DT_LOG(Receiver, Warning, "The %s stream resumes after a pause", s.name);
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
    out.depthPts = o.hasDepth ? o.depth.pts : hal::kNoPts; // the re-based timeline, as o.pts
    out.depthNextPts = o.hasNext ? o.depthNext.pts : hal::kNoPts;
    out.material = FrameHandle{};
    out.materialNext = FrameHandle{};
    if (materials && o.hasDepth) {
        hal::Pts found = hal::kNoPts;
        switch (materials->find(o.depth.pts, out.material, found)) {
        case MaterialTrack::Match::Same:
            break;
        case MaterialTrack::Match::Held:
            ++stats.materialHeld;
            break;
        case MaterialTrack::Match::Missing:
            ++stats.materialMissing;
            break;
        }
        if (o.hasNext)
            (void)materials->find(o.depthNext.pts, out.materialNext, found);
        materials->release(o.depth.pts);
    }
    out.pts = o.pts;
    out.index = o.index;
    out.depthMissing = o.depthMissing;
    out.depthDuplicated = o.depthDuplicated;
    out.concealed = o.concealed;
    out.discontinuity = o.discontinuity;
    out.generation = 0;
    ++stats.framesOutput;
    if (o.concealed)
        ++stats.framesConcealed;
}

} // namespace depthtouch::receiver
