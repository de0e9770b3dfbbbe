#include "h264_sps.h"

extern "C" {
#include <libavutil/pixdesc.h>
}

#include <array>

namespace depthtouch::drivers::ffmpeg {

namespace {

/// Bits of an RBSP (emulation prevention bytes already removed), MSB first.
class BitReader {
public:
    BitReader(const std::uint8_t *data, std::size_t size) noexcept : data_(data), size_(size) {}

    /// \return the next bit, or -1 past the end.
    int bit() noexcept
    {
        if (pos_ >= size_ * 8)
            return -1;
        const int b = (data_[pos_ / 8] >> (7 - pos_ % 8)) & 1;
        ++pos_;
        return b;
    }
    /// \return the next \a n (≤ 16) bits, or -1 past the end.
    int bits(int n) noexcept
    {
        int v = 0;
        for (int i = 0; i < n; ++i) {
            const int b = bit();
            if (b < 0)
                return -1;
            v = (v << 1) | b;
        }
        return v;
    }
    /// \return an unsigned Exp-Golomb value ue(v), or -1 past the end or when over 16 bits long.
    int ue() noexcept
    {
        int zeros = 0;
        for (;;) {
            const int b = bit();
            if (b < 0 || zeros > 16)
                return -1;
            if (b == 1)
                break;
            ++zeros;
        }
        const int rest = bits(zeros);
        return rest < 0 ? -1 : (1 << zeros) - 1 + rest;
    }

private:
    const std::uint8_t *data_;
    std::size_t size_;
    std::size_t pos_ = 0;
};

/// Parses one SPS NAL unit (header byte included) up to chroma_format_idc.
int chromaOfSps(const std::uint8_t *nal, std::size_t size) noexcept
{
    if (size < 2 || (nal[0] & 0x1f) != 7)
        return -1;
    // The fields needed lie in the first bytes: unescape (00 00 03 → 00 00) up to 32 of them.
    std::array<std::uint8_t, 32> rbsp{};
    std::size_t n = 0;
    int zeros = 0;
    for (std::size_t i = 1; i < size && n < rbsp.size(); ++i) {
        if (zeros >= 2 && nal[i] == 3) {
            zeros = 0;
            continue;
        }
        zeros = nal[i] == 0 ? zeros + 1 : 0;
        rbsp[n++] = nal[i];
    }
    BitReader r(rbsp.data(), n);
    const int profile = r.bits(8);
    if (profile < 0 || r.bits(16) < 0 || r.ue() < 0) // constraint flags + level, sps id
        return -1;
    // Profiles whose SPS carries chroma_format_idc (7.3.2.1.1); the others are 4:2:0.
    static constexpr int kWithChroma[] = {100, 110, 122, 244, 44,  83, 86,
                                          118, 128, 138, 139, 134, 135};
    for (const int p : kWithChroma)
        if (profile == p) {
            const int chroma = r.ue();
            return chroma >= 0 && chroma <= 3 ? chroma : -1;
        }
    return 1;
}

} // namespace

int h264ChromaFormatIdc(const std::uint8_t *extradata, std::size_t size) noexcept
{
    if (extradata == nullptr || size < 4)
        return -1;
    if (extradata[0] == 1) {
        // avcC: version, profile, compat, level, length size, then the SPS count and each SPS
        // with a 16-bit length.
        if (size < 8 || (extradata[5] & 0x1f) == 0)
            return -1;
        const std::size_t len = (static_cast<std::size_t>(extradata[6]) << 8) | extradata[7];
        return len <= size - 8 ? chromaOfSps(extradata + 8, len) : -1;
    }
    // Annex B: NAL units after 00 00 01 start codes.
    for (std::size_t i = 0; i + 3 < size; ++i) {
        if (extradata[i] != 0 || extradata[i + 1] != 0 || extradata[i + 2] != 1)
            continue;
        const std::size_t start = i + 3;
        std::size_t end = start;
        while (end + 2 < size &&
               !(extradata[end] == 0 && extradata[end + 1] == 0 && extradata[end + 2] <= 1))
            ++end;
        if (end + 2 >= size)
            end = size;
        if ((extradata[start] & 0x1f) == 7)
            return chromaOfSps(extradata + start, end - start);
        i = end - 1;
    }
    return -1;
}

AVPixelFormat samplesFormatOf(const AVCodecParameters &par) noexcept
{
    const auto fmt = static_cast<AVPixelFormat>(par.format);
    if (par.codec_id != AV_CODEC_ID_H264 || par.extradata == nullptr ||
        h264ChromaFormatIdc(par.extradata, static_cast<std::size_t>(par.extradata_size)) != 0)
        return fmt;
    const AVPixFmtDescriptor *d = av_pix_fmt_desc_get(fmt);
    if (d == nullptr || d->comp[0].depth <= 8)
        return AV_PIX_FMT_GRAY8;
    return d->comp[0].depth <= 10 ? AV_PIX_FMT_GRAY10 : AV_PIX_FMT_GRAY16;
}

bool isGray(AVPixelFormat f) noexcept
{
    return f == AV_PIX_FMT_GRAY8 || f == AV_PIX_FMT_GRAY16LE || f == AV_PIX_FMT_GRAY16BE ||
           f == AV_PIX_FMT_GRAY10LE || f == AV_PIX_FMT_GRAY10BE;
}

} // namespace depthtouch::drivers::ffmpeg
