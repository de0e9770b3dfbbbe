/// \file
/// \brief The Kinect-v1-style sensor model (see depth_noise.h).

#include "depthtouch/haptics/depth_noise.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

namespace depthtouch::haptics::bench {

namespace {

/// splitmix64 finaliser: a counter-based generator, so a draw depends only on (seed, frame, pixel,
/// stream) and never on the order of the loops.
std::uint64_t mix(std::uint64_t z) noexcept
{
    z += 0x9E3779B97F4A7C15ull;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

class Draws {
public:
    Draws(std::uint64_t seed, std::uint64_t frame) noexcept
        : base_(mix(seed) ^ mix(frame * 0x632BE59BD9B4E019ull))
    {
    }

    /// Uniform in [0, 1).
    [[nodiscard]] double uniform(std::size_t pixel, std::uint64_t stream) const noexcept
    {
        const std::uint64_t r = mix(base_ ^ mix(pixel * 8 + stream));
        return static_cast<double>(r >> 11) * 0x1.0p-53;
    }
    /// Standard normal (Box–Muller).
    [[nodiscard]] double gauss(std::size_t pixel) const noexcept
    {
        const double u1 = std::max(uniform(pixel, 5), 1e-300);
        const double u2 = uniform(pixel, 6);
        return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
    }

private:
    std::uint64_t base_;
};

bool surface(float z) noexcept
{
    return std::isfinite(z) && z > 0.0f;
}

/// Marks silhouette pixels (\a other: the depth across the edge, 0 when none) and the projector
/// shadow (\a hole) left of every silhouette whose near side is on the right.
struct EdgeModel {
    double edgeJump;
    double focalPx;
    double baseline;
};

void findSilhouettes(const depth::Plane<float> &z, const EdgeModel &o, depth::Plane<float> &other,
                     depth::Plane<std::uint8_t> &hole)
{
    const auto edge = [&](int xa, int ya, int xb, int yb) {
        const float a = z.at(xa, ya);
        const float b = z.at(xb, yb);
        if (!surface(a) || !surface(b) ||
            std::fabs(static_cast<double>(a) - static_cast<double>(b)) <=
                o.edgeJump * std::min(static_cast<double>(a), static_cast<double>(b)))
            return false;
        other.at(xa, ya) = b;
        other.at(xb, yb) = a;
        return true;
    };
    for (int y = 0; y < z.height; ++y) {
        for (int x = 0; x < z.width; ++x) {
            if (y + 1 < z.height)
                edge(x, y, x, y + 1);
            if (x + 1 >= z.width || !edge(x, y, x + 1, y))
                continue;
            const double far = static_cast<double>(z.at(x, y));
            const double near = static_cast<double>(z.at(x + 1, y));
            if (far <= near)
                continue;
            const double w = o.focalPx * o.baseline * (1.0 / near - 1.0 / far);
            const int n = static_cast<int>(std::ceil(w));
            for (int k = 0; k < n && x - k >= 0; ++k)
                if (static_cast<double>(z.at(x - k, y)) > near * (1.0 + o.edgeJump))
                    hole.at(x - k, y) = 1;
        }
    }
}

void speckle(const Draws &draws, double probability, depth::Plane<std::uint8_t> &hole)
{
    if (probability <= 0.0)
        return;
    for (int y = 0; y < hole.height; ++y)
        for (int x = 0; x < hole.width; ++x)
            if (draws.uniform(hole.index(x, y), 1) < probability)
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx)
                        if (x + dx >= 0 && x + dx < hole.width && y + dy >= 0 &&
                            y + dy < hole.height)
                            hole.at(x + dx, y + dy) = 1;
}

/// What a projector–camera model (structured light, active stereo) starts a frame from.
struct ProjectorFrame {
    depth::Plane<float> other;       ///< Depth across a silhouette, m (0: none); findSilhouettes().
    depth::Plane<std::uint8_t> hole; ///< Projector shadow and speckle holes (1: hole).
    Draws draws;                     ///< The frame's random draws.
};

/// The silhouettes, holes and draws of frame \a frameIndex of \a clean (m) under options \a o
/// (edgeJump, focalPx, baseline, speckleProbability, seed).
template <class Options>
ProjectorFrame projectorFrame(const depth::Plane<float> &clean, const Options &o,
                              std::uint64_t frameIndex)
{
    ProjectorFrame f{depth::Plane<float>(clean.width, clean.height, 0.0f),
                     depth::Plane<std::uint8_t>(clean.width, clean.height, 0),
                     Draws(o.seed, frameIndex)};
    findSilhouettes(clean, {o.edgeJump, o.focalPx, o.baseline}, f.other, f.hole);
    speckle(f.draws, o.speckleProbability, f.hole);
    return f;
}

std::uint16_t toMillimetres(double z) noexcept
{
    return static_cast<std::uint16_t>(std::clamp(std::lround(z * 1000.0), 1L, 65534L));
}

} // namespace

depth::Plane<std::uint16_t> applyTofNoise(const depth::Plane<float> &clean,
                                          const TofNoiseOptions &o, std::uint64_t frameIndex,
                                          const depth::Plane<std::uint8_t> *dark)
{
    const int w = clean.width;
    const int h = clean.height;
    depth::Plane<std::uint16_t> out(w, h, 0);
    depth::Plane<float> other(w, h, 0.0f);
    depth::Plane<std::uint8_t> none(w, h, 0);
    findSilhouettes(clean, {o.edgeJump, 0.0, 0.0}, other, none);
    // The depth across the nearest edge within flyingWidth px (0: none).
    depth::Plane<float> across(w, h, 0.0f);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            if (other.at(x, y) <= 0.0f)
                continue;
            for (int dy = -o.flyingWidth; dy <= o.flyingWidth; ++dy)
                for (int dx = -o.flyingWidth; dx <= o.flyingWidth; ++dx) {
                    const int xx = x + dx;
                    const int yy = y + dy;
                    if (xx >= 0 && yy >= 0 && xx < w && yy < h && across.at(xx, yy) <= 0.0f)
                        across.at(xx, yy) = std::max(other.at(x, y), clean.at(x, y));
                }
        }
    // Window means for the multipath bias (summed-area table over measured pixels).
    const auto W1 = static_cast<std::size_t>(w + 1);
    std::vector<double> sum(W1 * static_cast<std::size_t>(h + 1), 0.0);
    std::vector<double> cnt(sum.size(), 0.0);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const float z = clean.at(x, y);
            const std::size_t k =
                static_cast<std::size_t>(y + 1) * W1 + static_cast<std::size_t>(x + 1);
            sum[k] = (surface(z) ? static_cast<double>(z) : 0.0) + sum[k - 1] + sum[k - W1] -
                     sum[k - W1 - 1];
            cnt[k] = (surface(z) ? 1.0 : 0.0) + cnt[k - 1] + cnt[k - W1] - cnt[k - W1 - 1];
        }
    const auto box = [&](const std::vector<double> &t, int x0, int y0, int x1, int y1) {
        return t[static_cast<std::size_t>(y1) * W1 + static_cast<std::size_t>(x1)] -
               t[static_cast<std::size_t>(y0) * W1 + static_cast<std::size_t>(x1)] -
               t[static_cast<std::size_t>(y1) * W1 + static_cast<std::size_t>(x0)] +
               t[static_cast<std::size_t>(y0) * W1 + static_cast<std::size_t>(x0)];
    };
    const Draws draws(o.seed, frameIndex);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const std::size_t i = clean.index(x, y);
            if (!surface(clean.samples[i]))
                continue;
            double z = static_cast<double>(clean.samples[i]);
            const bool darkHere = dark != nullptr && dark->samples[i] != 0;
            if ((darkHere || z < o.saturateRange) && draws.uniform(i, 2) < o.darkHoleProbability)
                continue;
            const int r = o.multipathRadius;
            const int x0 = std::max(0, x - r);
            const int y0 = std::max(0, y - r);
            const int x1 = std::min(w, x + r + 1);
            const int y1 = std::min(h, y + r + 1);
            const double n = box(cnt, x0, y0, x1, y1);
            if (n > 0.0)
                z += o.multipathGain * std::max(0.0, z - box(sum, x0, y0, x1, y1) / n);
            if (across.samples[i] > 0.0f && draws.uniform(i, 3) < o.flyingProbability) {
                const double a = static_cast<double>(across.samples[i]);
                z += (a - z) * draws.uniform(i, 4);
            }
            z += (o.sigma + o.sigmaRelative * z) * draws.gauss(i);
            if (z < o.minRange || z > o.maxRange)
                continue;
            out.samples[i] = toMillimetres(z);
        }
    return out;
}

