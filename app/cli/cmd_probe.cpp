/// \file
/// \brief `depthtouch probe FILE`: what a 3D video holds and whether its color and depth frames
/// pair (docs/architecture.md §4): the streams, the depth metadata, which stream plays which role
/// and why, and how many color frames lack a depth partner. Demux only by default (packet PTS,
/// fast); with
/// --decode it runs the receiver (decode + pairing) and reports its counters too. A material track
/// (docs/materials.md) is shown with its role, lossless or not and the value ranges of its first
/// frame (decoded with libavcodec; regular files only: a FIFO or URL cannot be read twice).

#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "commands.h"
#include "option_cli.h"
#include "depthtouch/drivers/backends.h"
#include "depthtouch/media/material_track.h"
#include "depthtouch/platform/file_access.h"
#include "depthtouch/platform/log.h"
#include "depthtouch/probe/probe_report.h"
#include "depthtouch/receiver/receiver.h"

namespace depthtouch::cli {

namespace {

struct ProbeOptions {
    std::string file;
    bool json = false;
    bool decode = false;
    std::string source;        ///< Media source backend; empty: mock for mock: URLs, else ffmpeg.
    std::string sourceOptions; ///< The source's options (K=V,..), as play's --source-options.
    std::string decoder;       ///< Decoder backend for --decode; empty: matches the source.
};

/// What `probe` does (its line in `depthtouch --help`).
constexpr const char *kAbout =
    "Show the streams, depth metadata and color/depth pairing of a 3D video";

/// The options of `probe`, in `--help` order.
const OptionRow<ProbeOptions> kProbeRows[] = {
    {"file", &ProbeOptions::file, "Video file or stream URL", {}, kPositional | kRequired},
    {"json", &ProbeOptions::json, "Print JSON instead of text"},
    {"decode", &ProbeOptions::decode,
     "Also decode and pair every frame (concealed frames, decode errors)"},
    {"source", &ProbeOptions::source,
     "Media source backend (default: ffmpeg; mock for mock: URLs)"},
    {"source-options", &ProbeOptions::sourceOptions,
     "Options of the media source, as play's (e.g. rendition=480 for an HLS ladder)"},
    {"decoder", &ProbeOptions::decoder, "Video decoder backend for --decode (default: ffmpeg)"},
};

/// --decode reads the input twice (demux census, then the receiver): a FIFO cannot be. Prints why
/// and returns false for a FIFO under --decode.
bool decodeInputReadable(const ProbeOptions &opt)
{
    if (opt.decode && platform::pathKind(opt.file.c_str()) == platform::PathKind::Fifo) {
        std::fprintf(stderr,
                     "depthtouch probe: cannot --decode '%s': it is a FIFO, which can be "
                     "read only once (probe it without --decode, or save it to a file)\n",
                     opt.file.c_str());
        return false;
    }
    return true;
}

/// The --decode pass: runs the real receiver (decode + pairing) over the whole input and keeps its
/// counters in the report. Returns kExitOk, or kExitBadInput after printing why it could not run.
int runDecodePass(const ProbeOptions &opt, const std::string &sourceName, bool mockUrl,
                  const hal::BackendConfig &cfg, probe::ProbeReport &rep)
{
    auto src2 = drivers::createMediaSource(sourceName, cfg);
    const std::string decName = !opt.decoder.empty() ? opt.decoder : mockUrl ? "mock" : "ffmpeg";
    receiver::DecoderFactory factory = [&decName](const hal::StreamInfo &) {
        return drivers::createVideoDecoder(decName, hal::BackendConfig{});
    };
    if (!src2) {
        std::fprintf(stderr, "depthtouch probe: no media source '%s'\n", sourceName.c_str());
        return kExitBadInput;
    }
    auto r = receiver::Receiver::open(std::move(*src2), opt.file.c_str(), factory);
    if (!r) {
        std::fprintf(stderr, "depthtouch probe: cannot decode '%s': %s (%s)\n", opt.file.c_str(),
                     r.error().what, errcName(r.error().code));
        return kExitBadInput;
    }
    probe::addDecodePass(rep, **r);
    return kExitOk;
}

int runProbe(const ProbeOptions &opt)
{
    // Library warnings and errors would interleave with the report, or add a second line to a
    // refusal: the report and the one error line say what matters.
    platform::setLogLevel(platform::LogLevel::Off);
    const bool mockUrl = opt.file.rfind("mock:", 0) == 0;
    const std::string sourceName = !opt.source.empty() ? opt.source : mockUrl ? "mock" : "ffmpeg";
    if (!decodeInputReadable(opt))
        return kExitBadInput;
    hal::BackendConfig cfg;
    cfg.options = hal::OptionList(opt.sourceOptions);
    auto src = drivers::createMediaSource(sourceName, cfg);
    if (!src) {
        std::fprintf(stderr, "depthtouch probe: no media source '%s': %s\n", sourceName.c_str(),
                     src.error().what);
        return kExitBadInput;
    }
    if (auto r = (*src)->open(opt.file.c_str()); !r) {
        std::fprintf(stderr, "depthtouch probe: cannot read '%s': %s (%s)\n", opt.file.c_str(),
                     r.error().what, errcName(r.error().code));
        return kExitBadInput;
    }
    probe::ProbeReport rep = probe::census(**src);
    // The material track: read once more through libavformat (a regular file only).
    if (!mockUrl && platform::pathKind(opt.file.c_str()) == platform::PathKind::Regular) {
        if (auto m = media::probeMaterialStream(opt.file))
            rep.material = *m;
    }

    // Optional: the real receiver (decode + pairing).
    if (opt.decode) {
        if (const int rc = runDecodePass(opt, sourceName, mockUrl, cfg, rep); rc != kExitOk)
            return rc;
    }
    if (opt.json)
        std::printf("%s\n", probe::reportJson(rep, opt.file, opt.decode).dump(2).c_str());
    else
        probe::printReportText(stdout, rep, opt.file, opt.decode);
    return kExitOk;
}

} // namespace

void registerProbeCommand(CLI::App &app, int &exitCode)
{
    addTableCommand<ProbeOptions>(app, "probe", kAbout, kProbeRows, runProbe, exitCode);
}

} // namespace depthtouch::cli
