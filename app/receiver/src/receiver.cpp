#include "depthtouch/receiver/receiver.h"

#include <algorithm>
#include <cstring>
#include <string>

#include "depthtouch/platform/log.h"
#include "depthtouch/receiver/pts_pairer.h"

DT_LOG_CATEGORY(Receiver)

namespace depthtouch::receiver {

namespace {

using Pairer = PtsPairer<FrameHandle>;

constexpr hal::Pts kDefaultPeriod{33'333'333}; // 30 fps when a stream does not say
/// Loop passes without progress after which next() gives up on a decoder that neither outputs nor
/// drains (a broken backend): the input is ended instead of spinning forever.
constexpr int kStallPasses = 10'000;

bool isGray(hal::PixelFormat f) noexcept
{
    return f == hal::PixelFormat::Gray8 || f == hal::PixelFormat::Gray10 ||
           f == hal::PixelFormat::Gray16;
}

hal::Pts periodOf(const hal::Rational &rate) noexcept
{
    if (rate.num <= 0 || rate.den <= 0)
        return hal::Pts{0};
    const double p = 1e9 * static_cast<double>(rate.den) / static_cast<double>(rate.num);
    return p >= 1e5 && p <= 1e10 ? hal::Pts(static_cast<std::int64_t>(p + 0.5)) : hal::Pts{0};
}

/// DecoderBusy: the decoder has lent every frame, held here as zero-copy frames.
enum class Take : std::uint8_t { Progress, Nothing, Busy, DecoderBusy };

} // namespace

const char *receiverModeName(ReceiverMode mode) noexcept
{
    switch (mode) {
    case ReceiverMode::ColorAndDepth:
        return "color+depth";
    case ReceiverMode::ColorOnly:
        return "color-only";
    case ReceiverMode::DepthOnly:
        return "depth-only";
    }
    return "?";
}

DepthPair PairedFrame::depthPair() const noexcept
{
    DepthPair p;
    p.current = depth.get();
    p.next = depthNext.get();
    if (p.current != nullptr)
        p.currentPts = p.current->pts;
    if (p.next != nullptr)
        p.nextPts = p.next->pts;
    return p;
}

struct Receiver::Impl {
    struct Stream {
        bool used = false;
        PairStream which = PairStream::Color;
        hal::StreamInfo info;
        std::unique_ptr<hal::VideoDecoder> decoder;
        FrameStore store;
        hal::FrameRef pending; ///< Decoded, waiting for a free store frame.
        bool eosQueued = false;
        bool drained = false;
        bool paused = false; ///< Drained because its packets stopped while the other's went on.
        bool zeroCopy = false; ///< Some of its frames were kept as the decoder's dma-bufs.
        bool decoderBusy = false; ///< Its decoder has lent every frame (held zero-copy): not quiet.
        std::uint64_t sequence = 0;
    };

    Result<void> setUp(const DecoderFactory &makeDecoder);
    Result<void> setUpStream(Stream &s, int index, PairStream which,
                             const DecoderFactory &makeDecoder);
    Take takeFrame(Stream &s);
    bool readAndQueue();
    void endInput();
    void drainLaggingStream();
    void toPaired(Pairer::Output &o, PairedFrame &out);
    void note(std::string text)
    {
        DT_LOG(Receiver, Warning, "%s", text.c_str());
        info.notes.push_back(std::move(text));
    }
    Stream *streamOf(int index) noexcept
    {
        for (Stream &s : streams)
            if (s.used && s.info.index == index)
                return &s;
        return nullptr;
    }

