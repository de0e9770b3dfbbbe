#pragma once
// Small helpers shared by the mock backend tests.
#include <chrono>
#include <cstdint>
#include <initializer_list>
#include <optional>
#include <vector>

#include <gtest/gtest.h>

#include "depthtouch/drivers/mock/mock_pattern.h"
#include "depthtouch/hal/backends.h"
#include "depthtouch/hal/media_source.h"
#include "depthtouch/platform/clock.h"
#include "depthtouch/platform/result.h"
#include "support/expectations.h"

namespace depthtouch::drivers::testing {

using depthtouch::testing::errcOf;

/// The time point \a ms milliseconds after the clock epoch.
inline platform::TimePoint at(int ms)
{
    return platform::TimePoint(std::chrono::milliseconds(ms));
}

/// A backend configuration on \a clock with the backend options \a options (e.g. "pool=2").
inline hal::BackendConfig configWith(platform::Clock *clock, const char *options)
{
    hal::BackendConfig cfg;
    cfg.clock = clock;
    cfg.options = hal::OptionList(options);
    return cfg;
}

/// Expects \a create(cfg) to fail with InvalidArgument once the options of \a cfg are each of
/// \a refused in turn.
template <class Create>
void expectOptionsRefused(Create create, hal::BackendConfig cfg,
                          std::initializer_list<const char *> refused)
{
    for (const char *options : refused) {
        cfg.options = hal::OptionList(options);
        EXPECT_EQ(errcOf(create(cfg)), Errc::InvalidArgument) << options;
    }
}

/// A Mock codec packet with its own storage.
struct TestPacket {
    std::vector<std::uint8_t> bytes = std::vector<std::uint8_t>(kMockPacketMaxBytes);
    hal::Packet packet;

    TestPacket(hal::StreamKind kind, std::uint32_t frame, int width, int height, int fps = 25)
    {
        const bool key = frame % 10 == 0;
        bytes.resize(writeMockPacket(bytes.data(), kind, frame, width, height, key));
        packet.streamIndex = kind == hal::StreamKind::Color ? 0 : 1;
        packet.data = bytes.data();
        packet.size = bytes.size();
        packet.pts = hal::Pts(static_cast<std::int64_t>(frame) * 1'000'000'000 / fps);
        packet.dts = packet.pts;
        packet.keyframe = key;
    }
};

/// FNV-1a over the planes of \a img (rows only, no padding).
inline std::uint64_t hashImage(const hal::ImageView &img, std::uint64_t h = 1469598103934665603ull)
{
    for (int p = 0; p < hal::planeCount(img.format); ++p) {
        const hal::PlaneLayout l = hal::planeLayout(img.format, img.width, img.height, p);
        for (int y = 0; y < l.rows; ++y) {
            const std::uint8_t *row = img.row(p, y);
            for (int x = 0; x < l.rowBytes; ++x) {
                h ^= row[x];
                h *= 1099511628211ull;
            }
        }
    }
    return h;
}

/// FNV-1a step over the bytes of a trivially copyable value.
template <class T> std::uint64_t hashValue(std::uint64_t h, const T &v)
{
    const auto *b = reinterpret_cast<const std::uint8_t *>(&v);
    for (std::size_t i = 0; i < sizeof(T); ++i) {
        h ^= b[i];
        h *= 1099511628211ull;
    }
    return h;
}

} // namespace depthtouch::drivers::testing
