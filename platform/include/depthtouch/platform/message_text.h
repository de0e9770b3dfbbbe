#pragma once
/// \file
/// \brief Text from the user or a file put into a one-line message: bounded, printable.
/// A 10 MB value or a key with newlines must not become a 10 MB or a multi-line stderr message.
/// Thread-safety: reentrant.

#include <cstddef>
#include <string>
#include <string_view>

namespace depthtouch::platform {

/// \return \a text with every byte outside printable ASCII (newlines, control bytes, UTF-8) as '?'
/// and, when longer than \a maxBytes, cut there with "..." appended.
inline std::string printableText(std::string_view text, std::size_t maxBytes = 200)
{
    std::string out;
    const std::string_view kept = text.substr(0, maxBytes);
    out.reserve(kept.size() + 3);
    for (const char c : kept) {
        const auto u = static_cast<unsigned char>(c);
        out += u >= 0x20 && u < 0x7f ? c : '?';
    }
    if (text.size() > maxBytes)
        out += "...";
    return out;
}

/// \return \a text in single quotes, as printableText() with at most \a maxBytes kept.
inline std::string quotedText(std::string_view text, std::size_t maxBytes = 64)
{
    return "'" + printableText(text, maxBytes) + "'";
}

} // namespace depthtouch::platform
