#pragma once
/// \file
/// \brief The inside of Receiver, private to dt_receiver: its streams, pairer and input state. The
/// Impl's members live in receiver_setup.cpp (choosing and opening the streams) and
/// receiver_decode.cpp (reading packets, taking decoded frames into the stores, pairing);
/// receiver.cpp holds the public calls.
/// Thread-safety: thread-bound, as Receiver. Not real-time safe.

#include <cstdint>
#include <memory>
#include <string>

#include "depthtouch/receiver/frame_store.h"
#include "depthtouch/receiver/material_pairer.h"
#include "depthtouch/receiver/pts_pairer.h"
#include "depthtouch/hal/audio_source.h"
#include "depthtouch/receiver/receiver.h"

namespace depthtouch::receiver {

using Pairer = PtsPairer<FrameHandle>;
using MaterialTrack = MaterialPairer<FrameHandle>;

/// DecoderBusy: the decoder has lent every frame, held here as zero-copy frames.
enum class Take : std::uint8_t { Progress, Nothing, Busy, DecoderBusy };

/// \brief The state of one Receiver.
struct Receiver::Impl {
    struct Stream {
        bool used = false;
        bool material = false; ///< The material track (fed to `materials`, not to the pairer).
        PairStream which = PairStream::Color; ///< Color and depth only.
        const char *name = "color";           ///< "color", "depth" or "material" (logs).

        hal::StreamInfo info;
        std::unique_ptr<hal::VideoDecoder> decoder;
        FrameStore store;
        hal::FrameRef pending; ///< Decoded, waiting for a free store frame.
        bool eosQueued = false;
        bool drained = false;
        bool paused = false;   ///< Drained because its packets stopped while the other's went on.
        bool zeroCopy = false; ///< Some of its frames were kept as the decoder's dma-bufs.
        bool decoderBusy = false; ///< Its decoder has lent every frame (held zero-copy): not quiet.
        std::uint64_t sequence = 0;
        /// Packets of the other stream (color or depth) read since this stream's last packet: its
        /// packets stopped when they exceed half the pairing window (drainLaggingStream()).
        std::uint64_t partnerPackets = 0;
    };

    Result<void> setUp(const DecoderFactory &makeDecoder);
    Result<void> setUpStream(Stream &s, int index, PairStream which,
                             const DecoderFactory &makeDecoder);
    void setUpMaterial(const DecoderFactory &makeDecoder);
    Take takeFrame(Stream &s);
    /// Hands a filled store frame to the pairer or the material track.
    void pushFrame(Stream &s, FrameHandle &&h, const StoredFrame &f);
    /// Marks \a s ended for the pairing (pairer or material track).
    void endStream(Stream &s);
    /// \return whether `pending` may go out: its depth frames' materials are final.
    [[nodiscard]] bool materialReady() const noexcept;
    /// Drains the material decoder when `pending` waits for it and the pairing window is full.
    void drainLaggingMaterial();
    bool readAndQueue();
    void endInput();
    /// Drains the color or depth decoder whose frames lag by the pairing window, but only when its
    /// packets stopped (see the definition).
    void drainLaggingStream();
    void toPaired(Pairer::Output &o, PairedFrame &out);
    /// Hands `pending` out as \a out (toPaired()) and clears it.
    void emitPending(PairedFrame &out)
    {
        toPaired(pending, out);
        pending = Pairer::Output{};
        havePending = false;
    }
    /// Logs \a text as a warning and keeps it in the receiver's notes.
    void note(std::string text);
    /// \return the used stream of container index \a index, or null.
    Stream *streamOf(int index) noexcept
    {
        for (Stream &s : streams)
            if (s.used && s.info.index == index)
                return &s;
        return nullptr;
    }

    std::unique_ptr<hal::MediaSource> source;
    std::shared_ptr<hal::AudioPacketSink> audioSink; ///< Takes the audio packets (setAudioSink()).
    ReceiverConfig cfg;
    ReceiverInfo info;
    ReceiverStats stats;
    Stream streams[3]; ///< [0] color, [1] depth, [2] material.
    std::unique_ptr<Pairer> pairer;
    std::unique_ptr<MaterialTrack> materials; ///< With a material track only.
    Pairer::Output pending; ///< Pulled from the pairer, waiting for its material frames.
    bool havePending = false;
    std::uint64_t materialForced = 0; ///< Outputs decided without their material being final.
    hal::Packet packet;               ///< Read, not yet accepted by its decoder.
    bool havePacket = false;
    bool inputEnded = false;
    bool ended = false;
    hal::Pts skipBefore = hal::kNoPts;
    Error lastRejection{Errc::InvalidArgument, "The input has no usable video stream"};
};

} // namespace depthtouch::receiver