depth::Plane<std::uint16_t> applyStereoNoise(const depth::Plane<float> &clean,
                                             const StereoNoiseOptions &o, std::uint64_t frameIndex)
{
    depth::Plane<std::uint16_t> out(clean.width, clean.height, 0);
    const auto [other, hole, draws] = projectorFrame(clean, o, frameIndex);
    const double fb = o.focalPx * o.baseline;
    for (std::size_t i = 0; i < clean.size(); ++i) {
        if (!surface(clean.samples[i]) || hole.samples[i])
            continue;
        if (other.samples[i] > 0.0f && draws.uniform(i, 2) < o.edgeHoleProbability)
            continue;
        double z = static_cast<double>(clean.samples[i]);
        if (draws.uniform(i, 3) < o.outlierProbability) {
            z = o.outlierNear + (o.outlierFar - o.outlierNear) * draws.uniform(i, 4);
        } else {
            double d = fb / z + o.subpixelSigma * draws.gauss(i);
            if (o.subpixelStep > 0.0)
                d = std::round(d / o.subpixelStep) * o.subpixelStep;
            if (!(d > 0.0))
                continue;
            z = fb / d;
        }
        if (z < o.minRange || z > o.maxRange)
            continue;
        out.samples[i] = toMillimetres(z);
    }
    return out;
}

