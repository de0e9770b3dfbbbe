#include "depthtouch/haptics/replay.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>

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
        out.push_back(trim(line.substr(start, comma == std::string_view::npos ? line.npos : comma - start)));
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

Result<std::vector<TrajectorySample>> parseTrajectoryCsv(std::string_view text, std::size_t *errorLine)
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
        if (!rows.empty() && !(v[0] > rows.back().t))
            return fail("trajectory time is not strictly increasing");
        rows.push_back({v[0], v[1], v[2], v[3]});
    }
    if (header)
        return fail("trajectory is empty (no header)");
    if (rows.empty())
        return fail("trajectory has no rows");
    return rows;
}

TrajectorySample sampleTrajectory(const std::vector<TrajectorySample> &trajectory, double t) noexcept
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
    const std::size_t frameBytes =
        static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_) * bytesPerSample(format_);
    if (bytes_.empty() || bytes_.size() % frameBytes != 0)
        return unexpected(Errc::InvalidArgument, "depth file size is not a whole number of frames");
    return ok();
}

std::size_t RawVideoFrameProvider::frameCount() const noexcept
{
    const std::size_t frameBytes =
        static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_) * bytesPerSample(format_);
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

Result<std::vector<ForceLogRow>> replay(FrameProvider &frames,
                                        const std::vector<TrajectorySample> &trajectory,
                                        const ReplayOptions &options)
{
    if (!std::isfinite(options.rate) || options.rate <= 0.0)
        return unexpected(Errc::InvalidArgument, "haptic rate must be positive");
    if (trajectory.empty())
        return unexpected(Errc::InvalidArgument, "trajectory has no rows");
    DT_TRY(options.config.validate());
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

    const double tEnd = trajectory.back().t;
    const auto updates =
        tEnd < 0.0 ? std::size_t{0} : static_cast<std::size_t>(std::floor(tEnd * options.rate + 1e-9)) + 1;
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
    for (const ForceLogRow &r : rows) {
        const HapticOutput &o = r.out;
        const int n = std::snprintf(buf, sizeof buf,
                                    "%.6f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.6f,%.6f,%.6f,%d,%d\n", r.t,
                                    o.hip.x, o.hip.y, o.hip.z, o.proxy.x, o.proxy.y, o.proxy.z,
                                    o.force.x, o.force.y, o.force.z, o.contact ? 1 : 0,
                                    o.released ? 1 : 0);
        if (n > 0)
            out.append(buf, static_cast<std::size_t>(std::min(n, static_cast<int>(sizeof buf) - 1)));
    }
    return out;
}

} // namespace depthtouch::haptics
