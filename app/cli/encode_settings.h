#pragma once
/// \file
/// \brief `depthtouch encode`'s command-line options and their translation into
/// media::EncodeOptions: codecs, rate control, sound, depth conversion, and the checks that need
/// the whole option set (docs/making-content.md). Private to app/cli. Thread-safety: reentrant.

#include <optional>
#include <string>

#include "depthtouch/media/encode_job.h"

namespace depthtouch::cli {

/// The options of `encode`, as its option table (cmd_encode.cpp) fills them.
struct EncodeCliOptions {
    std::string color;
    std::string depth;
    std::string output;
    bool overwrite = false;   // ffmpeg's -y: an existing output file is replaced
    bool noOverwrite = false; // ffmpeg's -n: never (the default, said explicitly)
    std::string progress;     // ffmpeg's -progress: a file, pipe:1 (stdout) or pipe:2 (stderr)
    std::string format;
    double fps = 30.0;
    int crf = 23;
    std::string preset = "medium";
    int depthCrf = 18;
    int gop = 0;
    std::string bitrate, maxrate, bufsize;                // ffmpeg's -b:v, -maxrate, -bufsize
    std::string depthBitrate, depthMaxrate, depthBufsize; // the same for depth
    std::string muxrate;                                  // ffmpeg's -muxrate (MPEG-TS)
    bool depthLossless = false;
    std::string depthCodec; ///< h264, hevc, ffv1; empty: by --depth-bits.
    int depthBits = 0;      ///< 0: the codec's own (h264 8, hevc 10, ffv1 16).
    std::string size;
    std::string renditions; ///< --renditions: heights, tallest first ("1080,720,480").
    int threads = 0;
    long long frames = 0;
    double duration = 0.0;
    double depthScale = 0.001;
    int depthSaturation = 65535;
    std::optional<double> nearM;
    std::optional<double> farM;
    std::string depthMapping = "inverse_z";
    bool enhance = false;
    bool fillHoles = false;
    bool loop = false;
    std::string realtime = "auto";
    float enhanceTolerance = 1.0f;
    std::string colorFormat, colorVideoSize, colorPixFmt;
    std::string depthFormat, depthVideoSize, depthPixFmt;
    std::string material;    ///< --material SRC: material codes (image, sequence, video).
    std::string materialMap; ///< --material-map: label image.
    std::string materials;   ///< --materials: the table of --material-map.
    std::string audio;       ///< --audio FILE: the sound's source.
    bool noAudio = false;    ///< --no-audio.
};

/// \brief Fills \a eo from \a o and checks the whole set (EncodeOptions::validate(), the output
/// path before any input is read, the x264 preset). \return kExitOk, or the exit code (2: bad
/// input) after printing the one error line on stderr.
int encodeOptionsFrom(const EncodeCliOptions &o, media::EncodeOptions &eo);

} // namespace depthtouch::cli
