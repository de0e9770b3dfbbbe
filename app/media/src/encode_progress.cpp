/// \file
/// \brief ProgressLine: see encode_progress.h.

#include "depthtouch/media/encode_progress.h"

#include <cstdio>

namespace depthtouch::media {

void ProgressLine::update(const EncodeProgress &p)
{
    if (!enabled_ || p.elapsed - lastDraw_ < 0.25)
        return;
    lastDraw_ = p.elapsed;
    const double fps = p.elapsed > 0.0 ? static_cast<double>(p.frames) / p.elapsed : 0.0;
    if (p.totalFrames > 0 && fps > 0.0) {
        const double eta = static_cast<double>(p.totalFrames - p.frames) / fps;
        std::fprintf(stderr, "\rframe %lld/%lld  %.1f fps  ETA %.0f s   ", p.frames, p.totalFrames,
                     fps, eta > 0.0 ? eta : 0.0);
    } else {
        std::fprintf(stderr, "\rframe %lld  %.1f fps   ", p.frames, fps);
    }
    std::fflush(stderr);
    drawn_ = true;
}

void ProgressLine::finish()
{
    if (drawn_)
        std::fprintf(stderr, "\n");
    drawn_ = false;
}

} // namespace depthtouch::media
