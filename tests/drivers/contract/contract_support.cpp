#include "contract_support.h"

#include <cctype>
#include <cstdio>
#include <cstdlib>

#include <unistd.h>

#include "depthtouch/drivers/mock/mock_display.h"
#include "depthtouch/drivers/mock/mock_haptic_device.h"
#include "depthtouch/drivers/mock/mock_remote_input.h"
#ifdef DT_TEST_HAVE_EVDEV
#include "drivers/evdev/fake_event_source.h"
#endif
#include "depthtouch/drivers/mock/mock_depth_camera.h"
#if defined(DT_CONTRACT_FALCON)
#include "depthtouch/drivers/usb/fake_falcon.h"
#include "depthtouch/drivers/usb/falcon_haptic_device.h"
#endif
#include "depthtouch/drivers/mock/sim_haptic_device.h"

namespace depthtouch::contract {

#if DT_CONTRACT_V4L2
const DepthCameraHarness *v4l2DepthCameraHarness(); // v4l2_contract_harness.cpp: fake kernel
#endif


std::string backendParamName(const ::testing::TestParamInfo<std::string> &info)
{
    std::string out = info.param;
    for (char &c : out)
        if (std::isalnum(static_cast<unsigned char>(c)) == 0)
            c = '_';
    return out;
}

// The harness entries. A real backend adds its entry next to the mock one.

const HapticHarness *hapticHarness(std::string_view name)
{
    using drivers::MockHapticDevice;
    static const HapticHarness kMock{
        "",
        true,
        true,
        [](hal::HapticDevice &d) { dynamic_cast<MockHapticDevice &>(d).disconnect(); },
        [](hal::HapticDevice &d) { dynamic_cast<MockHapticDevice &>(d).reconnect(); },
        [](const hal::HapticDevice &d) {
            return dynamic_cast<const MockHapticDevice &>(d).lastForce();
        },
        [](hal::HapticDevice &d, platform::TimePoint t0) {
            using std::chrono::milliseconds;
            dynamic_cast<MockHapticDevice &>(d).setWaypoints({
                {t0, {0.0, 0.0, 0.0}, 0},
                {t0 + milliseconds(20), {0.2, -0.01, 0.03}, 1}, // beyond +x
                {t0 + milliseconds(40), {-0.2, 0.3, -0.2}, 3},  // beyond -x, +y, -z
                {t0 + milliseconds(60), {0.01, 0.02, 0.03}, 0},
            });
        },
    };
    static const HapticHarness kNone{"", true, false, {}, {}, {}, {}};
#if defined(DT_CONTRACT_FALCON)
    // The Falcon driver against its device emulator (option emulate): the real protocol, kinematics
    // and fault paths without the device.
    using drivers::FakeFalcon;
    using drivers::FalconHapticDevice;
    static const HapticHarness kFalcon{
        "emulate=1",
        true,
        true,
        [](hal::HapticDevice &d) {
            dynamic_cast<FakeFalcon &>(dynamic_cast<FalconHapticDevice &>(d).transport()).unplug();
        },
        [](hal::HapticDevice &d) {
            dynamic_cast<FakeFalcon &>(dynamic_cast<FalconHapticDevice &>(d).transport()).replug();
        },
        [](const hal::HapticDevice &d) {
            return dynamic_cast<const FalconHapticDevice &>(d).outputForce();
        },
        {},
    };
    if (name == "falcon")
        return &kFalcon;
#endif
    // The simulated hand explores with a strong push, so it reaches the workspace walls.
    using drivers::SimHapticDevice;
    static const HapticHarness kSim{
        "intent=explore,force=8,period=0.02,seed=7",
        true,
        true,
        [](hal::HapticDevice &d) { dynamic_cast<SimHapticDevice &>(d).disconnect(); },
        [](hal::HapticDevice &d) { dynamic_cast<SimHapticDevice &>(d).reconnect(); },
        [](const hal::HapticDevice &d) {
            return dynamic_cast<const SimHapticDevice &>(d).lastForce();
        },
        {},
    };
    if (name == "sim")
        return &kSim;
    if (name == "mock")
        return &kMock;
    if (name == "none")
        return &kNone;
    return nullptr;
}

// The ffmpeg backends read a real file: a color (H.264) + depth (FFV1 gray) MKV of 30 frames made
// once per run with the ffmpeg command-line tool. Empty when the tool is missing (no harness: the
// suites skip ffmpeg with a message).
const std::string &ffmpegContractClip()
{
    struct Clip {
        std::string dir;
        std::string path;
        Clip()
        {
            if (std::system("ffmpeg -version >/dev/null 2>&1") != 0) {
                std::fprintf(stderr,
                             "ffmpeg CLI not on PATH: no contract clip for the ffmpeg backends\n");
                return;
            }
            char tmpl[] = "/tmp/dt-contract-XXXXXX";
            if (::mkdtemp(tmpl) == nullptr)
                return;
            dir = tmpl;
            const std::string out = dir + "/clip.mkv";
            const std::string cmd =
                "ffmpeg -nostdin -v error -y -f lavfi -i testsrc=size=64x48:rate=30:duration=1 "
                "-f lavfi -i testsrc=size=64x48:rate=30:duration=1 -map 0 -map 1 "
                "-c:v:0 libx264 -pix_fmt:v:0 yuv420p -g 10 -bf 0 -c:v:1 ffv1 -pix_fmt:v:1 gray -g "
                "1 "
                "-metadata:s:v:0 title=color -metadata:s:v:1 title=depth "
                "-metadata:s:v:1 depth_near=0.5 -metadata:s:v:1 depth_far=4 "
                "-metadata:s:v:1 depth_mapping=inverse_z -metadata:s:v:1 depth_bits=8 " +
                out + " </dev/null";
            if (std::system(cmd.c_str()) == 0)
                path = out;
        }
        ~Clip()
        {
            if (!dir.empty()) {
                std::remove((dir + "/clip.mkv").c_str());
                ::rmdir(dir.c_str());
            }
        }
    };
    static const Clip clip;
    return clip.path;
}

const MediaSourceHarness *mediaSourceHarness(std::string_view name)
{
    static const MediaSourceHarness kMock{"", "mock://contract?frames=30&gop=10&width=32&height=24",
                                          "file:///nonexistent/clip.mkv", 30};
    if (name == "ffmpeg" && !ffmpegContractClip().empty()) {
        static const MediaSourceHarness kFfmpeg{"", ffmpegContractClip(),
                                                "/nonexistent/clip.mkv", 30};
        return &kFfmpeg;
    }
    return name == "mock" ? &kMock : nullptr;
}

const VideoDecoderHarness *videoDecoderHarness(std::string_view name)
{
    static const VideoDecoderHarness kMock{"", true, "mock", "",
                                           "mock://contract?frames=30&gop=10&width=32&height=24"};
    if (name == "ffmpeg" && !ffmpegContractClip().empty()) {
        static const VideoDecoderHarness kFfmpeg{"", true, "ffmpeg", "", ffmpegContractClip()};
        return &kFfmpeg;
    }
    return name == "mock" ? &kMock : nullptr;
}

const DisplayHarness *displayHarness(std::string_view name)
{
    using drivers::MockDisplay;
    static const DisplayHarness kMock{
        "",
        true,
        true,
        [](hal::Display &d) { dynamic_cast<MockDisplay &>(d).loseDisplay(); },
        [](hal::Display &d) { dynamic_cast<MockDisplay &>(d).restoreDisplay(); },
    };
    // EGL displays: real GL on the simulated clock (their vertical blank is simulated or paced on
    // the backend clock); nothing can unplug them from a test.
    static const DisplayHarness kEgl{"", true, true, {}, {}};
    if (name == "headless" || name == "x11")
        return &kEgl;
    return name == "mock" ? &kMock : nullptr;
}

const RemoteInputHarness *remoteInputHarness(std::string_view name)
{
    using drivers::MockRemoteInput;
    static const RemoteInputHarness kMock{
        "",
        true,
        [](hal::RemoteInput &r, hal::Key key, platform::TimePoint at) {
            dynamic_cast<MockRemoteInput &>(r).pushKey(key, at);
        },
        [](hal::RemoteInput &r) { dynamic_cast<MockRemoteInput &>(r).unplug(); },
    };
    static const RemoteInputHarness kNone{"", true, {}, {}};
#ifdef DT_TEST_HAVE_EVDEV
    // evdev on a fake event stream: the records a remote's input device would deliver.
    using drivers::EvdevRemoteInput;
    using drivers::test::FakeEventSource;
    static const RemoteInputHarness kEvdev{
        "",
        true,
        [](hal::RemoteInput &r, hal::Key key, platform::TimePoint at) {
            auto &fake = dynamic_cast<FakeEventSource &>(
                dynamic_cast<EvdevRemoteInput &>(r).source());
            const auto code = static_cast<unsigned short>(key);
            fake.pushKey(at, code, 1);
            fake.pushKey(at + std::chrono::milliseconds(100), code, 0);
        },
        [](hal::RemoteInput &r) {
            auto &fake = dynamic_cast<FakeEventSource &>(
                dynamic_cast<EvdevRemoteInput &>(r).source());
            fake.pushError(platform::TimePoint{}, Errc::NoDevice);
        },
        [](const hal::BackendConfig &cfg) -> Result<std::unique_ptr<hal::RemoteInput>> {
            auto r = EvdevRemoteInput::createWithSource(cfg, std::make_unique<FakeEventSource>());
            if (!r)
                return unexpected(r.error());
            return std::unique_ptr<hal::RemoteInput>(std::move(*r));
        },
    };
    if (name == "evdev")
        return &kEvdev;
#endif
    if (name == "mock")
        return &kMock;
    if (name == "none")
        return &kNone;
    return nullptr;
}

const DepthCameraHarness *depthCameraHarness(std::string_view name)
{
    using drivers::MockDepthCamera;
    static const DepthCameraHarness kMock{
        "",
        true,
        [](hal::DepthCamera &c) { dynamic_cast<MockDepthCamera &>(c).unplug(); },
        [](hal::DepthCamera &c) { dynamic_cast<MockDepthCamera &>(c).replug(); },
    };
#if DT_CONTRACT_V4L2
    if (name == "v4l2")
        return v4l2DepthCameraHarness();
#endif
    return name == "mock" ? &kMock : nullptr;
}

} // namespace depthtouch::contract
