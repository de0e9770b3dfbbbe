// The X11 window display on a private Xvfb server started by this program (skipped with a message
// when Xvfb is not installed): window and title, cleared colours read back, open on one thread and
// render on another, window close and X server loss as state Lost, and backend selection with and
// without $DISPLAY. The program also holds the Display contract suite; CTest runs it on `x11`
// separately (label contract).
#include <chrono>
#include <csignal>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include <GLES3/gl3.h>
#include <gtest/gtest.h>

#include "depthtouch/drivers/backends.h"
#include "depthtouch/drivers/egl/egl_x11_display.h"
#include "display_selection.h"
#include "gl_pixels.h"
#include "xvfb_server.h"

// Last: Xlib defines macros (None, Bool, Status) that other headers must not see.
#include <X11/Xlib.h>
#include <X11/Xutil.h>

namespace depthtouch::drivers {
namespace {

using test::drawHalves;
using test::expectRgb;
using test::pixelAt;
using test::pixelView;
using test::refusedThenAutoprobed;
using test::Rgb;

using testing::XvfbServer;
using State = hal::Display::State;

/// The Xvfb server of the whole program; $DISPLAY points at it while it runs.
class XvfbEnvironment final : public ::testing::Environment {
public:
    void SetUp() override
    {
        if (server.start())
            ::setenv("DISPLAY", server.name().c_str(), 1);
    }
    void TearDown() override { server.stop(SIGTERM); }

    XvfbServer server;
};

XvfbEnvironment *const gXvfb =
    static_cast<XvfbEnvironment *>(::testing::AddGlobalTestEnvironment(new XvfbEnvironment));

/// Sets or unsets $DISPLAY for one scope.
class ScopedDisplayEnv {
public:
    explicit ScopedDisplayEnv(const char *value)
    {
        if (const char *old = std::getenv("DISPLAY"); old != nullptr)
            saved_ = old;
        if (value != nullptr)
            ::setenv("DISPLAY", value, 1);
        else
            ::unsetenv("DISPLAY");
    }
    ~ScopedDisplayEnv()
    {
        if (saved_.empty())
            ::unsetenv("DISPLAY");
        else
            ::setenv("DISPLAY", saved_.c_str(), 1);
    }
    ScopedDisplayEnv(const ScopedDisplayEnv &) = delete;
    ScopedDisplayEnv &operator=(const ScopedDisplayEnv &) = delete;

private:
    std::string saved_;
};

/// An X client of its own, as a window manager or a user would be.
class XClient {
public:
    explicit XClient(const std::string &name) : dpy_(XOpenDisplay(name.c_str())) {}
    ~XClient()
    {
        if (dpy_ != nullptr)
            XCloseDisplay(dpy_);
    }
    XClient(const XClient &) = delete;
    XClient &operator=(const XClient &) = delete;

    [[nodiscard]] ::Display *get() const noexcept { return dpy_; }

    /// \return the top-level windows titled \a title.
    std::vector<::Window> windowsTitled(const char *title) const
    {
        std::vector<::Window> out;
        ::Window root = DefaultRootWindow(dpy_);
        ::Window rootRet = 0;
        ::Window parent = 0;
        ::Window *children = nullptr;
        unsigned count = 0;
        if (XQueryTree(dpy_, root, &rootRet, &parent, &children, &count) == 0)
            return out;
        for (unsigned i = 0; i < count; ++i) {
            char *name = nullptr;
            if (XFetchName(dpy_, children[i], &name) != 0 && name != nullptr) {
                if (std::string(name) == title)
                    out.push_back(children[i]);
                XFree(name);
            }
        }
        if (children != nullptr)
            XFree(children);
        return out;
    }

