#pragma once
/// \file
/// \brief What haptics_bench.cpp (the measurement) and haptics_bench_outputs.cpp (its files and
/// charts) share; not a public header.

#include <string>

namespace depthtouch::haptics::bench {

/// \brief A PSD figure (dB) as text with \a unit appended: "n/a" when not measured (NaN: moving
/// HIP), "no force" when |F| had no power (−infinity).
std::string psdText(double db, const char *unit);

} // namespace depthtouch::haptics::bench
