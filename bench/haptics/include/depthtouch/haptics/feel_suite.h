#pragma once
/// \file
/// \brief `depthtouch bench feel`'s run: the scenes it touches (every capture of the shared RGB-D
/// data found, holes kept as the receiver sees them, 8- and 16-bit; the synthetic scenes seen
/// through the sensor models; the depth of any --clip), the stroke families placed on each, the
/// settings of the renderers asked for, and their replay on a timing thread (feel_bench.h). The
/// clips are read with the media frame source (FFmpeg), the captures' PNGs with the image reader.
/// Progress goes to stderr, the scene lines and notes to stdout. Units: s, m (feel_scenes.h).
/// Thread-safety: call from one thread; runFeelSuite() starts and joins its own timing thread.

#include <optional>
#include <string>
#include <vector>

#include "depthtouch/haptics/feel_bench.h"
#include "depthtouch/haptics/feel_scenes.h"
#include "depthtouch/haptics/renderer.h"

namespace depthtouch::haptics::bench {

/// \brief What `bench feel` runs on and how (its command-line options).
struct FeelSuiteOptions {
    std::string data; ///< Folder of the shared captures; empty: defaultSharedDataDir().
    std::vector<std::string> clips; ///< Depth videos or DepthTouch files also touched.
    bool quick = false; ///< 8-bit only, fewer synthetic scenes and strokes, first settings only.
    bool fifo = true;   ///< Time on a SCHED_FIFO thread at the haptic priority.
    std::string dump;   ///< Per-update logs of the strokes whose 'scene|setting|stroke' has it.
    /// Only the scenes whose name (e.g. "bonn-crowd/16", a --clip's file name) contains one of
    /// these; empty: every scene.
    std::vector<std::string> scenes;
    /// Only the settings with these names (FeelSetting::name: "finger", "finger-ramp", ...;
    /// feelSettings()), `quick` or not; empty: every setting of the methods (with `quick`, each
    /// one's first).
    std::vector<std::string> settings;
    /// The dumped rows also carry the ideal ball's force (ball_ideal.h: up to 10⁵ lookups an
    /// update, seconds a stroke); without it those columns read nan and a dump of every stroke
    /// costs what the run does.
    bool dumpBallIdeal = false;
};

/// \return the first name in \a o.settings that is not a setting of \a methods (feelSettings()),
/// with the names there are in \a known (comma-separated); empty when every name is one.
std::string unknownFeelSetting(const FeelSuiteOptions &o, const std::vector<Method> &methods,
                               std::string &known);

/// \brief Why the suite stopped: the one-line message, and whether the input was bad (a --clip
/// whose depth cannot be read) rather than the run failing.
struct FeelSuiteError {
    bool badInput = false;
    std::string message;
};

/// \return $DT_SHARED_DATA when set and not empty, else "../shared/data".
std::string defaultSharedDataDir();

/// \brief Gathers the scenes into \a scenes: every capture found in the shared data (a missing
/// one is a note on stdout), the synthetic ones, the clips (at most 10 s each); and the clean
/// synthetic scenes of the accuracy figure into \a clean.
/// With FeelSuiteOptions::scenes, only the scenes it names (a capture or a synthetic scene not
/// named is not read or rendered).
/// \return nothing, or why not (a capture, a synthetic scene or a clip that cannot be read; no
/// scene left by FeelSuiteOptions::scenes, bad input).
std::optional<FeelSuiteError> loadFeelScenes(const FeelSuiteOptions &o,
                                             std::vector<FeelScene> &scenes,
                                             std::vector<FeelScene> &clean);

/// \brief Places the stroke families on \a scenes (a line per scene on stdout), plans the settings
/// of \a methods and replays every stroke with every setting on the timing thread (its scheduling
/// printed), into \a report. \return nothing, or why not (the thread could not start).
std::optional<FeelSuiteError> runFeelSuite(const FeelSuiteOptions &o,
                                           const std::vector<Method> &methods,
                                           const std::vector<FeelScene> &scenes,
                                           const std::vector<FeelScene> &clean, FeelReport &report);

} // namespace depthtouch::haptics::bench
