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

void ProgressReport::write(const EncodeProgress &p, const char *state)
{
    if (out_ == nullptr)
        return;
    const double fps = p.elapsed > 0.0 ? static_cast<double>(p.frames) / p.elapsed : 0.0;
    const auto us = static_cast<long long>(p.pts > 0.0 ? p.pts * 1e6 + 0.5 : 0.0);
    const int n =
        std::fprintf(out_,
                     "frame=%lld\nfps=%.2f\nout_time_us=%lld\nout_time=%02lld:%02lld:%02lld."
                     "%06lld\nelapsed=%.3f\nprogress=%s\n",
                     p.frames, fps, us, us / 3'600'000'000LL, us / 60'000'000LL % 60,
                     us / 1'000'000LL % 60, us % 1'000'000LL, p.elapsed, state);
    if (n < 0 || std::fflush(out_) != 0)
        failed_ = true;
}

void ProgressReport::update(const EncodeProgress &p)
{
    if (out_ == nullptr || p.elapsed - lastWrite_ < 0.5)
        return;
    lastWrite_ = p.elapsed;
    write(p, "continue");
}

bool ProgressReport::finish(const EncodeProgress &p)
{
    write(p, "end");
    return !failed_;
}

void ProgressLine::finish()
{
    if (drawn_)
        std::fprintf(stderr, "\n");
    drawn_ = false;
}

} // namespace depthtouch::media
