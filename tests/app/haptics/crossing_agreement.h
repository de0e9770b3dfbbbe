#pragma once
/// \file
/// \brief Compares two first-crossing queries (depthtouch/haptics/collision.h) on many random
/// segments: a fast query against its reference.

#include <cstdint>
#include <random>

#include <glm/vec3.hpp>

#include "depthtouch/haptics/collision.h"

namespace depthtouch::haptics::test {

/// What countAgreement() counted.
struct CrossingAgreement {
    int hits = 0;       ///< Segments on which the tested query found a crossing.
    int mismatches = 0; ///< Segments on which disagree() said the two answers differ.
};

/// Draws \a count segments and asks both queries about each one. Segment i (its ends a, b in m) is
/// segment(i, rng) → std::pair<glm::dvec3, glm::dvec3>, drawn from one std::mt19937_64 seeded with
/// \a seed; tested(a, b) and reference(a, b) → Crossing; disagree(tested, reference, a, b) → bool.
template <class Segment, class Tested, class Reference, class Disagree>
CrossingAgreement countAgreement(std::uint64_t seed, int count, Segment segment, Tested tested,
                                 Reference reference, Disagree disagree)
{
    std::mt19937_64 rng(seed);
    CrossingAgreement out;
    for (int i = 0; i < count; ++i) {
        const auto [a, b] = segment(i, rng);
        const Crossing t = tested(a, b);
        const Crossing r = reference(a, b);
        out.hits += t.hit ? 1 : 0;
        if (disagree(t, r, a, b))
            ++out.mismatches;
    }
    return out;
}

} // namespace depthtouch::haptics::test
