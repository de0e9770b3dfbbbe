#pragma once
/// \file
/// \brief The progress of an encode (`depthtouch encode`) drawn on one terminal line of stderr:
/// frames, frames per second and, when the total is known, the time left (s), redrawn at most
/// every 0.25 s of the encode's elapsed time (EncodeProgress, encode_job.h).
/// Thread-safety: call from the thread that runs the encode's callbacks.

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

} // namespace depthtouch::media
