#pragma once
/// \file
/// \brief The census of a 3D video that `depthtouch probe` reports (docs/architecture.md §4): its
/// packets counted per stream by a demux pass, the receiver's pairing rules (pts_pairer.h) run on
/// their PTS, each stream's duration, and the hole samples (§3 "Holes") of the depth frames the
/// real receiver decodes. Times are hal::Pts (ns). The media source and the receiver are the
/// caller's (the executable picks their backends).
/// Thread-safety: none needed; each call works on what it is handed, on the caller's thread.

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "depthtouch/hal/media_source.h"
#include "depthtouch/receiver/frame_store.h"
#include "depthtouch/receiver/pts_pairer.h"
#include "depthtouch/receiver/receiver.h"
#include "depthtouch/receiver/stream_roles.h"

namespace depthtouch::receiver {

/// Per-stream packet census of the demux pass.
struct StreamCount {
    std::uint64_t packets = 0;
    std::uint64_t keyframes = 0;
    std::vector<hal::Pts> pts;
};

struct PairingCensus {
    PairerStats stats;
    std::uint64_t colorFrames = 0;
    std::uint64_t colorWithPartner = 0;
};

/// The demux pass: every packet's stream, keyframe flag and PTS, and why reading stopped early.
struct DemuxCensus {
    std::vector<StreamCount> counts;
    std::uint64_t packets = 0;
    std::string readError; ///< Empty when reading reached the end of the stream.
};

/// \brief Reads every packet of the open source \a src (then closes it), counting them per stream
/// (\a streams of them; packets of other indices count in the total only).
DemuxCensus countPackets(hal::MediaSource &src, std::size_t streams);

/// \return each stream's duration: its PTS range plus one frame period (0 for a stream without
/// packets).
std::vector<hal::Pts> streamSpans(const hal::MediaInfo &info,
                                  const std::vector<StreamCount> &counts);

/// \brief Runs the pairing rules on the PTS of the streams of \a roles in \a counts (sorted in
/// place: presentation order). A rate that is unknown takes the other stream's, else 30 fps.
PairingCensus pairPackets(const hal::MediaInfo &info, const StreamRoles &roles,
                          std::vector<StreamCount> &counts);

/// \brief The hole samples (docs/architecture.md §3 "Holes") of the distinct depth frames decoded.
struct HoleCount {
    std::uint64_t samples = 0;
    std::uint64_t holes = 0;
    std::uint64_t lastSequence = ~std::uint64_t{0};

    /// Counts depth frame \a d, unless it is the one counted last (a depth frame reused).
    void add(const StoredFrame &d);
};

/// \brief Runs \a r (decode + pairing) to the end of its input or its first error, counting the
/// holes of the depth frames it pairs. Its counters are then in Receiver::stats().
HoleCount decodeToEnd(Receiver &r);

} // namespace depthtouch::receiver
