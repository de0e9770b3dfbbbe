#include "depthtouch/platform/report_file.h"

#include <cstdarg>
#include <filesystem>
#include <system_error>

namespace depthtouch::platform {

std::string createReportFolder(const std::string &dir)
{
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    return ec ? ec.message() : std::string();
}

bool createReportFolder(const std::string &dir, const std::string &what, std::string &error)
{
    const std::string why = createReportFolder(dir);
    if (!why.empty())
        error = what + ": " + why;
    return why.empty();
}

ReportFile::ReportFile(const std::string &path) noexcept : file_(std::fopen(path.c_str(), "w")) {}

ReportFile::~ReportFile()
{
    if (file_ != nullptr)
        std::fclose(file_);
}

void ReportFile::print(const char *format, ...) noexcept
{
    if (file_ == nullptr)
        return;
    std::va_list args;
    va_start(args, format);
    std::vfprintf(file_, format, args);
    va_end(args);
}

bool ReportFile::close() noexcept
{
    if (file_ == nullptr)
        return false;
    const bool written = std::ferror(file_) == 0;
    const bool closed = std::fclose(file_) == 0;
    file_ = nullptr;
    return written && closed;
}

} // namespace depthtouch::platform