double quantiseDisparity(double zM, double disparityStep) noexcept
{
    const double inv = std::round(1.0 / (zM * disparityStep)) * disparityStep;
    return inv > 0.0 ? 1.0 / inv : 0.0;
}

depth::Plane<std::uint16_t> applyKinectNoise(const depth::Plane<float> &clean,
                                             const KinectNoiseOptions &o, std::uint64_t frameIndex)
{
    depth::Plane<std::uint16_t> out(clean.width, clean.height, 0);
    const auto [other, hole, draws] = projectorFrame(clean, o, frameIndex);
    for (std::size_t i = 0; i < clean.size(); ++i) {
        double z = static_cast<double>(clean.samples[i]);
        if (!surface(clean.samples[i]) || hole.samples[i])
            continue;
        if (other.samples[i] > 0.0f) {
            const double u = draws.uniform(i, 2);
            if (u < o.edgeHoleProbability)
                continue;
            if (draws.uniform(i, 3) < o.flyingProbability) {
                const double lo = std::min(z, static_cast<double>(other.samples[i]));
                const double hi = std::max(z, static_cast<double>(other.samples[i]));
                z = lo + (0.2 + 0.6 * draws.uniform(i, 4)) * (hi - lo);
            }
        }
        double inv = 1.0 / z + o.flickerSigma * draws.gauss(i);
        if (o.disparityStep > 0.0)
            inv = std::round(inv / o.disparityStep) * o.disparityStep;
        if (!(inv > 0.0))
            continue;
        z = 1.0 / inv;
        if (z < o.minRange || z > o.maxRange)
            continue;
        out.samples[i] =
            static_cast<std::uint16_t>(std::clamp(std::lround(z * 1000.0), 1L, 65534L));
    }
    return out;
}

} // namespace depthtouch::haptics::bench
