// libFuzzer target over the `play --config` TOML loader (app/cli/play_config.h).
//
// Input: byte 0 says which keys count as given on the command line (bit i: the key's length
// modulo 8 is i); the rest is the file's text. Invariants (any violation traps): nothing throws;
// the result is empty or one printable line of bounded length; a key given on the command line is
// never applied.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "play_config.h"

namespace {

using namespace depthtouch::cli;

void check(bool ok)
{
    if (!ok)
        __builtin_trap();
}

/// Longest error line: fixed text plus at most two quoted 64-byte excerpts and a 200-byte
/// description.
constexpr std::size_t kMaxErrorBytes = 600;

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t *data, std::size_t size)
{
    if (size < 1 || size > kMaxPlayConfigBytes)
        return 0;
    const unsigned givenMask = data[0];
    const std::string_view text(reinterpret_cast<const char *>(data + 1), size - 1);
    const GivenOnCommandLine given = [givenMask](const std::string &key) {
        return (givenMask >> (key.size() % 8)) & 1u;
    };
    PlayOptions options;
    const PlayOptions defaults;
    std::string error;
    try {
        error = applyPlayConfigText(text, "fuzz.toml", given, options);
    } catch (...) {
        check(false);
    }
    check(error.size() <= kMaxErrorBytes);
    for (const char c : error)
        check(c >= 0x20 && c < 0x7f);
    // Keys of length 7 ("display", "control") and 6 ("haptic", "record") given: never applied.
    if ((givenMask >> 7) & 1u) {
        check(options.display == defaults.display);
        check(options.control == defaults.control);
    }
    if ((givenMask >> 6) & 1u) {
        check(options.haptic == defaults.haptic);
        check(options.record == defaults.record);
    }
    return 0;
}
