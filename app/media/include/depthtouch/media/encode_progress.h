#pragma once
/// \file
/// \brief The progress of an encode (`depthtouch encode`) drawn on one terminal line of stderr:
/// frames, frames per second and, when the total is known, the time left (s), redrawn at most
/// every 0.25 s of the encode's elapsed time (EncodeProgress, encode_job.h).
/// Thread-safety: call from the thread that runs the encode's callbacks.

#include <cstdio>

#include "depthtouch/media/encode_job.h"

namespace depthtouch::media {

/// \brief Draws "frame N/M  F fps  ETA S s" (or "frame N  F fps" without a total) on stderr.
class ProgressLine {
public:
    /// \param enabled false draws nothing (stderr is no terminal).
    explicit ProgressLine(bool enabled) : enabled_(enabled) {}
    /// Redraws the line from \a p, unless drawn less than 0.25 s (of p.elapsed) ago.
    void update(const EncodeProgress &p);
    /// Ends the line (a newline) when one was drawn.
    void finish();

private:
    bool enabled_;
    bool drawn_ = false;
    double lastDraw_ = -1.0;
};

/// \brief ffmpeg's `-progress` for scripts: blocks of key=value lines ("frame=N", "fps=F",
/// "out_time_us=U" (µs of video encoded), "out_time=HH:MM:SS.uuuuuu", "elapsed=S" (s of wall
/// time), then "progress=continue", or "progress=end" for the last one), written at most every
/// 0.5 s of the encode's elapsed time and flushed, to a stream the caller owns (a file, stdout).
/// Reference: ffmpeg(1), -progress url.
class ProgressReport {
public:
    /// \param out where the blocks go; nullptr writes nothing.
    explicit ProgressReport(std::FILE *out) : out_(out) {}
    /// Writes a block from \a p, unless one was written less than 0.5 s (of p.elapsed) ago.
    void update(const EncodeProgress &p);
    /// Writes the last block ("progress=end") from \a p. \return false when a write failed.
    bool finish(const EncodeProgress &p);

private:
    void write(const EncodeProgress &p, const char *state);

    std::FILE *out_;
    double lastWrite_ = -1.0;
    bool failed_ = false;
};

} // namespace depthtouch::media
