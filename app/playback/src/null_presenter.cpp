/// \file
/// \brief The null Presenter of builds without EGL/GLES: frames are presented undrawn.

#include "presenter.h"

namespace depthtouch::playback {

namespace {

/// Draws nothing; every frame counts as drawn.
class NullPresenter final : public Presenter {
public:
    void contextReady() override {}
    void newSession() override {}
    void dropPrepared() override {}
    void prepareAhead(const receiver::PairedFrame &, const receiver::PairedFrame *, int) override {}
    DrawOutcome draw(const DrawInput &) override { return {}; }
    void finishDrawing(bool) override {}
    std::optional<LodSample> afterPresent(double, bool, bool, bool) override
    {
        return std::nullopt;
    }
    void addStats(PlaybackStats &) const override {}
    OutputsLost shutdown() override { return {}; }
};

} // namespace

std::unique_ptr<Presenter> makePresenter(const PlaybackConfig &, hal::Display &, platform::Clock &,
                                         std::atomic<bool> &, const std::atomic<std::uint64_t> &)
{
    return std::make_unique<NullPresenter>();
}

bool presenterDraws(const hal::Display &) noexcept
{
    return false;
}

} // namespace depthtouch::playback
