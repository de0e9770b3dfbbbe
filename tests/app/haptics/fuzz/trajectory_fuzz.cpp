// libFuzzer target over the trajectory CSV reader of `depthtouch touch`
// (haptics::parseTrajectoryCsv).
//
// Input: the bytes are the CSV text. A parsed trajectory must keep the reader's promises (rows,
// times strictly increasing, every value finite and within ReplayLimits); sampleTrajectory() must
// stay finite and within the rows' bounds; a short one is replayed at 100 Hz against a flat 8×8
// frame, every force finite and within the maximum, and its force log must have one whole line a
// row. Any violation traps.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "depthtouch/haptics/replay.h"

namespace {

using namespace depthtouch;
using namespace depthtouch::haptics;

void check(bool ok)
{
    if (!ok)
        __builtin_trap();
}

bool finite(const TrajectorySample &s)
{
    return std::isfinite(s.t) && std::isfinite(s.x) && std::isfinite(s.y) && std::isfinite(s.z);
}

void checkRows(const std::vector<TrajectorySample> &rows)
{
    check(!rows.empty() && rows.size() <= ReplayLimits::kMaxRows);
    for (std::size_t i = 0; i < rows.size(); ++i) {
        const TrajectorySample &r = rows[i];
        check(finite(r));
        check(std::fabs(r.t) <= ReplayLimits::kMaxTimeSeconds);
        check(std::fabs(r.x) <= ReplayLimits::kMaxPositionMetres &&
              std::fabs(r.y) <= ReplayLimits::kMaxPositionMetres &&
              std::fabs(r.z) <= ReplayLimits::kMaxPositionMetres);
        check(i == 0 || r.t > rows[i - 1].t);
    }
    const double span = rows.back().t - rows.front().t;
    for (const double f : {-0.5, 0.0, 0.25, 0.5, 0.999, 1.0, 1.5}) {
        const TrajectorySample s = sampleTrajectory(rows, rows.front().t + f * span);
        check(finite(s));
        check(std::fabs(s.x) <= ReplayLimits::kMaxPositionMetres &&
              std::fabs(s.z) <= ReplayLimits::kMaxPositionMetres);
    }
}

void checkReplay(const std::vector<TrajectorySample> &rows)
{
    if (!(rows.back().t >= 0.0 && rows.back().t <= 2.0))
        return; // keep each input fast: at most 201 updates
    std::vector<std::uint8_t> flat(8 * 8, 128);
    RawVideoFrameProvider frames(std::move(flat), 8, 8, SampleFormat::Gray8, 30.0);
    ReplayOptions opt;
    opt.rate = ReplayLimits::kMinRate;
    opt.method = rows.size() % 2 == 0 ? Method::Finger : Method::Modified;
    opt.config = RendererConfig::forMethod(opt.method);
    auto out = replay(frames, rows, opt);
    check(static_cast<bool>(out));
    for (const ForceLogRow &r : *out) {
        const double f = std::sqrt(r.out.force.x * r.out.force.x + r.out.force.y * r.out.force.y +
                                   r.out.force.z * r.out.force.z);
        check(std::isfinite(f) && f <= opt.config.maxForce * (1.0 + 1e-9));
    }
    const std::string csv = formatForceLog(*out);
    check(static_cast<std::size_t>(std::count(csv.begin(), csv.end(), '\n')) == out->size() + 1);
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t *data, std::size_t size)
{
    const std::string_view text(reinterpret_cast<const char *>(data), size);
    std::size_t line = 0;
    const auto rows = parseTrajectoryCsv(text, &line);
    if (!rows) {
        check(rows.error().code == Errc::InvalidArgument);
        check(line <= static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n')) + 1);
        return 0;
    }
    check(line == 0);
    checkRows(*rows);
    checkReplay(*rows);
    return 0;
}