    /// Sends WM_DELETE_WINDOW to \a window, as a window manager does when the user closes it.
    void closeWindow(::Window window) const
    {
        XEvent ev{};
        ev.xclient.type = ClientMessage;
        ev.xclient.window = window;
        ev.xclient.message_type = XInternAtom(dpy_, "WM_PROTOCOLS", False);
        ev.xclient.format = 32;
        ev.xclient.data.l[0] = static_cast<long>(XInternAtom(dpy_, "WM_DELETE_WINDOW", False));
        ev.xclient.data.l[1] = CurrentTime;
        XSendEvent(dpy_, window, False, NoEventMask, &ev);
        XSync(dpy_, False);
    }

private:
    ::Display *dpy_;
};

class EglX11Test : public ::testing::Test {
protected:
    void SetUp() override
    {
        if (!gXvfb->server.running())
            GTEST_SKIP() << "No Xvfb server: " << gXvfb->server.why();
        cfg_.clock = &clock_;
    }

    std::unique_ptr<hal::Display> create(const char *options = "")
    {
        cfg_.options = hal::OptionList(options);
        auto d = EglX11Display::create(cfg_);
        EXPECT_TRUE(d) << d.error().what;
        return d ? std::move(*d) : nullptr;
    }

    /// Creates a display into d_ and opens a 160×120 window with dc_, makes it current when
    /// \a current, and presents once; fails the test (fatally) where any step fails.
    void openWindow(bool current)
    {
        d_ = create();
        ASSERT_NE(d_, nullptr);
        dc_.width = 160;
        dc_.height = 120;
        ASSERT_TRUE(d_->open(dc_));
        if (current) {
            ASSERT_TRUE(d_->makeCurrent());
        }
        ASSERT_TRUE(d_->present());
    }
    /// \return the X window of the x11 display \a d.
    static ::Window windowOf(hal::Display &d)
    {
        return static_cast<::Window>(dynamic_cast<EglX11Display &>(d).window());
    }
    /// Presents until the display reports Lost (X events arrive asynchronously).
    static bool presentUntilLost(hal::Display &d)
    {
        for (int i = 0; i < 200; ++i) {
            if (!d.present())
                return d.state() == State::Lost;
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        }
        return false;
    }

