#pragma once
/// \file
/// \brief enumName(): an enumerator's name from a table of names in declaration order, for the
/// `...Name()` functions of the layers above. Thread-safety: reentrant (reads constant tables).

#include <array>
#include <cstddef>

namespace depthtouch::platform {

/// \brief The name of \a value from \a names, the names of an enumeration's enumerators in
/// declaration order (enumerators numbered 0, 1, 2, ... without gaps).
/// \param fallback returned for a value past the end of \a names (a value cast from bad input).
/// \return a static string (the table's or \a fallback).
template <typename Enum, std::size_t N>
[[nodiscard]] constexpr const char *enumName(Enum value, const std::array<const char *, N> &names,
                                             const char *fallback) noexcept
{
    const auto index = static_cast<std::size_t>(value);
    return index < N ? names[index] : fallback;
}

} // namespace depthtouch::platform
