#pragma once
/// \file
/// \brief The steps the media benchmark's measurements share, private to dt_media_bench: encode a
/// clip into one MKV, decode a file through the receiver, view decoded depth as haptic frames,
/// replay a stroke on them and count pop-throughs, temporary files and the report's text cells.
/// Thread-safety: stateless functions. Not real-time safe.

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "depthtouch/haptics/depth_frame.h"
#include "depthtouch/haptics/replay.h"
#include "depthtouch/media/encoder.h"
#include "depthtouch/media/media_bench.h"
#include "depthtouch/platform/report_file.h"
#include "depthtouch/platform/result.h"
#include "depthtouch/receiver/receiver.h"

namespace depthtouch::media::bench {

/// \return the bit rate (kbit/s) of \a bytes over \a frames frames at \a fps.
double kbps(long long bytes, std::size_t frames, double fps);

/// One encode: color (optional) and depth of every clip frame into one MKV.
struct EncodeSetting {
    std::string preset;
    /// H264Gray (the clip's 8-bit nearness), H264Gray10 or HevcMain10 (its 16-bit nearness
    /// rounded to 10 bits), Ffv1Gray16 (its 16-bit nearness).
    VideoCodec depthCodec = VideoCodec::H264Gray;
    bool withColor = true;
    int colorCrf = 23;
    int depthCrf = 18;
    bool depthLossless = false;
    int threads = 1;
};

struct Encoded {
    long long colorBytes = 0;
    long long depthBytes = 0;
    double seconds = 0.0;    ///< First encode() to the muxer's finish(), flush included.
    double cpuSeconds = 0.0; ///< Process CPU time of the same.
};

/// \return the sizes and times of encoding every frame of \a clip with \a s into \a path.
Result<Encoded> encodeClip(const Clip &clip, const std::string &path, const EncodeSetting &s);

/// \return encodeClip() of the depth alone: \a codec at \a crf (or lossless) with \a preset.
Result<Encoded> encodeDepthOnly(const Clip &clip, const std::string &path,
                                const std::string &preset, VideoCodec codec, int crf, bool lossless,
                                int threads);

/// \return the replay of the paper's renderer (modified proxy graph, section IV) at the options'
/// haptic rate (Hz) in \a box (m).
haptics::ReplayOptions paperReplay(const MediaBenchOptions &options, const scene::SceneBox &box);

/// One pass of the receiver over a file.
struct Decoded {
    std::vector<double> frameSeconds; ///< Time of each next() that gave a paired frame.
    double seconds = 0.0;             ///< Their sum.
    double cpuSeconds = 0.0;          ///< Process CPU time of the same calls.
    receiver::ReceiverStats stats;
    std::vector<std::uint8_t> depth; ///< Depth frames back to back (when captured), W×H each.
    scene::SampleFormat depthFormat = scene::SampleFormat::Gray8; ///< Of the captured frames.
};

/// \return the times of one receiver pass over \a path; with \a capture, the depth frames as
/// well (\a width × \a height, Gray8 or Gray16 as decoded, the same for every frame).
/// \a depthOnly plays the depth stream alone.
Result<Decoded> decodeFile(const std::string &path, const ReceiverBackends &backends,
                           bool depthOnly, bool capture, int width, int height);

/// Views of W×H frames of \a format stored back to back, PTS i/fps.
std::vector<scene::DepthFrameView> viewsOf(const std::vector<std::uint8_t> &video, int width,
                                           int height, double fps,
                                           scene::SampleFormat format = scene::SampleFormat::Gray8);

/// Index of the frame shown at haptic time \a t (s from the first PTS), as replay() picks it.
std::size_t frameAt(const std::vector<scene::DepthFrameView> &frames, double t);

/// Updates of \a rows whose proxy ended below the surface the renderer saw (frames i, i+1
/// interpolated, paper Eq. 1) by more than a millionth of the sample spacing; -1 when a frame
/// pair cannot be set.
long countPopThroughs(const std::vector<scene::DepthFrameView> &frames,
                      const std::vector<haptics::ForceLogRow> &rows, const scene::SceneBox &box);

/// \return the force log of replaying \a stroke on the W×H frames of \a video (no copy).
Result<std::vector<haptics::ForceLogRow>>
replayOn(const std::vector<std::uint8_t> &video, int width, int height, double fps,
         const std::vector<haptics::TrajectorySample> &stroke,
         const haptics::ReplayOptions &options,
         scene::SampleFormat format = scene::SampleFormat::Gray8);

/// \return the path of temporary file \a name in the options' work folder.
std::string tempName(const MediaBenchOptions &o, const std::string &name);

/// Removes \a path unless the options keep the files.
void removeUnlessKept(const MediaBenchOptions &o, const std::string &path);

/// \return "WxH".
std::string sizeText(int w, int h);

/// \return \a db with two decimals, or "inf".
std::string psnrText(double db);

/// \return "lossless" or "crfN" for the depth setting of \a r.
std::string settingText(const RateRow &r);

/// Closes \a f, the report file at \a path. \return false with \a error "cannot write PATH" when
/// it was not written whole.
bool closeReport(platform::ReportFile &f, const std::string &path, std::string &error);

/// Closes the gnuplot script \a g at \a script (closeReport()) and runs it; \a note: how the
/// charts went (platform::plotStatusNote()). \return false with \a error when the script was not
/// written.
bool closeAndPlot(platform::ReportFile &g, const std::string &script, std::string &error,
                  std::string &note);

} // namespace depthtouch::media::bench
