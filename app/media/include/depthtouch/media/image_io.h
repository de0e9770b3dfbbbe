#pragma once
/// \file
/// \brief Image files through FFmpeg: libavformat demuxes (the image2 family: png_pipe, jpeg_pipe,
/// pgm_pipe…, chosen by probing the content), libavcodec decodes and encodes, libswscale converts
/// the layout. No image format is parsed by hand.
///
/// Errors carry static messages; the file name and FFmpeg's own message are logged (category
/// "Media"). Thread-safety: reentrant (each call owns its FFmpeg contexts).

#include <optional>
#include <string>

#include "depthtouch/media/image.h"
#include "depthtouch/platform/result.h"

namespace depthtouch::media {

/// \brief Reads a picture (PNG 8/16-bit gray, gray+alpha, palette or RGB(A); JPEG; PGM/PPM; BMP;
/// TIFF; any still format FFmpeg decodes) and converts it to \a format.
///
/// Conversions (libswscale): 16 → 8 bit keeps the high byte, 8 → 16 bit scales by 257, colour →
/// gray takes the luma (BT.601), gray → RGB replicates, alpha is dropped. A file already in the
/// requested layout is copied bit-exactly (16-bit big-endian PNG/PGM samples come out as native
/// uint16). \param[in] path file name \param[in] format wanted layout; nullopt = the file's own:
/// Gray16 for gray deeper than 8 bits, Gray8 for
///            other gray, Rgb24 otherwise
/// \return the image, tightly packed; errors: Errc::Io (missing or unreadable file),
/// Errc::InvalidArgument
///         (not a picture, corrupt or truncated data), Errc::NotSupported (no decoder or converter
///         for it).
Result<Image> readImage(const std::string &path, std::optional<PixelFormat> format = std::nullopt);

/// \brief Writes \a image as a PNG file with libavcodec's PNG encoder (Gray8 → 8-bit gray, Gray16 →
/// 16-bit gray, Rgb24 → 8-bit RGB; lossless: reading it back gives the same samples). Replaces \a
/// path whole (platform::writeOutputFile: written under a temporary name beside it and renamed
/// when complete, never a cut file). \return Errc::InvalidArgument for an empty or inconsistent
/// image, Errc::NotSupported when FFmpeg has no PNG encoder, Errc::Io when the file cannot be
/// written (no folder, a directory, a full disk).
Result<void> writePng(const std::string &path, const Image &image);

} // namespace depthtouch::media
