#pragma once
/// \file
/// \brief MediaSourceBase: the hal::MediaSource contract in one place, for every demuxer backend.
///
/// A backend derives from MediaSourceBase and implements only the device work (the protected
/// `...Device()` hooks); the public methods are `final` and do the contract of media_source.h
/// around them, as DisplayBase and VideoDecoderBase do for theirs (libcamera's queueRequest() and
/// queueRequestDevice()):
/// - open(): InvalidState unless Closed (logged, category HalSource); InvalidArgument for a null or
///   empty URL; then openDevice(); Open on success; on error closeDevice() undoes what it began and
///   the source stays Closed.
/// - close(): a no-op when Closed; else closeDevice(), then Closed.
/// - info(): the backend's infoDevice() when Open, an empty MediaInfo when Closed.
/// - readPacket(): InvalidState unless Open, then readPacketDevice().
/// - seek(): InvalidState unless Open; NotSupported when info().seekable is false; the position
///   clamped to [0, duration] (0 when the duration is unknown), then seekDevice().
/// interrupt() and cancelRead() stay the backend's (thread-safe, any state).
///
/// Thread-safety: thread-bound, as hal::MediaSource.

#include "depthtouch/hal/media_source.h"

namespace depthtouch::hal {

/// \brief The base of every media source backend: owns the state and the contract (see the file
/// comment); the backend implements the hooks.
class MediaSourceBase : public MediaSource {
public:
    ~MediaSourceBase() override = default;

    [[nodiscard]] State state() const noexcept final { return state_; }
    [[nodiscard]] Result<void> open(const char *url) final;
    void close() noexcept final;
    [[nodiscard]] const MediaInfo &info() const noexcept final;
    [[nodiscard]] Result<Packet> readPacket() final;
    [[nodiscard]] Result<void> seek(Pts position) final;

protected:
    MediaSourceBase() = default;

    /// \brief Opens \a url (called Closed, \a url non-empty) and reads the stream list.
    /// \return Errors: as open() (NotSupported, NoDevice, Io, InvalidArgument, Timeout).
    [[nodiscard]] virtual Result<void> openDevice(const char *url) = 0;
    /// \brief Frees what openDevice() set up (called Open, or after a failed openDevice()).
    virtual void closeDevice() noexcept = 0;
    /// \return the streams, duration and seekability (called Open).
    [[nodiscard]] virtual const MediaInfo &infoDevice() const noexcept = 0;
    /// \brief Reads the next packet (called Open). \return Errors: as readPacket().
    [[nodiscard]] virtual Result<Packet> readPacketDevice() = 0;
    /// \brief Seeks to \a position (called Open and seekable, \a position within [0, duration]).
    /// \return Errors: as seek() (Io, Timeout).
    [[nodiscard]] virtual Result<void> seekDevice(Pts position) = 0;

private:
    State state_ = State::Closed;
};

} // namespace depthtouch::hal
