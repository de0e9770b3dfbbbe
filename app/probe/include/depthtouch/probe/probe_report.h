#pragma once
/// \file
/// \brief What `depthtouch probe` reports of a 3D video (docs/playing.md "Receiving: probe and
/// pairing"): its streams and which role each plays and why, the depth metadata, the audio streams
/// and how long each overlaps the picture, the material track, and how many color frames have a
/// depth partner within half a frame (docs/architecture.md §4) — from the packets alone (census())
/// and, optionally, from decoding every frame through the receiver (addDecodePass()); as JSON
/// (reportJson(), the keys of `probe --json`) or as text (printReportText()).
///
/// App layer: the receiver's censuses and the material probe's reading; the media source and the
/// receiver are opened by the caller with the backends it chose (no driver here).
///
/// Thread-safety: a report belongs to one thread; the functions keep no state.

#include <cstdint>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "depthtouch/hal/media_source.h"
#include "depthtouch/media/material_track.h"
#include "depthtouch/receiver/packet_census.h"
#include "depthtouch/receiver/receiver.h"
#include "depthtouch/receiver/stream_roles.h"

namespace depthtouch::probe {

/// \brief Everything the report prints: the demux census, the pairing census and the --decode pass.
struct ProbeReport {
    hal::MediaInfo info;             ///< The streams as the media source describes them.
    receiver::StreamRoles roles;     ///< Which stream is color, depth (identifyStreams()) and why.
    receiver::DemuxCensus demux;     ///< Packets and key frames per stream; a read error, if any.
    std::vector<hal::Pts> spans;     ///< Per stream: first to last PTS plus one period, ns.
    receiver::PairingCensus census;  ///< Color frames with a depth partner by packet PTS.
    std::uint64_t unpairedColor = 0; ///< Color frames without one.
    bool everyPaired = false;        ///< Color and depth present and every color frame paired.
    nlohmann::json decodeJson;       ///< The --decode pass's counters (addDecodePass()), or null.
    std::string decodeText;          ///< The same as the text report's lines.
    std::optional<media::MaterialStreamInfo> material; ///< The material stream, when there is one.
};

/// \brief Reads every packet of the open \a source (consumed: read to its end or first error) and
/// returns the streams, roles, packet census and pairing census. Errors of the read are in
/// ProbeReport::demux.readError, not thrown.
[[nodiscard]] ProbeReport census(hal::MediaSource &source);

/// \brief Decodes and pairs every frame of the open receiver \a r (to its end) and adds its
/// counters to \a rep, with the hole count of the decoded depth when there is depth.
void addDecodePass(ProbeReport &rep, receiver::Receiver &r);

/// \return the JSON report of \a rep for \a file (`probe --json`): file, duration_s, packets,
/// read_error, streams, audio, depth_metadata (planes null when unknown), pairing, material,
/// notes, and decode when \a decode.
[[nodiscard]] nlohmann::json reportJson(const ProbeReport &rep, const std::string &file,
                                        bool decode);

/// \brief Writes the text report of \a rep for \a file to \a out (`probe`): a line per stream
/// with its role, the depth metadata, material and audio lines, pairing, notes, a read warning,
/// and the decode pass's lines when \a decode.
void printReportText(std::FILE *out, const ProbeReport &rep, const std::string &file, bool decode);

} // namespace depthtouch::probe
