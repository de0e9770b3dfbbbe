/// \file
/// \brief The Kinect-v1-style sensor model (see depth_noise.h).

#include "depthtouch/haptics/depth_noise.h"

#include <algorithm>
#include <cmath>
#include <numbers>

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

bool surface(float z) noexcept { return std::isfinite(z) && z > 0.0f; }

/// Marks silhouette pixels (\a other: the depth across the edge, 0 when none) and the projector
/// shadow (\a hole) left of every silhouette whose near side is on the right.
void findSilhouettes(const depth::Plane<float> &z, const KinectNoiseOptions &o,
                     depth::Plane<float> &other, depth::Plane<std::uint8_t> &hole)
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

void speckle(const Draws &draws, const KinectNoiseOptions &o, depth::Plane<std::uint8_t> &hole)
{
    if (o.speckleProbability <= 0.0)
        return;
    for (int y = 0; y < hole.height; ++y)
        for (int x = 0; x < hole.width; ++x)
            if (draws.uniform(hole.index(x, y), 1) < o.speckleProbability)
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx)
                        if (x + dx >= 0 && x + dx < hole.width && y + dy >= 0 &&
                            y + dy < hole.height)
                            hole.at(x + dx, y + dy) = 1;
}

} // namespace

double quantiseDisparity(double zM, double disparityStep) noexcept
{
    const double inv = std::round(1.0 / (zM * disparityStep)) * disparityStep;
    return inv > 0.0 ? 1.0 / inv : 0.0;
}

depth::Plane<std::uint16_t> applyKinectNoise(const depth::Plane<float> &clean,
                                             const KinectNoiseOptions &o, std::uint64_t frameIndex)
{
    depth::Plane<std::uint16_t> out(clean.width, clean.height, 0);
    depth::Plane<float> other(clean.width, clean.height, 0.0f);
    depth::Plane<std::uint8_t> hole(clean.width, clean.height, 0);
    findSilhouettes(clean, o, other, hole);
    const Draws draws(o.seed, frameIndex);
    speckle(draws, o, hole);
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
