/// \file
/// \brief Golden tests of what is drawn over the surface on a real GLES 3 context (EGL surfaceless,
/// llvmpipe): the haptic avatar, the on-screen display and PNG snapshots, including snapshots
/// queued faster than they are written. Skips without the platform.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <thread>
#include <vector>

#include <glm/vec4.hpp>
#include <GLES3/gl3.h>

#include "app/render/egl_test_context.h"
#include "app/render/golden_fixture.h"
#include "depthtouch/haptics/height_field.h"
#include "depthtouch/media/image_io.h"
#include "depthtouch/render/render_target.h"
#include "depthtouch/render/renderer.h"
#include "depthtouch/render/snapshot.h"

using namespace depthtouch;
using namespace depthtouch::render;
using namespace depthtouch::render::golden; // the fixture, its picture helpers and test frames

TEST_F(RenderGoldenTest, avatarOsdAndSnapshot)
{
    ASSERT_NO_FATAL_FAILURE(showFlatPlane(64, 48, {126, 128, 128}, 1.2)); // grey
    const Picture plain = draw(200, 150);
    // GIVEN the proxy resting on the surface near the box centre and the OSD on
    AvatarState av;
    av.visible = true;
    av.proxy = {0.01, -0.005, renderer_->mapping().point(0, 0, 128).z + av.radius};
    av.hip = av.proxy - glm::dvec3(0.0, 0.0, 0.004);
    renderer_->setAvatar(av);
    OsdState osd;
    osd.visible = true;
    osd.status = "PLAYING";
    osd.hapticsOn = true;
    osd.force = 4.0;
    renderer_->setOsd(osd);
    const Picture withAvatar = draw(200, 150);
    // THEN the pixel at the proxy is the sphere's warm colour instead of the grey surface
    const auto eyes = eyesFor(StereoMode::Mono, 200, 150);
    const glm::dvec2 at = project(eyes[0], 150, av.proxy + glm::dvec3(0, 0, av.radius));
    const Rgb before = plain.at(static_cast<int>(at.x), static_cast<int>(at.y));
    const Rgb sphere = withAvatar.at(static_cast<int>(at.x), static_cast<int>(at.y));
    EXPECT_NEAR(before.r, before.b, 3);
    EXPECT_GT(sphere.r, sphere.b + 60);
    // AND the OSD changed the top-left corner but not the bottom-right one
    int changedTopLeft = 0;
    int changedBottomRight = 0;
    for (int y = 0; y < 40; ++y)
        for (int x = 0; x < 60; ++x) {
            changedTopLeft += plain.at(x, y).g != withAvatar.at(x, y).g ? 1 : 0;
            changedBottomRight +=
                plain.at(199 - x, 149 - y).g != withAvatar.at(199 - x, 149 - y).g ? 1 : 0;
        }
    EXPECT_GT(changedTopLeft, 200);
    EXPECT_EQ(changedBottomRight, 0);

    // WHEN snapshotted to PNG THEN reading the file back gives the same pixels
    auto t = RenderTarget::create(200, 150);
    ASSERT_TRUE(t);
    ASSERT_TRUE(renderer_->render(*t));
    const std::string dir = ::testing::TempDir() + "/dt_render_snapshots";
    std::filesystem::remove_all(dir);
    Snapshotter snap(dir, 2);
    auto first = snap.onFrame(*t);
    ASSERT_TRUE(first);
    ASSERT_TRUE(first->has_value());
    auto second = snap.onFrame(*t);
    ASSERT_TRUE(second);
    EXPECT_FALSE(second->has_value());
    snap.request();
    auto third = snap.onFrame(*t);
    ASSERT_TRUE(third);
    ASSERT_TRUE(third->has_value());
    ASSERT_TRUE(snap.flush());
    EXPECT_EQ(snap.written(), 2u);
    auto img = media::readImage(**first, media::PixelFormat::Rgb24);
    ASSERT_TRUE(img);
    ASSERT_EQ(img->width, 200);
    ASSERT_EQ(img->height, 150);
    for (int y = 0; y < 150; ++y)
        ASSERT_EQ(0, std::memcmp(img->row(y),
                                 withAvatar.rgb.data() + static_cast<std::size_t>(y) * 600, 600))
            << y;
}