    std::unique_ptr<hal::MediaSource> source;
    ReceiverConfig cfg;
    ReceiverInfo info;
    ReceiverStats stats;
    Stream streams[2]; ///< [0] color, [1] depth.
    std::unique_ptr<Pairer> pairer;
    hal::Packet packet; ///< Read, not yet accepted by its decoder.
    bool havePacket = false;
    bool inputEnded = false;
    bool ended = false;
    hal::Pts skipBefore = hal::kNoPts;
    PairedFrame offered; ///< Refused by a sink, offered again first.
    bool haveOffered = false;
    Error lastRejection{Errc::InvalidArgument, "The input has no usable video stream"};
};

Result<void> Receiver::Impl::setUpStream(Stream &s, int index, PairStream which,
                                         const DecoderFactory &makeDecoder)
{
    const hal::StreamInfo &si = source->info().streams[static_cast<std::size_t>(index)];
    const bool depth = which == PairStream::Depth;
    const std::string name = std::string(depth ? "depth" : "color") + " stream " +
                             std::to_string(index) + " (" + hal::codecName(si.codec) + ", " +
                             std::to_string(si.width) + "x" + std::to_string(si.height) + ")";
    if (si.width < 1 || si.height < 1 || si.width > cfg.maxWidth || si.height > cfg.maxHeight) {
        note(name + " left out: frame size outside 1x1.." + std::to_string(cfg.maxWidth) + "x" +
             std::to_string(cfg.maxHeight));
        return unexpected(Errc::InvalidArgument, "Frame size of the stream is zero or too large");
    }
    hal::StreamConfig sc = hal::StreamConfig::fromStream(si);
    sc.kind = depth ? hal::StreamKind::Depth : hal::StreamKind::Color;
    if (depth && !isGray(sc.format)) // gray H.264 decodes as 4:2:0: its luma is the depth
        sc.format = si.depth.bits > 8 ? hal::PixelFormat::Gray16 : hal::PixelFormat::Gray8;
    if (!depth && sc.format == hal::PixelFormat::Unknown)
        sc.format = hal::PixelFormat::Yuv420p;

    const int frames = depth ? cfg.pairingWindow + 5 + 2 * cfg.consumerFrames
                             : cfg.pairingWindow + 4 + cfg.consumerFrames;
    const std::size_t bytes =
        hal::imageBytes(sc.format, sc.width, sc.height) * static_cast<std::size_t>(frames);
    if (bytes == 0 || bytes > cfg.maxPoolBytes) {
        note(name + " left out: its frames need " + std::to_string(bytes >> 20) +
             " MiB, more than the receiver's bound");
        return unexpected(Errc::OutOfResources, "The stream's frames exceed the memory bound");
    }
    auto dec = makeDecoder(si);
    if (!dec) {
        note(name + " left out: no decoder (" + dec.error().what + ")");
        return unexpected(dec.error());
    }
    if (auto r = (*dec)->configure(sc); !r) {
        note(name + " left out: the decoder refused it (" + r.error().what + ")");
        return r;
    }
    if (auto r = s.store.allocate(frames, sc.format, sc.width, sc.height); !r) {
        note(name + " left out: cannot allocate its frames");
        return r;
    }
    s.used = true;
    s.which = which;
    s.info = si;
    s.decoder = std::move(*dec);
    (depth ? info.depthFormat : info.colorFormat) = sc.format;
    return ok();
}

Result<void> Receiver::Impl::setUp(const DecoderFactory &makeDecoder)
{
    const hal::MediaInfo &mi = source->info();
    info.duration = mi.duration;
    info.roles = identifyStreams(mi, cfg.single);
    for (const std::string &n : info.roles.notes)
        note(n);
    if (info.roles.color >= 0)
        if (auto r = setUpStream(streams[0], info.roles.color, PairStream::Color, makeDecoder); !r)
            lastRejection = r.error();
    if (info.roles.depth >= 0)
        if (auto r = setUpStream(streams[1], info.roles.depth, PairStream::Depth, makeDecoder); !r)
            lastRejection = r.error();
    info.hasColor = streams[0].used;
    info.hasDepth = streams[1].used;
    if (!info.hasColor && !info.hasDepth)
        return unexpected(lastRejection);
    if (cfg.requireDepth && !info.hasDepth)
        return unexpected(Errc::NotSupported, "The input has no usable depth stream");
    if (cfg.requireColor && !info.hasColor)
        return unexpected(Errc::NotSupported, "The input has no usable color stream");
    if (info.hasColor)
        info.color = streams[0].info;
    if (info.hasDepth)
        info.depth = streams[1].info;
    info.mode = info.hasColor && info.hasDepth ? ReceiverMode::ColorAndDepth
                : info.hasColor                ? ReceiverMode::ColorOnly
                                               : ReceiverMode::DepthOnly;
    if (info.mode == ReceiverMode::ColorOnly)
        note("no depth stream: color only (play shows flat 2D, haptics off)");
    if (info.mode == ReceiverMode::DepthOnly)
        note("no color stream: depth only");

    hal::Pts cp = info.hasColor ? periodOf(info.color.frameRate) : hal::Pts{0};
    hal::Pts dp = info.hasDepth ? periodOf(info.depth.frameRate) : hal::Pts{0};
    if (cp == hal::Pts{0})
        cp = dp != hal::Pts{0} ? dp : kDefaultPeriod;
    if (dp == hal::Pts{0})
        dp = cp;
    if (info.hasColor && info.hasDepth && info.color.frameRate.den != 0 &&
        info.depth.frameRate.den != 0 && cp != dp)
        note("color and depth frame rates differ (" +
             std::to_string(info.color.frameRate.toDouble()) + " and " +
             std::to_string(info.depth.frameRate.toDouble()) +
             " fps): depth frames are reused or skipped to follow the color");
    info.colorPeriod = cp;
    info.depthPeriod = dp;
    PairerConfig pc;
    pc.color = info.hasColor;
    pc.depth = info.hasDepth;
    pc.colorPeriod = cp;
    pc.depthPeriod = dp;
    pc.window = cfg.pairingWindow;
    pairer = std::make_unique<Pairer>(pc);
    info.tolerance = pairer->tolerance();
    return ok();
}

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

Receiver::Receiver(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

Receiver::~Receiver()
{
    if (impl_) {
        impl_->offered = PairedFrame{};
        impl_->pairer.reset(); // drops its handles before the stores go
        for (auto &s : impl_->streams) {
            s.pending.reset();
            if (s.decoder)
                s.decoder->close();
        }
        impl_->source->close();
    }
}

Result<std::unique_ptr<Receiver>> Receiver::open(std::unique_ptr<hal::MediaSource> source,
                                                 const char *url, const DecoderFactory &makeDecoder,
                                                 const ReceiverConfig &cfg)
{
    if (!source || !makeDecoder)
        return unexpected(Errc::InvalidArgument, "Receiver needs a media source and decoders");
    if (cfg.pairingWindow < 1 || cfg.pairingWindow > 64 || cfg.consumerFrames < 1 ||
        cfg.consumerFrames > 64 || cfg.maxWidth < 1 || cfg.maxHeight < 1)
        return unexpected(Errc::InvalidArgument, "Receiver settings out of range");
    DT_TRY(source->open(url));
    auto impl = std::make_unique<Impl>();
    impl->source = std::move(source);
    impl->cfg = cfg;
    if (auto r = impl->setUp(makeDecoder); !r) {
        for (auto &s : impl->streams)
            if (s.decoder)
                s.decoder->close();
        impl->source->close();
        return unexpected(r.error());
    }
    return std::unique_ptr<Receiver>(new Receiver(std::move(impl)));
}

const ReceiverInfo &Receiver::info() const noexcept
{
    return impl_->info;
}

ReceiverStats Receiver::stats() const noexcept
{
    ReceiverStats s = impl_->stats;
    const PairerStats &p = impl_->pairer->stats();
    s.depthMissing = p.depthMissing;
    s.depthDuplicated = p.depthDuplicated;
    s.depthUnpaired = p.depthUnpaired;
    s.pairingForced = p.pairingForced;
    s.ptsMissing = p.ptsMissing;
    s.ptsDuplicates = p.ptsDuplicates;
    s.ptsNonMonotonic = p.ptsNonMonotonic;
    s.ptsGaps = p.ptsGaps;
    return s;
}

hal::MediaSource &Receiver::source() noexcept
{
    return *impl_->source;
}

bool Receiver::ended() const noexcept
{
    return impl_->ended;
}

Result<bool> Receiver::next(PairedFrame &out)
{
    Impl &d = *impl_;
    if (d.haveOffered) {
        out = std::move(d.offered);
        d.haveOffered = false;
        return true;
    }
    if (d.ended)
        return false;
    int stalled = 0;
    for (;;) {
        bool decoderBusy = false;
        Pairer::Output o;
        if (d.pairer->pull(o)) {
            d.toPaired(o, out);
            return true;
        }
        if (d.pairer->finished()) {
            d.ended = true;
            return false;
        }
        d.drainLaggingStream();
        bool progress = false;
        for (auto &s : d.streams) {
            if (!s.used)
                continue;
            const Take t = d.takeFrame(s);
            if (t == Take::Busy) {
                ++d.stats.consumerBusy;
                return unexpected(Errc::Busy, "The consumer holds every receiver frame");
            }
            if (t == Take::Progress) {
                progress = true;
                break;
            }
            decoderBusy = decoderBusy || t == Take::DecoderBusy;
        }
        if (!progress && !d.inputEnded)
            progress = d.readAndQueue();
        if (!progress && decoderBusy) { // zero-copy frames come back when the consumer drops them
            ++d.stats.consumerBusy;
            return unexpected(Errc::Busy, "The consumer holds every zero-copy decoder frame");
        }
        if (!progress && d.inputEnded) {
            bool allDrained = true;
            for (auto &s : d.streams)
                allDrained = allDrained && (!s.used || s.drained);
            if (allDrained) { // decoders done; let the pairer decide the rest
                for (auto &s : d.streams)
                    if (s.used)
                        d.pairer->endOfStream(s.which);
                progress = true;
            }
        }
        stalled = progress ? 0 : stalled + 1;
        if (stalled > kStallPasses) {
            DT_LOG(Receiver, Error, "A decoder neither outputs nor drains: ending the input");
            d.endInput();
            for (auto &s : d.streams) {
                if (s.used && !s.drained) {
                    s.drained = true;
                    d.pairer->endOfStream(s.which);
                    ++d.stats.decodeErrors;
                }
            }
            stalled = 0;
        }
    }
}

Result<std::size_t> Receiver::deliver(PairedFrameSink &sink, std::size_t maxFrames)
{
    Impl &d = *impl_;
    std::size_t taken = 0;
    while (taken < maxFrames) {
        PairedFrame f;
        auto r = next(f);
        if (!r) {
            if (taken > 0 && r.error().code == Errc::Busy)
                return taken;
            return unexpected(r.error());
        }
        if (!*r)
            break;
        if (!sink.offer(f)) {
            d.offered = std::move(f);
            d.haveOffered = true;
            break;
        }
        ++taken;
    }
    return taken;
}

Result<void> Receiver::seek(hal::Pts position)
{
    Impl &d = *impl_;
    DT_TRY(d.source->seek(position));
    for (auto &s : d.streams) {
        if (!s.used)
            continue;
        s.pending.reset();
        (void)s.decoder->flush();
        s.eosQueued = false;
        s.drained = false;
        s.paused = false;
    }
    d.pairer->reset();
    d.offered = PairedFrame{};
    d.haveOffered = false;
    d.havePacket = false;
    d.inputEnded = false;
    d.ended = false;
    d.skipBefore = position - d.info.tolerance;
    ++d.stats.seeks;
    return ok();
}

} // namespace depthtouch::receiver
