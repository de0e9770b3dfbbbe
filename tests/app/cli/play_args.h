#pragma once
/// \file
/// \brief Test support: the argument lists of `depthtouch play` runs for Process and
/// runProcess() (cli_process.h). The executable is the DEPTHTOUCH macro that the test's target
/// defines. Header-only.

#include <string>
#include <vector>

namespace depthtouch::testing {

/// A program and its arguments, as Process takes them.
using Args = std::vector<std::string>;

/// A mock clip of one second: 30 frames at 30 fps.
inline const std::string kMockClip = "mock://clip?frames=30&fps=30";

/// `depthtouch play URL` on the mock backends (haptic device \a haptic), then \a extra.
inline Args mockPlay(const std::string &url, const Args &extra = {},
                     const std::string &haptic = "none")
{
    Args a = {DEPTHTOUCH, "play",      url,    "--source", "mock", "--decoder",
              "mock",     "--display", "mock", "--haptic", haptic};
    a.insert(a.end(), extra.begin(), extra.end());
    return a;
}

/// `depthtouch play URL` on the ffmpeg source and decoder (mock display, no haptic device), then
/// \a extra.
inline Args ffmpegPlay(const std::string &url, const Args &extra = {})
{
    Args a = {DEPTHTOUCH, "play", url, "--display", "mock", "--haptic", "none"};
    a.insert(a.end(), extra.begin(), extra.end());
    return a;
}

} // namespace depthtouch::testing
