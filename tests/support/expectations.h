#pragma once
/// \file
/// \brief Small helpers of expectations shared by the test programs: the error code of a Result,
/// and the names an enumeration's toString() gives. Header-only.

#include <initializer_list>
#include <optional>
#include <utility>

#include <gtest/gtest.h>

#include "depthtouch/platform/result.h"

namespace depthtouch::testing {

/// \return the error code of \a r (a Result), or std::nullopt when it succeeded.
template <class R> std::optional<Errc> errcOf(const R &r)
{
    if (r)
        return std::nullopt;
    return r.error().code;
}

/// Expects toString(value) (found by argument-dependent lookup) to be the name beside each value
/// of \a names.
template <class E> void expectNames(std::initializer_list<std::pair<E, const char *>> names)
{
    for (const auto &[value, name] : names)
        EXPECT_STREQ(toString(value), name);
}

} // namespace depthtouch::testing
