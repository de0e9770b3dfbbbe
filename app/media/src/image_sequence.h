#pragma once
/// \file
/// \brief The numbers of the files an image-sequence pattern (`d/frame-%06d.png`) names, so a
/// sequence with a gap (frames 0-9 and 20-29) can be followed across it: libavformat's image2
/// demuxer stops at the first missing number. Private to dt_media. Thread-safety: reentrant.

#include <string>
#include <vector>

namespace depthtouch::media::detail {

/// \brief Lists the folder of \a pattern (one printf `%d`, `%Nd` or `%0Nd` conversion) and returns
/// the numbers n, sorted, for which a file named exactly `printf(pattern, n)` exists (n ≥ 0).
/// \return the numbers; empty when the folder cannot be read or the pattern has another form.
std::vector<long long> imageSequenceNumbers(const std::string &pattern);

/// \return the first number of \a numbers (sorted) greater than \a last, or -1.
long long nextImageNumber(const std::vector<long long> &numbers, long long last) noexcept;

} // namespace depthtouch::media::detail
