#pragma once
/// \file
/// \brief Test support for the seed-corpus writers of text fuzzers (the control socket's lines,
/// the play --config TOML): each seed a selector byte and a text, written as DIR/seed-NAME.
/// Header-only. Thread-safety: reentrant.

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <span>
#include <string>

namespace depthtouch::testing {

/// One seed: a file name, the fuzz target's selector byte (its first input byte), the text.
struct TextSeed {
    const char *name;
    char selector;
    const char *text;
};

/// \brief The main() of a seed writer: `PROGRAM DIR` writes every seed of \a seeds into DIR
/// (created). \return the exit code: 0, 1 when a file could not be written, 2 for bad usage.
inline int writeTextSeeds(int argc, char **argv, const char *program,
                          std::span<const TextSeed> seeds)
{
    if (argc != 2) {
        std::fprintf(stderr, "usage: %s DIR\n", program);
        return 2;
    }
    const std::string dir = argv[1];
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    for (const TextSeed &s : seeds) {
        std::ofstream out(dir + "/seed-" + s.name, std::ios::binary);
        out.put(s.selector);
        out << s.text;
        if (!out) {
            std::fprintf(stderr, "%s: cannot write %s/seed-%s\n", program, dir.c_str(), s.name);
            return 1;
        }
    }
    return 0;
}

} // namespace depthtouch::testing
