/// \file
/// \brief The report of `depthtouch probe` (probe_report.h): census, decode pass, JSON and text.

#include "depthtouch/probe/probe_report.h"

#include <algorithm>
#include <cstdio>
#include <string>

#include "depthtouch/platform/clock.h"

namespace depthtouch::probe {

namespace {

/// A depth plane (m) as the report shows it: unknown (0 in hal::DepthMetadata: a file made from
/// 8-bit nearness without --near/--far, whose tags say "unknown") is not a distance.
std::string planeText(double metres)
{
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g m", metres);
    return metres > 0.0 ? buf : "unknown";
}

/// The same in the JSON report: null when unknown.
nlohmann::json planeJson(double metres)
{
    return metres > 0.0 ? nlohmann::json(metres) : nlohmann::json(nullptr);
}

std::string rateText(const hal::Rational &r)
{
    if (r.num <= 0 || r.den <= 0)
        return "unknown";
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3g", r.toDouble());
    return buf;
}

/// The receiver's counters as the JSON report's "decode" object.
nlohmann::json decodeStatsJson(const char *mode, const receiver::ReceiverStats &s)
{
    return {{"mode", mode},
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
            {"read_errors", s.readErrors},
            {"color_frames_hardware", s.colorFramesHardware},
            {"depth_frames_hardware", s.depthFramesHardware}};
}

/// The receiver's counters as the text report's "decode" line.
std::string decodeStatsText(const char *mode, const receiver::ReceiverStats &s)
{
    char line[512];
    std::snprintf(line, sizeof line,
                  "decode (%s): %llu color + %llu depth frames -> %llu paired; %llu concealed, "
                  "%llu decode errors, %llu without depth, %llu reused depth, %llu read errors; "
                  "%llu color + %llu depth frames decoded in hardware\n",
                  mode, static_cast<unsigned long long>(s.colorFrames),
                  static_cast<unsigned long long>(s.depthFrames),
                  static_cast<unsigned long long>(s.framesOutput),
                  static_cast<unsigned long long>(s.framesConcealed),
                  static_cast<unsigned long long>(s.decodeErrors),
                  static_cast<unsigned long long>(s.depthMissing),
                  static_cast<unsigned long long>(s.depthDuplicated),
                  static_cast<unsigned long long>(s.readErrors),
                  static_cast<unsigned long long>(s.colorFramesHardware),
                  static_cast<unsigned long long>(s.depthFramesHardware));
    return line;
}

/// The text report's "holes" line.
std::string holesText(const receiver::HoleCount &h, std::uint32_t holeBelow)
{
    char line[200];
    std::snprintf(
        line, sizeof line,
        "holes: %.2f %% of %llu decoded depth samples (below %u, decoded units)\n",
        h.samples > 0 ? 100.0 * static_cast<double>(h.holes) / static_cast<double>(h.samples) : 0.0,
        static_cast<unsigned long long>(h.samples), holeBelow);
    return line;
}

/// The role a stream plays, with the reason it was chosen ("ignored" for any other stream).
std::string roleOf(const ProbeReport &rep, int index)
{
    const receiver::StreamRoles &roles = rep.roles;
    if (rep.material && index == rep.material->index && index != roles.color &&
        index != roles.depth)
        return "material (" + rep.material->titleFrom + ")";
    if (index == roles.color)
        return std::string("color (") + roles.colorReason + ")";
    if (index == roles.depth)
        return std::string("depth (") + roles.depthReason + ")";
    return "ignored";
}

/// The text report's words for the depth_occupancy tag \a threshold.
std::string occupancyText(std::uint32_t threshold)
{
    return threshold == 0 ? std::string("no holes (no depth_occupancy)")
                          : "holes below " + std::to_string(threshold) + " (depth_occupancy)";
}

/// The depth stream's description, or nullptr when the file has none.
const hal::StreamInfo *depthStreamOf(const ProbeReport &rep)
{
    return rep.roles.depth >= 0 ? &rep.info.streams[static_cast<std::size_t>(rep.roles.depth)]
                                : nullptr;
}

/// The JSON report's "streams" array.
nlohmann::json streamsJson(const ProbeReport &rep)
{
    nlohmann::json streams = nlohmann::json::array();
    for (const hal::StreamInfo &s : rep.info.streams) {
        const receiver::StreamCount &c = rep.demux.counts[static_cast<std::size_t>(s.index)];
        streams.push_back(
            {{"index", s.index},
             {"title", s.title},
             {"role", roleOf(rep, s.index)},
             {"codec", hal::codecName(s.codec)},
             {"width", s.width},
             {"height", s.height},
             {"pix_fmt", hal::pixelFormatName(s.format)},
             {"frame_rate", s.frameRate.toDouble()},
             {"frames", c.packets},
             {"keyframes", c.keyframes},
             {"duration_s", platform::toSeconds(rep.spans[static_cast<std::size_t>(s.index)])}});
    }
    return streams;
}

/// How long (s) audio stream \a a overlaps the picture, taken as [0, the longest video stream's
/// span]; 0 when it does not, or when its length is unknown.
double audioOverlap(const ProbeReport &rep, const hal::AudioStreamInfo &a)
{
    hal::Pts picture{0};
    for (const hal::Pts span : rep.spans)
        picture = std::max(picture, span);
    const double begin = std::max(0.0, platform::toSeconds(a.start));
    const double end =
        std::min(platform::toSeconds(picture), platform::toSeconds(a.start + a.duration));
    return std::max(0.0, end - begin);
}

/// The JSON report's "audio" array.
nlohmann::json audioJson(const ProbeReport &rep)
{
    nlohmann::json audio = nlohmann::json::array();
    for (const hal::AudioStreamInfo &a : rep.info.audio)
        audio.push_back({{"stream", a.containerIndex},
                         {"codec", a.codec},
                         {"sample_rate", a.sampleRate},
                         {"channels", a.channels},
                         {"start_s", platform::toSeconds(a.start)},
                         {"duration_s", platform::toSeconds(a.duration)},
                         {"language", a.language.empty() ? nlohmann::json(nullptr)
                                                         : nlohmann::json(a.language)},
                         {"overlap_s", audioOverlap(rep, a)}});
    return audio;
}

/// Prints one line per audio stream.
void printAudioText(std::FILE *out, const ProbeReport &rep)
{
    for (const hal::AudioStreamInfo &a : rep.info.audio) {
        char overlap[96];
        if (const double o = audioOverlap(rep, a); o > 0.0)
            std::snprintf(overlap, sizeof overlap, "overlaps the picture for %.3f s", o);
        else
            std::snprintf(overlap, sizeof overlap, "does not overlap the picture");
        std::fprintf(out, "audio: stream #%d %s, %d Hz, %d channel%s, %.3f s from %.3f s%s%s; %s\n",
                     a.containerIndex, a.codec.c_str(), a.sampleRate, a.channels,
                     a.channels == 1 ? "" : "s", platform::toSeconds(a.duration),
                     platform::toSeconds(a.start), a.language.empty() ? "" : ", language ",
                     a.language.c_str(), overlap);
    }
}

/// Prints the material line ("has materials") when the file has a material track.
void printMaterialText(std::FILE *out, const ProbeReport &rep)
{
    if (!rep.material)
        return;
    const media::MaterialStreamInfo &m = *rep.material;
    const char *lossless = !m.lossless ? "unknown" : *m.lossless ? "yes" : "NO";
    std::fprintf(out, "material: stream #%d %dx%d %s %s, lossless %s%s; has materials\n", m.index,
                 m.width, m.height, m.codec.c_str(), m.pixelFormat.c_str(), lossless,
                 m.tagsPresent ? ", planes and scales tagged" : "");
    if (m.decoded)
        std::fprintf(
            out,
            "material first frame: stiffness scale %.4g..%.4g, static friction %.3g..%.3g, "
            "dynamic friction %.3g..%.3g\n",
            m.minValue[0], m.maxValue[0], m.minValue[1], m.maxValue[1], m.minValue[2],
            m.maxValue[2]);
}

/// Prints the text report's header line, one line per stream and the depth metadata line.
void printStreamsText(std::FILE *out, const std::string &file, const ProbeReport &rep)
{
    const hal::MediaInfo &info = rep.info;
    std::fprintf(out, "%s: %zu video stream%s, %.3f s\n", file.c_str(), info.streams.size(),
                 info.streams.size() == 1 ? "" : "s", platform::toSeconds(info.duration));
    if (!info.renditions.empty()) {
        std::fprintf(out,
                     "renditions: %zu (HLS multivariant playlist; the source option rendition "
                     "picks one)\n",
                     info.renditions.size());
        for (const hal::RenditionInfo &r : info.renditions)
            std::fprintf(out, "  %dx%d, %.0f kbit/s%s\n", r.width, r.height,
                         static_cast<double>(r.bitRate) / 1000.0, r.kept ? " (read below)" : "");
    }
    for (const hal::StreamInfo &s : info.streams) {
        const receiver::StreamCount &c = rep.demux.counts[static_cast<std::size_t>(s.index)];
        std::fprintf(out, "  #%d %-8s %-32s %-6s %dx%d %-8s %s fps, %llu frames (%.3f s)\n",
                     s.index, s.title.empty() ? "-" : s.title.c_str(), roleOf(rep, s.index).c_str(),
                     hal::codecName(s.codec), s.width, s.height, hal::pixelFormatName(s.format),
                     rateText(s.frameRate).c_str(), static_cast<unsigned long long>(c.packets),
                     platform::toSeconds(rep.spans[static_cast<std::size_t>(s.index)]));
    }
    if (const hal::StreamInfo *depth = depthStreamOf(rep); depth != nullptr) {
        const hal::DepthMetadata &m = depth->depth;
        if (receiver::hasDepthMetadata(m))
            std::fprintf(out, "depth metadata: near %s, far %s, mapping %s, %d bits, %s\n",
                         planeText(m.nearMetres).c_str(), planeText(m.farMetres).c_str(),
                         m.mapping.empty() ? "-" : m.mapping.c_str(), m.bits,
                         occupancyText(m.occupancy).c_str());
        else
            std::fprintf(out, "depth metadata: none\n");
    }
    printMaterialText(out, rep);
    printAudioText(out, rep);
}

/// Prints the text report's pairing line and timestamp line.
void printPairingText(std::FILE *out, const ProbeReport &rep)
{
    const receiver::StreamRoles &roles = rep.roles;
    const receiver::PairingCensus &census = rep.census;
    if (roles.color >= 0 && roles.depth >= 0)
        std::fprintf(out,
                     "pairing: %llu of %llu color frames have a depth partner within half a frame "
                     "(%llu without: %llu reuse the previous depth frame, %llu have none); %llu "
                     "depth frames unpaired; %s\n",
                     static_cast<unsigned long long>(census.colorWithPartner),
                     static_cast<unsigned long long>(census.colorFrames),
                     static_cast<unsigned long long>(rep.unpairedColor),
                     static_cast<unsigned long long>(census.stats.depthDuplicated),
                     static_cast<unsigned long long>(census.stats.depthMissing),
                     static_cast<unsigned long long>(census.stats.depthUnpaired),
                     rep.everyPaired ? "every color frame is paired"
                                     : "NOT every color frame is paired");
    else if (roles.depth >= 0)
        std::fprintf(out, "pairing: no color stream (depth only, %llu frames)\n",
                     static_cast<unsigned long long>(
                         rep.demux.counts[static_cast<std::size_t>(roles.depth)].packets));
    else
        std::fprintf(out, "pairing: no depth stream (color only: plays flat 2D, haptics off)\n");
    if (census.stats.ptsGaps + census.stats.ptsDuplicates > 0)
        std::fprintf(out, "timestamps: %llu gaps, %llu duplicates\n",
                     static_cast<unsigned long long>(census.stats.ptsGaps),
                     static_cast<unsigned long long>(census.stats.ptsDuplicates));
}

} // namespace

void printReportText(std::FILE *out, const ProbeReport &rep, const std::string &file, bool decode)
{
    printStreamsText(out, file, rep);
    printPairingText(out, rep);
    for (const std::string &n : rep.roles.notes)
        std::fprintf(out, "note: %s\n", n.c_str());
    if (!rep.demux.readError.empty())
        std::fprintf(
            out, "warning: reading stopped after %llu packets: %s (truncated or damaged file)\n",
            static_cast<unsigned long long>(rep.demux.packets), rep.demux.readError.c_str());
    if (decode)
        std::fprintf(out, "%s", rep.decodeText.c_str());
}

ProbeReport census(hal::MediaSource &source)
{
    ProbeReport rep;
    rep.info = source.info();
    rep.roles = receiver::identifyStreams(rep.info);
    rep.demux = receiver::countPackets(source, rep.info.streams.size());
    rep.spans = receiver::streamSpans(rep.info, rep.demux.counts);
    rep.census = receiver::pairPackets(rep.info, rep.roles, rep.demux.counts);
    rep.unpairedColor = rep.census.colorFrames - rep.census.colorWithPartner;
    rep.everyPaired = rep.roles.color >= 0 && rep.roles.depth >= 0 && rep.unpairedColor == 0;
    return rep;
}

void addDecodePass(ProbeReport &rep, receiver::Receiver &r)
{
    const receiver::HoleCount holes = receiver::decodeToEnd(r);
    const receiver::ReceiverStats s = r.stats();
    rep.decodeJson = decodeStatsJson(receiver::receiverModeName(r.info().mode), s);
    rep.decodeText = decodeStatsText(receiver::receiverModeName(r.info().mode), s);
    if (r.info().hasDepth) {
        rep.decodeJson["hole_below"] = r.info().depthHoleBelow;
        rep.decodeJson["depth_samples"] = holes.samples;
        rep.decodeJson["hole_samples"] = holes.holes;
        rep.decodeText += holesText(holes, r.info().depthHoleBelow);
    }
}

nlohmann::json reportJson(const ProbeReport &rep, const std::string &file, bool decode)
{
    const receiver::PairingCensus &census = rep.census;
    const hal::StreamInfo *depth = depthStreamOf(rep);
    nlohmann::json j;
    j["file"] = file;
    j["duration_s"] = platform::toSeconds(rep.info.duration);
    j["packets"] = rep.demux.packets;
    j["read_error"] =
        rep.demux.readError.empty() ? nlohmann::json(nullptr) : nlohmann::json(rep.demux.readError);
    j["streams"] = streamsJson(rep);
    j["renditions"] = nlohmann::json::array();
    for (const hal::RenditionInfo &r : rep.info.renditions)
        j["renditions"].push_back(
            {{"width", r.width}, {"height", r.height}, {"bandwidth", r.bitRate}, {"kept", r.kept}});
    j["audio"] = audioJson(rep);
    if (depth != nullptr)
        j["depth_metadata"] = {{"near_m", planeJson(depth->depth.nearMetres)},
                               {"far_m", planeJson(depth->depth.farMetres)},
                               {"mapping", depth->depth.mapping},
                               {"bits", depth->depth.bits},
                               {"occupancy", depth->depth.occupancy}};
    else
        j["depth_metadata"] = nullptr;
    j["pairing"] = {{"color_frames", census.colorFrames},
                    {"color_with_depth_partner", census.colorWithPartner},
                    {"color_without_depth_partner", rep.unpairedColor},
                    {"depth_reused", census.stats.depthDuplicated},
                    {"depth_missing", census.stats.depthMissing},
                    {"depth_unpaired", census.stats.depthUnpaired},
                    {"pts_gaps", census.stats.ptsGaps},
                    {"pts_duplicates", census.stats.ptsDuplicates},
                    {"every_color_frame_paired", rep.everyPaired}};
    if (const auto &m = rep.material) {
        nlohmann::json mj = {{"stream", m->index},        {"width", m->width},
                             {"height", m->height},       {"codec", m->codec},
                             {"pix_fmt", m->pixelFormat}, {"tags", m->tagsPresent}};
        mj["lossless"] = m->lossless ? nlohmann::json(*m->lossless) : nlohmann::json(nullptr);
        if (m->decoded)
            mj["first_frame"] = {{"stiffness_scale", {m->minValue[0], m->maxValue[0]}},
                                 {"static_friction", {m->minValue[1], m->maxValue[1]}},
                                 {"dynamic_friction", {m->minValue[2], m->maxValue[2]}}};
        j["material"] = mj;
    }
    j["notes"] = rep.roles.notes;
    if (decode)
        j["decode"] = rep.decodeJson;
    return j;
}

} // namespace depthtouch::probe
