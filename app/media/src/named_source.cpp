/// \file
/// \brief NamedSource: see named_source.h.

#include "depthtouch/media/named_source.h"

#include <utility>

namespace depthtouch::media {

NamedSource::NamedSource(std::string role, std::string spec, std::unique_ptr<FrameSource> inner)
    : role_(std::move(role)), spec_(std::move(spec)), inner_(std::move(inner))
{
}

Result<SourceFrame> NamedSource::next(PixelFormat format, int width, int height)
{
    auto r = inner_->next(format, width, height);
    if (!r && r.error().code != Errc::EndOfStream && !failed_) {
        failed_ = true;
        error_ = r.error();
    }
    return r;
}

std::string NamedSource::message() const
{
    char buf[256];
    return "cannot read " + role_ + " input '" + spec_ + "': " + error_.format(buf, sizeof buf);
}

} // namespace depthtouch::media
