// Writes the seed corpus of receiver_fuzz into the folder given as argument: small color + depth
// clips (written with libavformat/libavcodec at run time, no committed binaries), each prefixed
// with the demuxer selector byte of the fuzz target.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "test_media.h"

namespace rt = depthtouch::receivertest;

namespace {

bool emit(const std::string &dir, const std::string &name, char selector, const rt::Clip &clip)
{
    const std::string tmp = dir + "/" + name;
    const std::string err = rt::writeClip(tmp, clip);
    if (!err.empty()) {
        std::fprintf(stderr, "receiver_fuzz_seeds: %s: %s\n", name.c_str(), err.c_str());
        return false;
    }
    std::vector<char> bytes;
    {
        std::ifstream in(tmp, std::ios::binary);
        bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }
    std::filesystem::remove(tmp);
    std::ofstream out(dir + "/seed-" + name, std::ios::binary);
    out.put(selector);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    return static_cast<bool>(out);
}

} // namespace

int main(int argc, char **argv)
{
    if (argc != 2) {
        std::fprintf(stderr, "usage: receiver_fuzz_seeds DIR\n");
        return 2;
    }
    const std::string dir = argv[1];
    std::filesystem::create_directories(dir);
    bool ok = true;
    rt::Clip std = rt::Clip::standard(32, 24, 4, 30);
    ok = emit(dir, "std.mkv", 0, std) && ok;
    ok = emit(dir, "std.ts", 1, std) && ok;
    ok = emit(dir, "std.mp4", 2, std) && ok;
    rt::Clip rates = rt::Clip::standard(16, 16, 6, 30);
    rates.depth.fps = 15;
    rates.depth.frames = 2;
    rates.color.bframes = 1;
    ok = emit(dir, "rates.mkv", 3, rates) && ok;
    rt::Clip gap = rt::Clip::standard(16, 16, 4, 30);
    gap.color.pts = {0, 1, 5, 6};
    gap.depth.pts = {0, 2, 3, 6};
    gap.depth.encoder = "ffv1";
    ok = emit(dir, "gap.mkv", 0, gap) && ok;
    rt::Clip single = rt::Clip::standard(16, 16, 3, 30);
    single.color.enabled = false;
    ok = emit(dir, "depth-only.mkv", 0, single) && ok;
    return ok ? 0 : 1;
}