    platform::ManualClock clock_{platform::ManualClock::Mode::AutoAdvance};
    hal::BackendConfig cfg_;
    std::unique_ptr<hal::Display> d_; ///< The display of openWindow().
    hal::DisplayConfig dc_;           ///< Its configuration.
};

TEST_F(EglX11Test, opensAFixedSizeWindowTitledDepthTouch)
{
    auto d = create();
    ASSERT_NE(d, nullptr);
    EXPECT_TRUE(d->capabilities().hasGlesContext);
    EXPECT_FALSE(d->capabilities().offscreen);
    EXPECT_FALSE(d->capabilities().readback); // not asked for
    hal::DisplayConfig dc;
    dc.mode = "320x200@50";
    ASSERT_TRUE(d->open(dc));
    EXPECT_EQ(d->size().width, 320);
    EXPECT_EQ(d->size().height, 200);
    EXPECT_DOUBLE_EQ(d->refreshHz(), 50.0);
    EXPECT_EQ(d->framebuffer(), 0u);

    XClient other(gXvfb->server.name());
    ASSERT_NE(other.get(), nullptr);
    const auto windows = other.windowsTitled("DepthTouch");
    ASSERT_EQ(windows.size(), 1u);
    EXPECT_EQ(windows[0], dynamic_cast<EglX11Display &>(*d).window());
    XWindowAttributes attrs{};
    ASSERT_NE(XGetWindowAttributes(other.get(), windows[0], &attrs), 0);
    EXPECT_EQ(attrs.width, 320);
    EXPECT_EQ(attrs.height, 200);
    EXPECT_EQ(attrs.map_state, IsViewable);
    std::vector<std::uint8_t> buf;
    EXPECT_EQ(d->readPixels(pixelView(buf, 320, 200)).error().code, Errc::NotSupported);

    // AND close() takes the window away
    d->close();
    EXPECT_TRUE(other.windowsTitled("DepthTouch").empty());
    EXPECT_EQ(d->size().width, 0);
}

TEST_F(EglX11Test, clearedColorsReadBackTopRowFirst)
{
    auto d = create("readback=1");
    ASSERT_NE(d, nullptr);
    EXPECT_TRUE(d->capabilities().readback);
    hal::DisplayConfig dc;
    dc.width = 96;
    dc.height = 64;
    ASSERT_TRUE(d->open(dc));
    std::vector<std::uint8_t> buf;
    hal::ImageView img = pixelView(buf, 96, 64);
    EXPECT_EQ(d->readPixels(img).error().code, Errc::InvalidState); // nothing presented yet
    ASSERT_TRUE(d->makeCurrent());
    // GIVEN a frame whose top half is orange and bottom half blue
    const Rgb orange{255, 128, 0};
    const Rgb blue{0, 64, 255};
    drawHalves(96, 64, orange, blue);
    auto info = d->present();
    ASSERT_TRUE(info) << info.error().what;
    EXPECT_EQ(info->frameCounter, 1u);
    // THEN the presented frame reads back with its top row first
    ASSERT_TRUE(d->readPixels(img));
    expectRgb(pixelAt(img, 0, 0), orange, "top left");
    expectRgb(pixelAt(img, 95, 31), orange, "end of the top half");
    expectRgb(pixelAt(img, 0, 32), blue, "start of the bottom half");
    expectRgb(pixelAt(img, 95, 63), blue, "bottom right");
    // AND drawing the next frame does not change what was presented
    drawHalves(96, 64, blue, blue);
    ASSERT_TRUE(d->readPixels(img));
    expectRgb(pixelAt(img, 0, 0), orange, "top left while the next frame is drawn");
    ASSERT_TRUE(d->present());
    ASSERT_TRUE(d->readPixels(img));
    expectRgb(pixelAt(img, 0, 0), blue, "top left of the second frame");
    std::vector<std::uint8_t> small;
    EXPECT_EQ(d->readPixels(pixelView(small, 48, 32)).error().code, Errc::InvalidArgument);
}

TEST_F(EglX11Test, openedOnOneThreadRendersOnAnother)
{
    // The player opens the display and renders on its render thread; open() must leave no
    // context bound to the thread that called it.
    auto d = create("readback=1");
    ASSERT_NE(d, nullptr);
    hal::DisplayConfig dc;
    dc.width = 64;
    dc.height = 48;
    bool opened = false;
    std::thread opener([&] { opened = static_cast<bool>(d->open(dc)); });
    opener.join();
    ASSERT_TRUE(opened);
    ASSERT_TRUE(d->makeCurrent());
    drawHalves(64, 48, {10, 200, 30}, {10, 200, 30});
    ASSERT_TRUE(d->present());
    std::vector<std::uint8_t> buf;
    hal::ImageView img = pixelView(buf, 64, 48);
    ASSERT_TRUE(d->readPixels(img));
    expectRgb(pixelAt(img, 32, 24), {10, 200, 30}, "centre");
}

TEST_F(EglX11Test, closingTheWindowMakesTheDisplayLost)
{
    ASSERT_NO_FATAL_FAILURE(openWindow(false));
    // WHEN the user closes the window
    XClient wm(gXvfb->server.name());
    ASSERT_NE(wm.get(), nullptr);
    wm.closeWindow(windowOf(*d_));
    // THEN present() reports NoDevice and the display is Lost
    ASSERT_TRUE(presentUntilLost(*d_));
    EXPECT_EQ(d_->present().error().code, Errc::NoDevice);
    EXPECT_EQ(d_->makeCurrent().error().code, Errc::NoDevice);
    // AND closing and opening again gives a new window
    d_->close();
    EXPECT_EQ(d_->state(), State::Closed);
    ASSERT_TRUE(d_->open(dc_));
    auto info = d_->present();
    ASSERT_TRUE(info);
    EXPECT_EQ(info->frameCounter, 1u);
    EXPECT_EQ(wm.windowsTitled("DepthTouch").size(), 1u);
}

TEST_F(EglX11Test, aWindowDestroyedByAnotherClientMakesTheDisplayLost)
{
    ASSERT_NO_FATAL_FAILURE(openWindow(true));
    // WHEN another client destroys the window (requests on it then fail with X protocol errors,
    // which must not end the process)
    XClient other(gXvfb->server.name());
    ASSERT_NE(other.get(), nullptr);
    XDestroyWindow(other.get(), windowOf(*d_));
    XSync(other.get(), False);
    // THEN the display is Lost and closes cleanly
    ASSERT_TRUE(presentUntilLost(*d_));
    d_->close();
    EXPECT_TRUE(other.windowsTitled("DepthTouch").empty());
}

TEST_F(EglX11Test, losingTheXServerMakesTheDisplayLostWithoutACrash)
{
    // GIVEN a display on an X server of its own
    XvfbServer server;
    ASSERT_TRUE(server.start()) << server.why();
    cfg_.device = server.name();
    ASSERT_NO_FATAL_FAILURE(openWindow(true));
    // WHEN the server dies
    server.stop(SIGKILL);
    // THEN the display is Lost, and opening fails with NoDevice while no server runs
    ASSERT_TRUE(presentUntilLost(*d_));
    EXPECT_EQ(d_->makeCurrent().error().code, Errc::NoDevice);
    d_->close();
    EXPECT_EQ(d_->state(), State::Closed);
    EXPECT_EQ(d_->open(dc_).error().code, Errc::NoDevice);
    // AND once a server is back on that display, open() works and counting restarts
    ASSERT_TRUE(server.start(/*reuseNumber=*/true)) << server.why();
    ASSERT_EQ(server.name(), std::string(cfg_.device));
    ASSERT_TRUE(d_->open(dc_));
    auto info = d_->present();
    ASSERT_TRUE(info) << info.error().what;
    EXPECT_EQ(info->frameCounter, 1u);
    d_->close();
}

TEST_F(EglX11Test, optionsAreCheckedAndFullscreenCoversTheScreen)
{
    cfg_.options = hal::OptionList("fullscreen=maybe");
    EXPECT_EQ(EglX11Display::create(cfg_).error().code, Errc::InvalidArgument);
    cfg_.options = hal::OptionList("fulscreen=1");
    EXPECT_EQ(EglX11Display::create(cfg_).error().code, Errc::InvalidArgument);
    auto d = create("fullscreen=1");
    ASSERT_NE(d, nullptr);
    ASSERT_TRUE(d->open({}));
    EXPECT_EQ(d->size().width, 1280); // the Xvfb screen
    EXPECT_EQ(d->size().height, 720);
    ASSERT_TRUE(d->present());
}

TEST_F(EglX11Test, autoprobeTakesX11WhenAServerAnswers)
{
    hal::SelectionReport report;
    auto d = createDisplay("", cfg_, &report);
    ASSERT_TRUE(d) << report.message;
    // kms comes first, but this machine has no DRM card with a connected display
    EXPECT_EQ(report.chosen, "x11");
}

TEST(EglX11SelectionTest, withoutDisplayAutoprobeTakesHeadlessAndX11FailsClearly)
{
    ScopedDisplayEnv env(nullptr);
    // kms (tried first) finds no display here
    EXPECT_EQ(refusedThenAutoprobed("x11", "No X server"), "headless");
}

TEST(EglX11SelectionTest, unreachableServerIsNoDevice)
{
    // A display number no server uses here.
    ScopedDisplayEnv env(":4093");
    hal::SelectionReport report;
    auto x11 = createDisplay("x11", {}, &report);
    ASSERT_FALSE(x11);
    EXPECT_EQ(x11.error().code, Errc::NoDevice);
    EXPECT_NE(report.message.find("No X server"), std::string::npos) << report.message;
    auto any = createDisplay("", {}, &report);
    ASSERT_TRUE(any) << report.message;
    EXPECT_NE(report.chosen, "x11");
}

} // namespace
} // namespace depthtouch::drivers
