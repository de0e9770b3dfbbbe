// KMS connector and mode selection against a fake DRM (DrmApi), and the kms backend's NoDevice
// on a machine without /dev/dri.
#include <filesystem>
#include <map>

#include <gtest/gtest.h>

#include "depthtouch/drivers/backends.h"
#include "depthtouch/drivers/egl/egl_gbm_display.h"
#include "depthtouch/drivers/egl/kms_output.h"
#include "display_selection.h"

namespace depthtouch::drivers {
namespace {

class FakeDrm final : public DrmApi {
public:
    std::vector<std::string> listCards() override
    {
        std::vector<std::string> out;
        for (const auto &[path, card] : cards)
            out.push_back(path);
        return out;
    }
    Result<DrmCardInfo> probeCard(const std::string &path) override
    {
        auto it = cards.find(path);
        if (it == cards.end())
            return unexpected(Errc::NoDevice, "no such card");
        if (!it->second)
            return unexpected(Errc::NotSupported, "not KMS");
        return *it->second;
    }
    std::map<std::string, std::optional<DrmCardInfo>> cards;
};

DrmModeInfo mode(int w, int h, double hz, bool preferred = false)
{
    return {std::to_string(w) + "x" + std::to_string(h), w, h, hz, preferred};
}

/// card0: a render-only GPU; card1: HDMI-A-1 (connected TV, 1080p preferred) and DP-1 (empty).
FakeDrm setTopBox()
{
    FakeDrm drm;
    drm.cards["/dev/dri/card0"] = std::nullopt;
    DrmCardInfo card;
    card.path = "/dev/dri/card1";
    card.connectors.push_back({31, "HDMI-A-1", true,
                               {mode(1280, 720, 60.0), mode(1920, 1080, 60.0, true),
                                mode(1920, 1080, 50.0), mode(1920, 1080, 59.94),
                                mode(720, 576, 50.0)}});
    card.connectors.push_back({32, "DP-1", false, {}});
    drm.cards["/dev/dri/card1"] = card;
    return drm;
}

hal::DisplayConfig withMode(const char *m)
{
    hal::DisplayConfig cfg;
    cfg.mode = m;
    return cfg;
}

TEST(KmsOutputTest, defaultIsThePreferredModeOfTheFirstConnectedConnector)
{
    FakeDrm drm = setTopBox();
    auto sel = selectKmsOutput(drm, {});
    ASSERT_TRUE(sel) << sel.error().what;
    EXPECT_EQ(sel->card.path, "/dev/dri/card1"); // card0 has no KMS: skipped
    EXPECT_EQ(sel->connectorInfo().name, "HDMI-A-1");
    EXPECT_EQ(sel->modeInfo().width, 1920);
    EXPECT_DOUBLE_EQ(sel->modeInfo().refreshHz, 60.0);
}

TEST(KmsOutputTest, requestedSizeAndRateChooseTheNearestMode)
{
    FakeDrm drm = setTopBox();
    auto sel = selectKmsOutput(drm, withMode("1920x1080@50"));
    ASSERT_TRUE(sel);
    EXPECT_DOUBLE_EQ(sel->modeInfo().refreshHz, 50.0);
    sel = selectKmsOutput(drm, withMode("HDMI-A-1:1920x1080@59.9"));
    ASSERT_TRUE(sel);
    EXPECT_DOUBLE_EQ(sel->modeInfo().refreshHz, 59.94);
    // Size without a rate: the highest rate of that size.
    sel = selectKmsOutput(drm, withMode("1920x1080"));
    ASSERT_TRUE(sel);
    EXPECT_DOUBLE_EQ(sel->modeInfo().refreshHz, 60.0);
    // DisplayConfig fields win over the mode string.
    hal::DisplayConfig cfg = withMode("1920x1080@60");
    cfg.width = 720;
    cfg.height = 576;
    cfg.refreshHz = 50.0;
    sel = selectKmsOutput(drm, cfg);
    ASSERT_TRUE(sel);
    EXPECT_EQ(sel->modeInfo().height, 576);
}

TEST(KmsOutputTest, missingThingsGiveClearErrors)
{
    FakeDrm drm = setTopBox();
    EXPECT_EQ(selectKmsOutput(drm, withMode("1920x1080@30")).error().code, Errc::NotSupported);
    EXPECT_EQ(selectKmsOutput(drm, withMode("640x480")).error().code, Errc::NotSupported);
    EXPECT_EQ(selectKmsOutput(drm, withMode("DP-1")).error().code, Errc::NoDevice);
    EXPECT_EQ(selectKmsOutput(drm, withMode("HDMI-A-2")).error().code, Errc::NoDevice);
    EXPECT_EQ(selectKmsOutput(drm, withMode("1920x")).error().code, Errc::NotSupported);
    hal::DisplayConfig negative;
    negative.width = -1;
    EXPECT_EQ(selectKmsOutput(drm, negative).error().code, Errc::InvalidArgument);
    FakeDrm empty;
    EXPECT_EQ(selectKmsOutput(empty, {}).error().code, Errc::NoDevice);
    // A TV unplugged from every connector.
    drm.cards["/dev/dri/card1"]->connectors[0].connected = false;
    EXPECT_EQ(selectKmsOutput(drm, {}).error().code, Errc::NoDevice);
}

TEST(KmsOutputTest, screenModeFollowsAnExplicitModeElseTheContentSizeWhenTheSinkHasIt)
{
    FakeDrm drm = setTopBox();
    hal::DisplayConfig content;
    content.width = 960; // side-by-side of a 480x324 clip: no such mode on a TV
    content.height = 324;
    // GIVEN no mode text: the content size has no mode, so the preferred one is used
    auto sel = selectKmsScreenMode(drm, content, "");
    ASSERT_TRUE(sel) << sel.error().what;
    EXPECT_EQ(sel->modeInfo().width, 1920);
    EXPECT_DOUBLE_EQ(sel->modeInfo().refreshHz, 60.0);
    // A content size the sink offers is taken.
    hal::DisplayConfig hd;
    hd.width = 1280;
    hd.height = 720;
    sel = selectKmsScreenMode(drm, hd, "");
    ASSERT_TRUE(sel);
    EXPECT_EQ(sel->modeInfo().width, 1280);
    // An explicit mode (option, else cfg.mode) wins over the content size, and is strict.
    sel = selectKmsScreenMode(drm, hd, "HDMI-A-1:720x576@50");
    ASSERT_TRUE(sel);
    EXPECT_EQ(sel->modeInfo().height, 576);
    hal::DisplayConfig withText = hd;
    withText.mode = "1920x1080@50";
    sel = selectKmsScreenMode(drm, withText, "");
    ASSERT_TRUE(sel);
    EXPECT_DOUBLE_EQ(sel->modeInfo().refreshHz, 50.0);
    EXPECT_EQ(selectKmsScreenMode(drm, hd, "640x480").error().code, Errc::NotSupported);
    // A connector alone keeps the content-size rule on that connector.
    sel = selectKmsScreenMode(drm, content, "HDMI-A-1");
    ASSERT_TRUE(sel);
    EXPECT_EQ(sel->connectorInfo().name, "HDMI-A-1");
    EXPECT_EQ(sel->modeInfo().width, 1920);
    EXPECT_EQ(selectKmsScreenMode(drm, content, "DP-1").error().code, Errc::NoDevice);
    hal::DisplayConfig negative;
    negative.height = -5;
    EXPECT_EQ(selectKmsScreenMode(drm, negative, "").error().code, Errc::InvalidArgument);
}

TEST(KmsOutputTest, crtcIsTheEncodersCurrentOneElseTheFirstItCanDrive)
{
    const std::vector<std::uint32_t> crtcs = {50, 51, 52};
    // The connector's encoder 20 drives CRTC 52 now: keep it (no flicker, no stealing).
    EXPECT_EQ(chooseCrtc(20, {{20, 52, 0b111}}, crtcs), 52u);
    // No current encoder: the first CRTC in card order that one of its encoders can drive.
    EXPECT_EQ(chooseCrtc(0, {{20, 0, 0b100}, {21, 0, 0b110}}, crtcs), 51u);
    // The current encoder drives nothing: same rule.
    EXPECT_EQ(chooseCrtc(20, {{20, 0, 0b100}}, crtcs), 52u);
    // No encoder can drive any CRTC of the card.
    EXPECT_EQ(chooseCrtc(0, {{20, 0, 0b1000}}, crtcs), 0u);
    EXPECT_EQ(chooseCrtc(0, {}, crtcs), 0u);
}

TEST(KmsBackendTest, noDrmDeviceIsNoDevice)
{
    if (std::filesystem::exists("/dev/dri"))
        GTEST_SKIP() << "This machine has /dev/dri";
    EXPECT_EQ(EglGbmDisplay::create({}).error().code, Errc::NoDevice);
    // Autoprobe moves on to the next display.
    EXPECT_NE(test::refusedThenAutoprobed("kms", "No DRM device"), "kms");
}

TEST(KmsBackendTest, optionsAreCheckedBeforeTheDevice)
{
    // Bad options are bad input (exit code 2 in the CLI) whether or not a card exists.
    hal::BackendConfig cfg;
    cfg.options = hal::OptionList("resolution=1080p");
    EXPECT_EQ(EglGbmDisplay::create(cfg).error().code, Errc::InvalidArgument);
    cfg.options = hal::OptionList("mode=1920x");
    EXPECT_EQ(EglGbmDisplay::create(cfg).error().code, Errc::InvalidArgument);
    cfg.options = hal::OptionList("readback=maybe");
    EXPECT_EQ(EglGbmDisplay::create(cfg).error().code, Errc::InvalidArgument);
    // Good ones parse.
    cfg.options = hal::OptionList("mode=HDMI-A-1:1280x720@50,card=/dev/dri/card1,readback=1");
    auto s = EglGbmDisplay::Settings::parse(cfg);
    ASSERT_TRUE(s) << s.error().what;
    EXPECT_EQ(s->mode, "HDMI-A-1:1280x720@50");
    EXPECT_EQ(s->card, "/dev/dri/card1");
    EXPECT_TRUE(s->readback);
    // The card may come as the device path too.
    hal::BackendConfig dev;
    dev.device = "/dev/dri/card2";
    auto d = EglGbmDisplay::Settings::parse(dev);
    ASSERT_TRUE(d);
    EXPECT_EQ(d->card, "/dev/dri/card2");
    EXPECT_FALSE(d->readback);
    // A card path that does not exist is no device.
    cfg.options = hal::OptionList("card=/nonexistent/card7");
    EXPECT_EQ(EglGbmDisplay::create(cfg).error().code, Errc::NoDevice);
}

} // namespace
} // namespace depthtouch::drivers
