// The synthetic scenes' CPU geometry (app/synthetic/src/meshes.h): the curtain's folds, checked
// against the shape its header gives, vertex by vertex.
#include "meshes.h"

#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

namespace depthtouch::synthetic {
namespace {

TEST(SyntheticMeshesTest, theCurtainsFoldsDeepenLinearlyFromTopToBottom)
{
    // GIVEN a curtain 1.4 m wide, 0.9 m high, folds 35 mm deep and 0.22 m long (the curtain
    // scene's)
    constexpr float kWidth = 1.4f, kHeight = 0.9f, kFold = 0.035f, kPeriod = 0.22f;
    constexpr int kColumns = 280, kRows = 4;
    const MeshData m = makeCurtain(kWidth, kHeight, kFold, kPeriod, kColumns, kRows);
    ASSERT_EQ(m.positions.size(), static_cast<std::size_t>((kColumns + 1) * (kRows + 1)));
    // THEN every row's deepest fold is foldDepth (0.6 + 0.4 (0.5 - y / height)): the full depth at
    // the bottom edge, 0.6 of it at the top, and each vertex sits on that row's sine
    const float k = 2.0f * 3.14159265f / kPeriod;
    for (int r = 0; r <= kRows; ++r) {
        const float y = kHeight * (0.5f - static_cast<float>(r) / kRows);
        const float amplitude = kFold * (0.6f + 0.4f * (0.5f - y / kHeight));
        float deepest = 0.0f;
        for (int c = 0; c <= kColumns; ++c) {
            const glm::vec3 &p = m.positions[static_cast<std::size_t>(r * (kColumns + 1) + c)];
            ASSERT_NEAR(p.y, y, 1e-6f);
            EXPECT_NEAR(p.z, amplitude * std::sin(k * p.x), 1e-5f)
                << "row " << r << " column " << c;
            deepest = std::max(deepest, std::fabs(p.z));
        }
        EXPECT_NEAR(deepest, amplitude, 0.02f * kFold) << "row " << r;
    }
    EXPECT_NEAR(m.positions.front().y, kHeight / 2, 1e-6f); // row 0 is the top
}

} // namespace
} // namespace depthtouch::synthetic