// The OSD shows the stiffness the finger feels (what the remote's CH+ and CH− change) on a line of
// its own under the haptics line: the panel grows by that line, and the line's pixels follow the
// number (900 and 800 N/m, the same length of text, draw differently there and nowhere else).
TEST_F(RenderGoldenTest, theOsdShowsTheStiffnessOnALineOfItsOwn)
{
    ASSERT_NO_FATAL_FAILURE(showFlatPlane(64, 48, {126, 128, 128}, 1.2)); // grey
    OsdState osd;
    osd.visible = true;
    osd.status = "PLAYING";
    osd.hapticsOn = true;
    renderer_->setOsd(osd);
    const Picture without = draw(200, 150);
    osd.stiffness = 900.0;
    renderer_->setOsd(osd);
    const Picture k900 = draw(200, 150);
    osd.stiffness = 800.0;
    renderer_->setOsd(osd);
    const Picture k800 = draw(200, 150);
    // Rows (from the top) where two pictures differ, over the whole width.
    const auto rowsDiffering = [](const Picture &a, const Picture &b) {
        std::vector<int> rows;
        for (int y = 0; y < 150; ++y)
            for (int x = 0; x < 200; ++x)
                if (a.at(x, y).g != b.at(x, y).g || a.at(x, y).r != b.at(x, y).r) {
                    rows.push_back(y);
                    break;
                }
        return rows;
    };
    const std::vector<int> grown = rowsDiffering(without, k900);
    const std::vector<int> number = rowsDiffering(k900, k800);
    ASSERT_FALSE(grown.empty()) << "the stiffness line changed nothing";
    ASSERT_FALSE(number.empty()) << "900 and 800 N/m look the same";
    // The number's rows are one text line (8 px at this size) in the panel's top 60 rows, below
    // the status and haptics lines (which 900 and 800 leave alone).
    EXPECT_LE(number.back() - number.front(), 8);
    EXPECT_GT(number.front(), 20);
    EXPECT_LT(number.back(), 60);
    // A stiffness of 0 (no haptic task) draws no line: the picture of the plain OSD.
    osd.stiffness = 0.0;
    renderer_->setOsd(osd);
    EXPECT_TRUE(rowsDiffering(without, draw(200, 150)).empty());
}

// A haptic device that is not connected (lost, or not yet plugged in where the player waits for
// it) reads "HAPTICS: NO DEVICE" instead of "HAPTICS ON": the haptics line changes, in grey, not
// the green of a device that pushes back.
TEST_F(RenderGoldenTest, theOsdSaysWhenTheHapticDeviceIsNotConnected)
{
    ASSERT_NO_FATAL_FAILURE(showFlatPlane(64, 48, {126, 128, 128}, 1.2)); // grey
    OsdState osd;
    osd.visible = true;
    osd.status = "PLAYING";
    osd.hapticsOn = true;
    renderer_->setOsd(osd);
    const Picture on = draw(200, 150);
    osd.deviceConnected = false;
    renderer_->setOsd(osd);
    const Picture noDevice = draw(200, 150);
    // The haptics line (the second text line, under the status) is what changes.
    int firstRow = 150;
    int lastRow = -1;
    for (int y = 0; y < 150; ++y)
        for (int x = 0; x < 200; ++x)
            if (on.at(x, y).g != noDevice.at(x, y).g || on.at(x, y).r != noDevice.at(x, y).r) {
                firstRow = std::min(firstRow, y);
                lastRow = std::max(lastRow, y);
            }
    ASSERT_GE(lastRow, 0) << "the device's state changed nothing on screen";
    EXPECT_GT(firstRow, 10) << "the status line above it is left alone";
    EXPECT_LT(lastRow, 60) << "within the panel (its three lines end above row 60)";
    // No green text: a pixel whose green clearly outweighs red and blue is the "ON" colour.
    const auto greenText = [&](const Picture &p) {
        int n = 0;
        for (int y = 0; y < 40; ++y)
            for (int x = 0; x < 200; ++x)
                n += p.at(x, y).g > p.at(x, y).r + 60 ? 1 : 0;
        return n;
    };
    EXPECT_GT(greenText(on), 20) << "HAPTICS ON is green";
    EXPECT_EQ(greenText(noDevice), 0) << "HAPTICS: NO DEVICE is not";
}

