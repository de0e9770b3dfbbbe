#include "depthtouch/haptics/replay.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>

#include <glm/geometric.hpp>

#include "depthtouch/haptics/passivity.h"

namespace depthtouch::haptics {

namespace {

std::string_view trim(std::string_view s) noexcept
{
    while (!s.empty() && (s.front() == ' ' || s.front() == '\t'))
        s.remove_prefix(1);
    while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r'))
        s.remove_suffix(1);
    return s;
}

/// Splits \a line at commas into \a out (cleared first).
void splitFields(std::string_view line, std::vector<std::string_view> &out)
{
    out.clear();
    std::size_t start = 0;
    for (;;) {
        const std::size_t comma = line.find(',', start);
        out.push_back(
            trim(line.substr(start, comma == std::string_view::npos ? line.npos : comma - start)));
        if (comma == std::string_view::npos)
            break;
        start = comma + 1;
    }
}

bool parseNumber(std::string_view s, double &v) noexcept
{
    if (s.empty())
        return false;
    if (s.front() == '+')
        s.remove_prefix(1);
    const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    return ec == std::errc() && ptr == s.data() + s.size() && std::isfinite(v);
}

} // namespace

Result<std::vector<TrajectorySample>> parseTrajectoryCsv(std::string_view text,
                                                         std::size_t *errorLine)
{
    std::size_t line = 0;
    auto fail = [&](const char *what) -> Result<std::vector<TrajectorySample>> {
        if (errorLine != nullptr)
            *errorLine = line;
        return unexpected(Errc::InvalidArgument, what);
    };
    if (errorLine != nullptr)
        *errorLine = 0;
    std::vector<TrajectorySample> rows;
    std::vector<std::string_view> fields;
    int col[4] = {-1, -1, -1, -1};
    std::size_t nColumns = 0;
    bool header = true;
    std::size_t pos = 0;
    while (pos < text.size()) {
        const std::size_t end = std::min(text.find('\n', pos), text.size());
        const std::string_view raw = trim(text.substr(pos, end - pos));
        pos = end + 1;
        ++line;
        if (raw.empty())
            continue;
        splitFields(raw, fields);
        if (header) {
            static constexpr std::string_view kNames[4] = {"t", "x", "y", "z"};
            for (std::size_t i = 0; i < fields.size(); ++i)
                for (int k = 0; k < 4; ++k)
                    if (fields[i] == kNames[k])
                        col[k] = static_cast<int>(i);
            if (std::any_of(std::begin(col), std::end(col), [](int c) { return c < 0; }))
                return fail("trajectory header must name the columns t,x,y,z");
            nColumns = fields.size();
            header = false;
            continue;
        }
        if (fields.size() != nColumns)
            return fail("trajectory row has a different number of fields than the header");
        double v[4];
        for (int k = 0; k < 4; ++k)
            if (!parseNumber(fields[static_cast<std::size_t>(col[k])], v[k]))
                return fail("trajectory value is not a finite number");
        if (std::fabs(v[0]) > ReplayLimits::kMaxTimeSeconds)
            return fail("trajectory time is beyond 1e6 s");
        for (int k = 1; k < 4; ++k)
            if (std::fabs(v[k]) > ReplayLimits::kMaxPositionMetres)
                return fail("trajectory position is beyond 100 m");
        if (!rows.empty() && !(v[0] > rows.back().t))
            return fail("trajectory time is not strictly increasing");
        if (rows.size() >= ReplayLimits::kMaxRows)
            return fail("trajectory has more than 1000000 rows");
        rows.push_back({v[0], v[1], v[2], v[3]});
    }
    if (header)
        return fail("trajectory is empty (no header)");
    if (rows.empty())
        return fail("trajectory has no rows");
    return rows;
}

TrajectorySample sampleTrajectory(const std::vector<TrajectorySample> &trajectory,
                                  double t) noexcept
{
    if (t <= trajectory.front().t)
        return trajectory.front();
    if (t >= trajectory.back().t)
        return trajectory.back();
    const auto it = std::upper_bound(trajectory.begin(), trajectory.end(), t,
                                     [](double v, const TrajectorySample &s) { return v < s.t; });
    const TrajectorySample &b = *it;
    const TrajectorySample &a = *(it - 1);
    const double w = (t - a.t) / (b.t - a.t);
    return {t, a.x + (b.x - a.x) * w, a.y + (b.y - a.y) * w, a.z + (b.z - a.z) * w};
}

RawVideoFrameProvider::RawVideoFrameProvider(std::vector<std::uint8_t> bytes, int width, int height,
                                             SampleFormat format, double fps)
    : bytes_(std::move(bytes)), width_(width), height_(height), format_(format), fps_(fps)
{
}

Result<void> RawVideoFrameProvider::validate() const noexcept
{
    if (width_ < 2 || height_ < 2)
        return unexpected(Errc::InvalidArgument, "depth size must be at least 2x2");
    if (!std::isfinite(fps_) || fps_ <= 0.0)
        return unexpected(Errc::InvalidArgument, "depth frame rate must be positive");
    const std::size_t frameBytes = static_cast<std::size_t>(width_) *
                                   static_cast<std::size_t>(height_) * bytesPerSample(format_);
    if (bytes_.empty() || bytes_.size() % frameBytes != 0)
        return unexpected(Errc::InvalidArgument, "depth file size is not a whole number of frames");
    return ok();
}

std::size_t RawVideoFrameProvider::frameCount() const noexcept
{
    const std::size_t frameBytes = static_cast<std::size_t>(width_) *
                                   static_cast<std::size_t>(height_) * bytesPerSample(format_);
    return frameBytes == 0 ? 0 : bytes_.size() / frameBytes;
}

Result<DepthFrameView> RawVideoFrameProvider::frame(std::size_t i) noexcept
{
    DT_TRY(validate());
    if (i >= frameCount())
        return unexpected(Errc::InvalidArgument, "depth frame index out of range");
    const std::size_t stride = static_cast<std::size_t>(width_) * bytesPerSample(format_);
    DepthFrameView v;
    v.data = bytes_.data() + i * stride * static_cast<std::size_t>(height_);
    v.width = width_;
    v.height = height_;
    v.strideBytes = stride;
    v.format = format_;
    v.pts = static_cast<double>(i) / fps_;
    return v;
}

Result<void> validateReplayOptions(const ReplayOptions &options) noexcept
{
    using L = ReplayLimits;
    const auto within = [](double v, double max) {
        return std::isfinite(v) && v > 0.0 && v <= max;
    };
    if (!(options.rate >= L::kMinRate && options.rate <= L::kMaxRate))
        return unexpected(Errc::InvalidArgument, "haptic rate must be in 100..10000 Hz");
    DT_TRY(options.config.validate());
    const RendererConfig &c = options.config;
    if (!(c.damping >= 0.0 && c.damping <= L::kMaxDamping))
        return unexpected(Errc::InvalidArgument, "damping must be in [0, 1000] N*s/m");
    if (!within(c.maxForce, L::kMaxForce))
        return unexpected(Errc::InvalidArgument, "max force must be in (0, 1000] N");
    if (!within(c.maxForceStep, L::kMaxForceStep))
        return unexpected(Errc::InvalidArgument, "max force step must be in (0, 10000] N");
    if (!within(c.rampTime, L::kMaxRampTime))
        return unexpected(Errc::InvalidArgument, "ramp time must be in (0, 3600] s");
    if (!within(c.box.width, L::kMaxBoxMetres) || !within(c.box.depth, L::kMaxBoxMetres))
        return unexpected(Errc::InvalidArgument, "box width and depth must be in (0, 100] m");
    if (!std::isnan(c.fingerRadius) && !(c.fingerRadius <= c.box.width))
        return unexpected(Errc::InvalidArgument, "finger radius must be at most the box width");
    return ok();
}

Result<std::vector<ForceLogRow>> replay(FrameProvider &frames,
                                        const std::vector<TrajectorySample> &trajectory,
                                        const ReplayOptions &options)
{
    DT_TRY(validateReplayOptions(options));
    if (trajectory.empty())
        return unexpected(Errc::InvalidArgument, "trajectory has no rows");
    const double tEnd = trajectory.back().t;
    if (!(tEnd >= 0.0))
        return unexpected(Errc::InvalidArgument,
                          "trajectory ends before t = 0 (nothing to replay)");
    if (!(tEnd * options.rate < static_cast<double>(ReplayLimits::kMaxUpdates)))
        return unexpected(
            Errc::InvalidArgument,
            "trajectory too long: more than 1000000 haptic updates (1000 s at 1 kHz)");
    const std::size_t count = frames.frameCount();
    if (count == 0)
        return unexpected(Errc::InvalidArgument, "depth video has no frames");
    auto first = frames.frame(0);
    if (!first)
        return unexpected(first.error());
    const DepthFrameView f0 = *first;
    DT_TRY(f0.validate());
    auto made = makeRenderer(options.method, options.config, f0.width, f0.height);
    if (!made)
        return unexpected(made.error());
    HapticRenderer &renderer = **made;

    const auto updates = static_cast<std::size_t>(std::floor(tEnd * options.rate + 1e-9)) + 1;
    std::vector<ForceLogRow> rows;
    rows.reserve(updates);
    std::size_t current = 0;
    DepthFrameView cur = f0;
    DepthFrameView next{};
    bool haveNext = false;
    auto load = [&](std::size_t i) -> Result<void> {
        auto c = frames.frame(i);
        if (!c)
            return unexpected(c.error());
        cur = *c;
        haveNext = i + 1 < count;
        if (haveNext) {
            auto n = frames.frame(i + 1);
            if (!n)
                return unexpected(n.error());
            next = *n;
        }
        if (cur.width != f0.width || cur.height != f0.height)
            return unexpected(Errc::InvalidArgument, "depth frames change size");
        return renderer.setFrames(cur, haveNext ? &next : nullptr);
    };
    DT_TRY(load(0));
    const TrajectorySample s0 = sampleTrajectory(trajectory, 0.0);
    renderer.reset({s0.x, s0.y, s0.z});
    for (std::size_t n = 0; n < updates; ++n) {
        const double t = static_cast<double>(n) / options.rate;
        std::size_t want = current;
        while (want + 1 < count) {
            auto nf = frames.frame(want + 1);
            if (!nf)
                return unexpected(nf.error());
            if (nf->pts - f0.pts > t)
                break;
            ++want;
        }
        if (want != current) {
            current = want;
            DT_TRY(load(current));
        }
        const TrajectorySample s = sampleTrajectory(trajectory, t);
        rows.push_back({t, renderer.update({s.x, s.y, s.z}, f0.pts + t)});
    }
    return rows;
}

std::string formatForceLog(const std::vector<ForceLogRow> &rows)
{
    std::string out = "t,hip_x,hip_y,hip_z,proxy_x,proxy_y,proxy_z,fx,fy,fz,contact,released\n";
    out.reserve(out.size() + rows.size() * 120);
    char buf[320];
    std::string wide;
    for (const ForceLogRow &r : rows) {
        const HapticOutput &o = r.out;
        const auto print = [&r, &o](char *to, std::size_t size) {
            return std::snprintf(
                to, size, "%.6f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.6f,%.6f,%.6f,%d,%d\n", r.t, o.hip.x,
                o.hip.y, o.hip.z, o.proxy.x, o.proxy.y, o.proxy.z, o.force.x, o.force.y, o.force.z,
                o.contact ? 1 : 0, o.released ? 1 : 0);
        };
        const int n = print(buf, sizeof buf);
        if (n < 0)
            continue;
        if (static_cast<std::size_t>(n) < sizeof buf) {
            out.append(buf, static_cast<std::size_t>(n));
        } else { // a huge value: %f prints every digit (1e300 is 301 of them)
            wide.assign(static_cast<std::size_t>(n) + 1, '\0');
            print(wide.data(), wide.size());
            out.append(wide.data(), static_cast<std::size_t>(n));
        }
    }
    return out;
}

ReplaySummary summarizeReplay(const std::vector<ForceLogRow> &rows)
{
    ReplaySummary sum;
    std::size_t contact = 0;
    PassivityObserver energy;
    for (const ForceLogRow &r : rows) {
        energy.update(r.out.hip, r.out.force);
        contact += r.out.contact ? 1u : 0u;
        sum.trips += r.out.released ? 1u : 0u;
        sum.maxForce = std::max(sum.maxForce, glm::length(r.out.force));
    }
    sum.energy = energy.energy();
    sum.energyPeak = energy.peak();
    sum.seconds = rows.empty() ? 0.0 : rows.back().t - rows.front().t;
    sum.contactPercent =
        rows.empty() ? 0.0
                     : 100.0 * static_cast<double>(contact) / static_cast<double>(rows.size());
    return sum;
}

} // namespace depthtouch::haptics
