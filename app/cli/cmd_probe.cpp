/// \file
/// \brief `depthtouch probe FILE`: what a 3D video holds and whether its color and depth frames
/// pair (DESIGN §4): the streams, the depth metadata, which stream plays which role and why, and
/// how many color frames lack a depth partner. Demux only by default (packet PTS, fast); with
/// --decode it runs the receiver (decode + pairing) and reports its counters too.

#include <algorithm>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "option_cli.h"
#include "depthtouch/drivers/backends.h"
#include "depthtouch/platform/file_access.h"
#include "depthtouch/platform/log.h"
#include "depthtouch/receiver/pts_pairer.h"
#include "depthtouch/receiver/receiver.h"
#include "depthtouch/receiver/stream_roles.h"

namespace depthtouch::cli {

namespace {

struct ProbeOptions {
    std::string file;
    bool json = false;
    bool decode = false;
    std::string source;  ///< Media source backend; empty: mock for mock: URLs, else ffmpeg.
    std::string decoder; ///< Decoder backend for --decode; empty: matches the source.
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
    {"decoder", &ProbeOptions::decoder, "Video decoder backend for --decode (default: ffmpeg)"},
};

/// Per-stream packet census of the demux pass.
struct StreamCount {
    std::uint64_t packets = 0;
    std::uint64_t keyframes = 0;
    std::vector<hal::Pts> pts;
};

struct PairingCensus {
    receiver::PairerStats stats;
    std::uint64_t colorFrames = 0;
    std::uint64_t colorWithPartner = 0;
};

hal::Pts periodOf(const hal::Rational &r)
{
    return r.num > 0 && r.den > 0
               ? hal::Pts(static_cast<std::int64_t>(1e9 * static_cast<double>(r.den) / r.num + 0.5))
               : hal::Pts{0};
}

/// Runs the pairing rules on the streams' packet PTS (presentation order = sorted).
PairingCensus pairPackets(const hal::MediaInfo &info, const receiver::StreamRoles &roles,
                          std::vector<StreamCount> &counts)
{
    PairingCensus out;
    receiver::PairerConfig pc;
    pc.color = roles.color >= 0;
    pc.depth = roles.depth >= 0;
    if (!pc.color && !pc.depth)
        return out;
    hal::Pts cp = pc.color ? periodOf(info.streams[static_cast<std::size_t>(roles.color)].frameRate)
                           : hal::Pts{0};
    hal::Pts dp = pc.depth ? periodOf(info.streams[static_cast<std::size_t>(roles.depth)].frameRate)
                           : hal::Pts{0};
    if (cp <= hal::Pts{0})
        cp = dp > hal::Pts{0} ? dp : hal::Pts(33'333'333);
    if (dp <= hal::Pts{0})
        dp = cp;
    pc.colorPeriod = cp;
    pc.depthPeriod = dp;
    receiver::PtsPairer<int> pairer(pc);
    std::vector<hal::Pts> empty;
    std::vector<hal::Pts> &c = pc.color ? counts[static_cast<std::size_t>(roles.color)].pts : empty;
    std::vector<hal::Pts> &d = pc.depth ? counts[static_cast<std::size_t>(roles.depth)].pts : empty;
    std::sort(c.begin(), c.end());
    std::sort(d.begin(), d.end());
    std::size_t ci = 0;
    std::size_t di = 0;
    receiver::PtsPairer<int>::Output o;
    const auto drainOutputs = [&] {
        while (pairer.pull(o)) {
            if (o.hasColor) {
                ++out.colorFrames;
                if (!o.depthMissing && !o.depthDuplicated && o.hasDepth)
                    ++out.colorWithPartner;
            }
        }
    };
    while (ci < c.size() || di < d.size()) {
        const bool color = di >= d.size() || (ci < c.size() && c[ci] <= d[di]);
        receiver::PtsPairer<int>::Item item;
        item.pts = color ? c[ci++] : d[di++];
        (void)pairer.push(color ? receiver::PairStream::Color : receiver::PairStream::Depth,
                          std::move(item));
        drainOutputs();
    }
    pairer.endOfStream(receiver::PairStream::Color);
    pairer.endOfStream(receiver::PairStream::Depth);
    drainOutputs();
    out.stats = pairer.stats();
    return out;
}

std::string rateText(const hal::Rational &r)
{
    if (r.num <= 0 || r.den <= 0)
        return "unknown";
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3g", r.toDouble());
    return buf;
}

int runProbe(const ProbeOptions &opt)
{
    // Library warnings would interleave with the report; the report says what matters.
    platform::setLogLevel(platform::LogLevel::Error);
    const bool mockUrl = opt.file.rfind("mock:", 0) == 0;
    const std::string sourceName = !opt.source.empty() ? opt.source : mockUrl ? "mock" : "ffmpeg";
    if (opt.decode && platform::pathKind(opt.file.c_str()) == platform::PathKind::Fifo) {
        // --decode reads the input twice (demux census, then the receiver): a FIFO cannot be.
        std::fprintf(stderr,
                     "depthtouch probe: cannot --decode '%s': it is a FIFO, which can be "
                     "read only once (probe it without --decode, or save it to a file)\n",
                     opt.file.c_str());
        return kExitBadInput;
    }
    hal::BackendConfig cfg;
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
    const hal::MediaInfo info = (*src)->info();
    const receiver::StreamRoles roles = receiver::identifyStreams(info);

    std::vector<StreamCount> counts(info.streams.size());
    std::uint64_t packets = 0;
    std::string readError;
    for (;;) {
        auto p = (*src)->readPacket();
        if (!p) {
            if (p.error().code != Errc::EndOfStream)
                readError = p.error().what;
            break;
        }
        ++packets;
        if (p->streamIndex < 0 || static_cast<std::size_t>(p->streamIndex) >= counts.size())
            continue;
        StreamCount &sc = counts[static_cast<std::size_t>(p->streamIndex)];
        ++sc.packets;
        sc.keyframes += p->keyframe ? 1u : 0u;
        sc.pts.push_back(p->pts);
    }
    (*src)->close();
    std::vector<hal::Pts> spans(counts.size(), hal::Pts{0});
    for (std::size_t i = 0; i < counts.size(); ++i) {
        const auto &v = counts[i].pts;
        if (!v.empty()) {
            const auto [lo, hi] = std::minmax_element(v.begin(), v.end());
            spans[i] = *hi - *lo + periodOf(info.streams[i].frameRate);
        }
    }
    const PairingCensus census = pairPackets(info, roles, counts);
    const std::uint64_t unpairedColor = census.colorFrames - census.colorWithPartner;
    const bool everyPaired = roles.color >= 0 && roles.depth >= 0 && unpairedColor == 0;

    // Optional: the real receiver (decode + pairing).
    nlohmann::json decodeJson;
    std::string decodeText;
    if (opt.decode) {
        auto src2 = drivers::createMediaSource(sourceName, cfg);
        const std::string decName = !opt.decoder.empty() ? opt.decoder
                                    : mockUrl            ? "mock"
                                                         : "ffmpeg";
        receiver::DecoderFactory factory = [&decName](const hal::StreamInfo &) {
            return drivers::createVideoDecoder(decName, hal::BackendConfig{});
        };
        if (!src2) {
            std::fprintf(stderr, "depthtouch probe: no media source '%s'\n", sourceName.c_str());
            return kExitBadInput;
        }
        auto r = receiver::Receiver::open(std::move(*src2), opt.file.c_str(), factory);
        if (!r) {
            std::fprintf(stderr, "depthtouch probe: cannot decode '%s': %s (%s)\n",
                         opt.file.c_str(), r.error().what, errcName(r.error().code));
            return kExitBadInput;
        }
        receiver::PairedFrame f;
        for (;;) {
            auto n = (*r)->next(f);
            if (!n || !*n)
                break;
        }
        f = receiver::PairedFrame{};
        const receiver::ReceiverStats s = (*r)->stats();
        decodeJson = {{"mode", receiver::receiverModeName((*r)->info().mode)},
                      {"color_frames", s.colorFrames},
                      {"depth_frames", s.depthFrames},
                      {"paired_frames", s.framesOutput},
                      {"concealed", s.framesConcealed},
                      {"decode_errors", s.decodeErrors},
                      {"depth_missing", s.depthMissing},
                      {"depth_duplicated", s.depthDuplicated},
                      {"depth_unpaired", s.depthUnpaired},
                      {"pts_gaps", s.ptsGaps},
                      {"pts_duplicates", s.ptsDuplicates},
                      {"pts_non_monotonic", s.ptsNonMonotonic},
                      {"read_errors", s.readErrors}};
        char line[512];
        std::snprintf(
            line, sizeof line,
            "decode (%s): %llu color + %llu depth frames -> %llu paired; %llu concealed, "
            "%llu decode errors, %llu without depth, %llu reused depth, %llu read errors\n",
            receiver::receiverModeName((*r)->info().mode),
            static_cast<unsigned long long>(s.colorFrames),
            static_cast<unsigned long long>(s.depthFrames),
            static_cast<unsigned long long>(s.framesOutput),
            static_cast<unsigned long long>(s.framesConcealed),
            static_cast<unsigned long long>(s.decodeErrors),
            static_cast<unsigned long long>(s.depthMissing),
            static_cast<unsigned long long>(s.depthDuplicated),
            static_cast<unsigned long long>(s.readErrors));
        decodeText = line;
    }

    const auto roleOf = [&](int index) -> std::string {
        if (index == roles.color)
            return std::string("color (") + roles.colorReason + ")";
        if (index == roles.depth)
            return std::string("depth (") + roles.depthReason + ")";
        return "ignored";
    };
    const hal::StreamInfo *depth =
        roles.depth >= 0 ? &info.streams[static_cast<std::size_t>(roles.depth)] : nullptr;

    if (opt.json) {
        nlohmann::json j;
        j["file"] = opt.file;
        j["duration_s"] = platform::toSeconds(info.duration);
        j["packets"] = packets;
        j["read_error"] = readError.empty() ? nlohmann::json(nullptr) : nlohmann::json(readError);
        nlohmann::json streams = nlohmann::json::array();
        for (const hal::StreamInfo &s : info.streams) {
            const StreamCount &c = counts[static_cast<std::size_t>(s.index)];
            streams.push_back(
                {{"index", s.index},
                 {"title", s.title},
                 {"role", roleOf(s.index)},
                 {"codec", hal::codecName(s.codec)},
                 {"width", s.width},
                 {"height", s.height},
                 {"pix_fmt", hal::pixelFormatName(s.format)},
                 {"frame_rate", s.frameRate.toDouble()},
                 {"frames", c.packets},
                 {"keyframes", c.keyframes},
                 {"duration_s", platform::toSeconds(spans[static_cast<std::size_t>(s.index)])}});
        }
        j["streams"] = streams;
        if (depth != nullptr)
            j["depth_metadata"] = {{"near_m", depth->depth.nearMetres},
                                   {"far_m", depth->depth.farMetres},
                                   {"mapping", depth->depth.mapping},
                                   {"bits", depth->depth.bits}};
        else
            j["depth_metadata"] = nullptr;
        j["pairing"] = {{"color_frames", census.colorFrames},
                        {"color_with_depth_partner", census.colorWithPartner},
                        {"color_without_depth_partner", unpairedColor},
                        {"depth_reused", census.stats.depthDuplicated},
                        {"depth_missing", census.stats.depthMissing},
                        {"depth_unpaired", census.stats.depthUnpaired},
                        {"pts_gaps", census.stats.ptsGaps},
                        {"pts_duplicates", census.stats.ptsDuplicates},
                        {"every_color_frame_paired", everyPaired}};
        j["notes"] = roles.notes;
        if (opt.decode)
            j["decode"] = decodeJson;
        std::printf("%s\n", j.dump(2).c_str());
        return kExitOk;
    }

    std::printf("%s: %zu video stream%s, %.3f s\n", opt.file.c_str(), info.streams.size(),
                info.streams.size() == 1 ? "" : "s", platform::toSeconds(info.duration));
    for (const hal::StreamInfo &s : info.streams) {
        const StreamCount &c = counts[static_cast<std::size_t>(s.index)];
        std::printf("  #%d %-8s %-26s %-6s %dx%d %-8s %s fps, %llu frames (%.3f s)\n", s.index,
                    s.title.empty() ? "-" : s.title.c_str(), roleOf(s.index).c_str(),
                    hal::codecName(s.codec), s.width, s.height, hal::pixelFormatName(s.format),
                    rateText(s.frameRate).c_str(), static_cast<unsigned long long>(c.packets),
                    platform::toSeconds(spans[static_cast<std::size_t>(s.index)]));
    }
    if (depth != nullptr) {
        const hal::DepthMetadata &m = depth->depth;
        if (receiver::hasDepthMetadata(m))
            std::printf("depth metadata: near %g m, far %g m, mapping %s, %d bits\n", m.nearMetres,
                        m.farMetres, m.mapping.empty() ? "-" : m.mapping.c_str(), m.bits);
        else
            std::printf("depth metadata: none\n");
    }
    if (roles.color >= 0 && roles.depth >= 0)
        std::printf("pairing: %llu of %llu color frames have a depth partner within half a frame "
                    "(%llu without: %llu reuse the previous depth frame, %llu have none); %llu "
                    "depth frames unpaired; %s\n",
                    static_cast<unsigned long long>(census.colorWithPartner),
                    static_cast<unsigned long long>(census.colorFrames),
                    static_cast<unsigned long long>(unpairedColor),
                    static_cast<unsigned long long>(census.stats.depthDuplicated),
                    static_cast<unsigned long long>(census.stats.depthMissing),
                    static_cast<unsigned long long>(census.stats.depthUnpaired),
                    everyPaired ? "every color frame is paired"
                                : "NOT every color frame is paired");
    else if (roles.depth >= 0)
        std::printf(
            "pairing: no color stream (depth only, %llu frames)\n",
            static_cast<unsigned long long>(counts[static_cast<std::size_t>(roles.depth)].packets));
    else
        std::printf("pairing: no depth stream (color only: plays flat 2D, haptics off)\n");
    if (census.stats.ptsGaps + census.stats.ptsDuplicates > 0)
        std::printf("timestamps: %llu gaps, %llu duplicates\n",
                    static_cast<unsigned long long>(census.stats.ptsGaps),
                    static_cast<unsigned long long>(census.stats.ptsDuplicates));
    for (const std::string &n : roles.notes)
        std::printf("note: %s\n", n.c_str());
    if (!readError.empty())
        std::printf("warning: reading stopped after %llu packets: %s (truncated or damaged file)\n",
                    static_cast<unsigned long long>(packets), readError.c_str());
    if (opt.decode)
        std::printf("%s", decodeText.c_str());
    return kExitOk;
}

} // namespace

void registerProbeCommand(CLI::App &app, int &exitCode)
{
    addTableCommand<ProbeOptions>(app, "probe", kAbout, kProbeRows, runProbe, exitCode);
}

} // namespace depthtouch::cli