// A remote waited for and not plugged in (or lost) adds a line "REMOTE: NO DEVICE" under the
// haptics line, in grey; a remote that is there (or no remote) draws the OSD as before.
TEST_F(RenderGoldenTest, theOsdSaysWhenTheRemoteIsNotConnected)
{
    ASSERT_NO_FATAL_FAILURE(showFlatPlane(64, 48, {126, 128, 128}, 1.2)); // grey
    OsdState osd;
    osd.visible = true;
    osd.status = "PLAYING";
    osd.hapticsOn = true;
    renderer_->setOsd(osd);
    const Picture there = draw(200, 150);
    osd.remoteConnected = false;
    renderer_->setOsd(osd);
    const Picture missing = draw(200, 150);
    // Within the plain panel (x < 88: its 84 px from the 6 px margin; the longer line widens the
    // panel to the right), the rows that differ are the new line's and the force bar's (moved
    // down one line).
    constexpr int kPanelRight = 88;
    int firstRow = 150;
    int lastRow = -1;
    for (int y = 0; y < 150; ++y)
        for (int x = 0; x < kPanelRight; ++x)
            if (there.at(x, y).g != missing.at(x, y).g || there.at(x, y).r != missing.at(x, y).r) {
                firstRow = std::min(firstRow, y);
                lastRow = std::max(lastRow, y);
            }
    ASSERT_GE(lastRow, 0) << "the remote's state changed nothing on screen";
    EXPECT_GT(firstRow, 30) << "the status and haptics lines above it are left alone";
    EXPECT_LT(lastRow, 66) << "within the panel (its four lines end above row 66)";
    // The line is text: light grey pixels (r, g and b alike, brighter than the plane seen through
    // the panel) in its rows, where the plain OSD has the bar's dark frame.
    const auto lightGrey = [&](const Picture &p) {
        int n = 0;
        for (int y = firstRow; y < firstRow + 8; ++y)
            for (int x = 0; x < kPanelRight; ++x) {
                const Rgb c = p.at(x, y);
                n += c.r > 110 && std::abs(c.r - c.g) < 12 && std::abs(c.g - c.b) < 12 ? 1 : 0;
            }
        return n;
    };
    EXPECT_EQ(lightGrey(there), 0);
    EXPECT_GT(lightGrey(missing), 40) << "no grey text where the line should be";
    // The status and haptics lines keep their look: HAPTICS ON stays green.
    int green = 0;
    for (int y = 0; y < firstRow; ++y)
        for (int x = 0; x < kPanelRight; ++x)
            green += missing.at(x, y).g > missing.at(x, y).r + 60 ? 1 : 0;
    EXPECT_GT(green, 20) << "HAPTICS ON is still green above the remote's line";
    // Connected again: the plain OSD, pixel for pixel.
    osd.remoteConnected = true;
    renderer_->setOsd(osd);
    const Picture back = draw(200, 150);
    for (int y = 0; y < 150; ++y)
        for (int x = 0; x < 200; ++x)
            ASSERT_EQ(back.at(x, y).g, there.at(x, y).g) << "at " << x << "," << y;
}

