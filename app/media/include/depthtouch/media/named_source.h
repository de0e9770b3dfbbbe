#pragma once
/// \file
/// \brief A media::FrameSource that remembers its role, its spec and its first error, so that the
/// one error line of `depthtouch encode` can say which input failed ("cannot read depth input
/// 'd.mkv': ..."). Frames pass through unchanged; the end of the stream is no error.
/// Thread-safety: as the wrapped source (one thread).

#include <memory>
#include <string>

#include "depthtouch/media/frame_source.h"

namespace depthtouch::media {

/// \brief A FrameSource named by its role and spec that keeps its first error.
class NamedSource final : public FrameSource {
public:
    /// \param role e.g. "color"; \param spec the input as given; \param inner the source.
    NamedSource(std::string role, std::string spec, std::unique_ptr<FrameSource> inner);

    [[nodiscard]] const SourceInfo &info() const noexcept override { return inner_->info(); }
    /// \return the inner source's frame; its first error other than EndOfStream is kept.
    Result<SourceFrame> next(PixelFormat format, int width, int height) override;
    /// \return whether a frame failed.
    [[nodiscard]] bool failed() const noexcept { return failed_; }
    /// \return "cannot read ROLE input 'SPEC': " and the first error (Error::format()).
    [[nodiscard]] std::string message() const;

private:
    std::string role_;
    std::string spec_;
    std::unique_ptr<FrameSource> inner_;
    bool failed_ = false;
    Error error_{};
};

} // namespace depthtouch::media
