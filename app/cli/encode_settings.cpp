/// \file
/// \brief `depthtouch encode`'s options into media::EncodeOptions (see encode_settings.h).

#include "encode_settings.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <system_error>
#include <sstream>
#include <string>

#include "commands.h"
#include "output_paths.h"
#include "depthtouch/media/encoder.h"
#include "depthtouch/platform/file_access.h"

namespace depthtouch::cli {

namespace {

int fail(int code, const std::string &message)
{
    std::fprintf(stderr, "depthtouch encode: %s\n", message.c_str());
    return code;
}

bool parseSize(const std::string &text, int &w, int &h)
{
    char x = 0;
    std::istringstream ss(text);
    return static_cast<bool>(ss >> w >> x >> h) && x == 'x' && ss.eof() && w > 0 && h > 0;
}

/// The bit-rate options as ffmpeg reads them into \a eo (checked together by
/// EncodeOptions::validate()). Returns kExitOk, or the exit code after printing the one error line.
int setRateOptions(const EncodeCliOptions &o, media::EncodeOptions &eo)
{
    const struct {
        const char *name;
        const std::string &text;
        long long &value;
    } rates[] = {{"--bitrate", o.bitrate, eo.colorRate.bitRate},
                 {"--maxrate", o.maxrate, eo.colorRate.maxRate},
                 {"--bufsize", o.bufsize, eo.colorRate.bufSize},
                 {"--depth-bitrate", o.depthBitrate, eo.depthRate.bitRate},
                 {"--depth-maxrate", o.depthMaxrate, eo.depthRate.maxRate},
                 {"--depth-bufsize", o.depthBufsize, eo.depthRate.bufSize},
                 {"--muxrate", o.muxrate, eo.muxRate}};
    for (const auto &r : rates) {
        if (r.text.empty())
            continue;
        const auto v = media::parseBitRate(r.text);
        if (!v)
            return fail(kExitBadInput, std::string(r.name) +
                                           " must be bits/s as ffmpeg writes them "
                                           "(500k, 4M, 2.5M; 1k or more)");
        r.value = *v;
    }
    eo.gop = o.gop;
    return kExitOk;
}

/// --renditions: comma-separated heights in pixels (their order and range are
/// EncodeOptions::validate()'s).
int setRenditions(const EncodeCliOptions &o, media::EncodeOptions &eo)
{
    std::size_t at = 0;
    while (at < o.renditions.size()) {
        const std::size_t comma = std::min(o.renditions.find(',', at), o.renditions.size());
        const std::string item = o.renditions.substr(at, comma - at);
        char *end = nullptr;
        const long h = std::strtol(item.c_str(), &end, 10);
        if (item.empty() || *end != '\0' || h <= 0 || h > 100000)
            return fail(kExitBadInput, "--renditions must be heights in pixels, tallest first "
                                       "(1080,720,480): '" +
                                           item + "' is not one");
        eo.renditions.push_back(static_cast<int>(h));
        at = comma + 1;
    }
    return kExitOk;
}

/// The sound: --audio's file, else the color input when it is a regular file (its first audio
/// stream, if any); none with --no-audio or --loop (the sound would end after one pass).
int setAudioOptions(const EncodeCliOptions &o, media::EncodeOptions &eo)
{
    std::error_code ec;
    if (o.audio.empty()) {
        if (!o.noAudio && !o.loop && std::filesystem::is_regular_file(o.color, ec)) {
            eo.audioSource = o.color;
            eo.audioFromPicture = true;
        }
        return kExitOk;
    }
    if (o.noAudio || o.loop)
        return fail(kExitBadInput, "--audio excludes --no-audio and --loop");
    if (!std::filesystem::is_regular_file(o.audio, ec))
        return fail(kExitBadInput, "--audio must name a file: '" + o.audio + "' is not one");
    eo.audioSource = o.audio;
    eo.audioFromPicture = o.audio == o.color;
    eo.audioRequired = true;
    return kExitOk;
}

/// The depth codec of --depth-codec and --depth-bits (each alone picks the other's default:
/// h264 8, hevc 10, ffv1 16; 16 bits alone: ffv1). Returns kExitOk, or the exit code after
/// printing the one error line.
int setDepthCodec(const EncodeCliOptions &o, media::EncodeOptions &eo)
{
    const std::string codec =
        !o.depthCodec.empty() ? o.depthCodec : (o.depthBits == 16 ? "ffv1" : "h264");
    const int bits = o.depthBits != 0 ? o.depthBits
                                      : (codec == "hevc"   ? 10
                                         : codec == "ffv1" ? 16
                                                           : 8);
    if (codec == "h264" && bits == 8)
        eo.depthCodec = media::VideoCodec::H264Gray;
    else if (codec == "h264" && bits == 10)
        eo.depthCodec = media::VideoCodec::H264Gray10;
    else if (codec == "hevc" && bits == 10)
        eo.depthCodec = media::VideoCodec::HevcMain10;
    else if (codec == "ffv1" && bits == 16)
        eo.depthCodec = media::VideoCodec::Ffv1Gray16;
    else
        return fail(kExitBadInput, "--depth-bits must be 8 or 10 with --depth-codec h264, 10 with "
                                   "hevc, 16 with ffv1, not " +
                                       std::to_string(o.depthBits) + " with " + codec);
    return kExitOk;
}

/// The output, container, color encoder, depth codec, grid and limits. Returns kExitOk, or the exit
/// code after printing the one error line.
int setOutputOptions(const EncodeCliOptions &o, media::EncodeOptions &eo)
{
    eo.output = o.output;
    if (!o.format.empty()) {
        auto c = media::parseContainer(o.format);
        if (!c)
            return fail(kExitBadInput, "--format must be mkv, mp4, ts or hls");
        eo.container = *c;
    }
    eo.crf = o.crf;
    eo.preset = o.preset;
    eo.depthCrf = o.depthCrf;
    eo.depthLossless = o.depthLossless;
    if (const int rc = setDepthCodec(o, eo); rc != kExitOk)
        return rc;
    if (!o.size.empty() && !parseSize(o.size, eo.width, eo.height))
        return fail(kExitBadInput, "--size must be WxH (pixels)");
    eo.threads = o.threads;
    eo.maxFrames = o.frames;
    eo.maxDuration = o.duration;
    // A live output (a URL, an endless loop) leaves at the media rate, a file as fast as it can.
    eo.paced =
        o.realtime == "on" || (o.realtime == "auto" && (media::isOutputUrl(o.output) || o.loop));
    if (const int rc = setAudioOptions(o, eo); rc != kExitOk)
        return rc;
    return setRateOptions(o, eo);
}

/// The raw depth conversion, the nearness mapping and range, and the enhancement. Returns kExitOk,
/// or the exit code after printing the one error line.
int setDepthOptions(const EncodeCliOptions &o, media::EncodeOptions &eo)
{
    eo.raw.metresPerUnit = o.depthScale;
    if (o.depthSaturation < 1 || o.depthSaturation > 65535)
        return fail(kExitBadInput, "--depth-saturation must be in 1..65535");
    eo.raw.saturation = static_cast<std::uint16_t>(o.depthSaturation);
    auto mapping = depth::parseMapping(o.depthMapping);
    if (!mapping)
        return fail(kExitBadInput, "--depth-mapping must be inverse_z or linear");
    eo.mapping = *mapping;
    if (o.nearM.has_value() != o.farM.has_value())
        return fail(kExitBadInput, "--near and --far go together");
    if (o.nearM)
        eo.range = depth::DepthRange{*o.nearM, *o.farM};
    eo.enhance = o.enhance;
    eo.fillHoles = o.fillHoles;
    eo.enhanceOptions.sampling.tolerance = o.enhanceTolerance;
    return kExitOk;
}

/// A raw video input (--X-format rawvideo, or a .yuv file, which ffmpeg takes as raw video)
/// has no header to say its frame size: without --X-video-size it cannot be opened (ffmpeg said
/// only "Invalid argument"). Returns kExitOk, or kExitBadInput after the error line.
int checkRawInput(const char *which, const std::string &path, const std::string &format,
                  const std::string &videoSize)
{
    const std::string ext = std::filesystem::path(path).extension().string();
    const bool raw = format == "rawvideo" || (format.empty() && ext == ".yuv");
    if (!raw || !videoSize.empty())
        return kExitOk;
    return fail(kExitBadInput, std::string("the raw video of --") + which + " '" + path +
                                   "' needs --" + which + "-video-size WxH and --" + which +
                                   "-pix-fmt (a raw frame has no header to say them)");
}

/// ffmpeg's -y and -n: an output that is an existing regular file is replaced only with -y (a
/// device or a FIFO is written into, not replaced). Returns kExitOk, or kExitBadInput after the
/// error line.
int checkOverwrite(const EncodeCliOptions &o)
{
    std::error_code ec;
    if (o.overwrite || !std::filesystem::is_regular_file(o.output, ec))
        return kExitOk;
    return fail(kExitBadInput, "'" + o.output +
                                   "' exists: -y replaces it (ffmpeg's -y); without -y (or with "
                                   "-n) encode never does");
}

/// The checks that need the whole option set: frame rate, the options' own validation, the output
/// path (before any input is read) and the x264 preset. Returns kExitOk, or the exit code after
/// printing the one error line.
int checkEncodeOptions(const EncodeCliOptions &o, const media::EncodeOptions &eo)
{
    if (!(o.fps >= media::kMinEncodeFps) || o.fps > media::kMaxEncodeFps)
        return fail(kExitBadInput, "--fps must be in 0.1..1000 frames/s");
    if (auto v = eo.validate(); !v)
        return fail(kExitBadInput, v.error().what);
    if (!media::isOutputUrl(o.output)) {
        // Before any input is read: what planOutput() refuses, and an output that is an input.
        if (auto p = platform::planOutput(o.output); !p)
            return fail(kExitBadInput, "cannot write '" + o.output + "': it " + p.error().what);
        const platform::OutputPathCheck same =
            platform::checkDistinctPaths({{"--color", o.color},
                                          {"--depth", o.depth},
                                          {"--material", o.material},
                                          {"--material-map", o.materialMap},
                                          {"--materials", o.materials},
                                          {"--audio", o.audio}},
                                         {{"-o", o.output}});
        if (same.exitCode != kExitOk)
            return fail(same.exitCode, same.message);
        if (int rc = checkOverwrite(o); rc != kExitOk)
            return rc;
    }
    if (o.overwrite && o.noOverwrite)
        return fail(kExitBadInput, "-y and -n exclude each other");
    if (int rc = checkRawInput("color", o.color, o.colorFormat, o.colorVideoSize); rc != kExitOk)
        return rc;
    if (int rc = checkRawInput("depth", o.depth, o.depthFormat, o.depthVideoSize); rc != kExitOk)
        return rc;
    static constexpr const char *kPresets[] = {"ultrafast", "superfast", "veryfast", "faster",
                                               "fast",      "medium",    "slow",     "slower",
                                               "veryslow",  "placebo"};
    bool presetOk = false;
    for (const char *p : kPresets)
        presetOk = presetOk || o.preset == p;
    if (!presetOk)
        return fail(kExitBadInput, "--preset must be an x264 preset (ultrafast ... veryslow)");
    return kExitOk;
}

} // namespace

int encodeOptionsFrom(const EncodeCliOptions &o, media::EncodeOptions &eo)
{
    if (const int rc = setOutputOptions(o, eo); rc != kExitOk)
        return rc;
    if (const int rc = setDepthOptions(o, eo); rc != kExitOk)
        return rc;
    if (const int rc = setRenditions(o, eo); rc != kExitOk)
        return rc;
    return checkEncodeOptions(o, eo);
}

} // namespace depthtouch::cli
