#include "depthtouch/receiver/receiver.h"

#include <algorithm>
#include <array>
#include <cstring>
#include <string>
#include <utility>

#include "depthtouch/platform/enum_names.h"
#include "depthtouch/platform/log.h"
#include "receiver_impl.h"

DT_LOG_CATEGORY(Receiver)

namespace depthtouch::receiver {

namespace {

/// Loop passes without progress after which next() gives up on a decoder that neither outputs nor
/// drains (a broken backend): the input is ended instead of spinning forever.
constexpr int kStallPasses = 10'000;

} // namespace

const char *receiverModeName(ReceiverMode mode) noexcept
{
    static constexpr std::array<const char *, 3> kNames = {"color+depth", "color-only",
                                                           "depth-only"};
    return platform::enumName(mode, kNames, "?");
}

StoredDepthPair PairedFrame::depthPair() const noexcept
{
    StoredDepthPair p;
    p.current = depth.get();
    p.next = depthNext.get();
    if (p.current != nullptr)
        p.currentPts = depthPts != hal::kNoPts ? depthPts : p.current->pts;
    if (p.next != nullptr)
        p.nextPts = depthNextPts != hal::kNoPts ? depthNextPts : p.next->pts;
    p.material = material.get();
    p.materialNext = materialNext.get();
    return p;
}

Receiver::Receiver(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

Receiver::~Receiver()
{
    if (impl_) {
        impl_->pending = Pairer::Output{}; // drops their handles before the stores go
        impl_->pairer.reset();
        impl_->materials.reset();
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
    s.pairingForced = p.pairingForced + impl_->materialForced;
    s.ptsMissing = p.ptsMissing;
    s.ptsDuplicates = p.ptsDuplicates;
    s.ptsNonMonotonic = p.ptsNonMonotonic;
    if (impl_->materials) {
        const MaterialPairerStats &m = impl_->materials->stats();
        s.ptsMissing += m.ptsMissing;
        s.ptsDuplicates += m.ptsDuplicates;
        s.ptsNonMonotonic += m.ptsNonMonotonic;
    }
    s.ptsGaps = p.ptsGaps;
    s.ptsJumps = p.ptsJumps;
    s.ptsDiscontinuities = p.ptsDiscontinuities;
    const auto hardware = [](const Impl::Stream &st) -> std::uint64_t {
        return st.decoder ? st.decoder->stats().framesHardware : 0;
    };
    s.colorFramesHardware = hardware(impl_->streams[0]);
    s.depthFramesHardware = hardware(impl_->streams[1]);
    return s;
}

hal::MediaSource &Receiver::source() noexcept
{
    return *impl_->source;
}

void Receiver::setAudioSink(std::shared_ptr<hal::AudioPacketSink> sink) noexcept
{
    impl_->audioSink = std::move(sink);
}

bool Receiver::ended() const noexcept
{
    return impl_->ended;
}

Result<bool> Receiver::next(PairedFrame &out)
{
    Impl &d = *impl_;
    if (d.ended)
        return false;
    int stalled = 0;
    for (;;) {
        bool decoderBusy = false;
        if (!d.havePending)
            d.havePending = d.pairer->pull(d.pending);
        if (d.havePending && d.materialReady()) {
            d.emitPending(out);
            return true;
        }
        if (!d.havePending && d.pairer->finished()) {
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
                        d.endStream(s);
                progress = true;
            }
        }
        if (!progress && d.havePending) { // the material lags and nothing else can move: bounded
            ++d.materialForced;
            d.emitPending(out);
            return true;
        }
        stalled = progress ? 0 : stalled + 1;
        if (stalled > kStallPasses) {
            DT_LOG(Receiver, Error, "A decoder neither outputs nor drains: ending the input");
            d.endInput();
            for (auto &s : d.streams) {
                if (s.used && !s.drained) {
                    s.drained = true;
                    d.endStream(s);
                    ++d.stats.decodeErrors;
                }
            }
            stalled = 0;
        }
    }
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
        s.partnerPackets = 0;
    }
    d.pending = Pairer::Output{};
    d.havePending = false;
    d.pairer->reset();
    if (d.materials)
        d.materials->reset(position);
    d.havePacket = false;
    d.inputEnded = false;
    d.ended = false;
    d.skipBefore = position - d.info.tolerance;
    ++d.stats.seeks;
    return ok();
}

} // namespace depthtouch::receiver