TEST_F(RenderGoldenTest, theAvatarSphereIsRoundWhereItCutsTheSurface)
{
    // GIVEN a flat surface and a large proxy sphere (r = 50 mm) sunk into it until only its front
    // 5 % shows: the visible cap is where the sphere's mesh lies in front of the surface
    ASSERT_NO_FATAL_FAILURE(showFlatPlane(64, 48, {126, 128, 128}, 1.2)); // grey
    AvatarState av;
    av.visible = true;
    av.radius = 0.05;
    const double surface = renderer_->mapping().point(32, 24, 128).z;
    av.proxy = {0.0, 0.0, surface - 0.95 * av.radius};
    av.hip = av.proxy; // no HIP marker
    renderer_->setAvatar(av);
    const Picture pic = draw(400, 300);
    const auto eyes = eyesFor(StereoMode::Mono, 400, 300);
    const glm::dvec2 at = project(eyes[0], 300, av.proxy + glm::dvec3(0, 0, av.radius));
    const int cx = static_cast<int>(at.x);
    const int cy = static_cast<int>(at.y);
    const auto warm = [&pic](int x, int y) {
        const Rgb c = pic.at(x, y);
        return c.r > c.b + 60;
    };
    ASSERT_TRUE(warm(cx, cy));
    // WHEN the cap's half-widths are measured from its centre, across and along the sphere's axis
    int left = 0, right = 0, up = 0, down = 0;
    while (cx - left - 1 >= 0 && warm(cx - left - 1, cy))
        ++left;
    while (cx + right + 1 < 400 && warm(cx + right + 1, cy))
        ++right;
    while (cy - up - 1 >= 0 && warm(cx, cy - up - 1))
        ++up;
    while (cy + down + 1 < 300 && warm(cx, cy + down + 1))
        ++down;
    // THEN the cap is a circle (a sphere cut by a plane facing the camera): its widths across and
    // along agree within 15 % (a sphere of 12 slices instead of 24 sags 3.4 % of r between its
    // meridians and shows a cap about 0.63 times as wide as it is tall)
    const double across = 0.5 * (left + right);
    const double along = 0.5 * (up + down);
    ASSERT_GT(along, 8.0) << "the cap is too small to measure";
    EXPECT_NEAR(across / along, 1.0, 0.15)
        << "cap " << left << "+" << right << " px across, " << up << "+" << down << " px along";
}

TEST_F(RenderGoldenTest, snapshotsQueuedFasterThanWrittenAreAllWrittenAndErrorsReported)
{
    const Depth8 d(64, 48, bumpy);
    ASSERT_TRUE(renderer_->setDepth(d.view()));
    auto t = RenderTarget::create(320, 240);
    ASSERT_TRUE(t);
    ASSERT_TRUE(renderer_->render(*t));
    const std::string dir = ::testing::TempDir() + "/dt_render_snapshot_burst";
    std::filesystem::remove_all(dir);
    {
        // WHEN every one of 12 frames is snapshotted (more than the writer queue holds)
        Snapshotter snap(dir, 1, "burst");
        for (int i = 0; i < 12; ++i) {
            auto r = snap.onFrame(*t);
            ASSERT_TRUE(r);
            ASSERT_TRUE(r->has_value());
        }
    } // the destructor waits for the writer
    // THEN every file is there and complete
    for (int i = 0; i < 12; ++i) {
        char name[64];
        std::snprintf(name, sizeof name, "/burst-%06d.png", i);
        auto img = media::readImage(dir + name, media::PixelFormat::Rgb24);
        ASSERT_TRUE(img) << name;
        EXPECT_EQ(img->width, 320);
    }
    // WHEN a snapshot's file cannot be written (a directory stands in its way)
    std::filesystem::remove(dir + "/burst-000000.png");
    std::filesystem::create_directories(dir + "/burst-000000.png");
    std::filesystem::remove(dir + "/burst-000001.png");
    Snapshotter again(dir, 1, "burst");
    auto r0 = again.onFrame(*t);
    ASSERT_TRUE(r0);
    auto r1 = again.onFrame(*t);
    // THEN the error comes back once (from flush() or the next frame), and the next file is written
    const auto flushed = again.flush();
    EXPECT_TRUE(!r1 || !flushed) << "the failed write was not reported";
    if (!flushed) {
        EXPECT_EQ(flushed.error().code, Errc::Io);
    }
    EXPECT_TRUE(again.flush()) << "an error is reported once";
    EXPECT_TRUE(std::filesystem::is_regular_file(dir + "/burst-000001.png"));
}
