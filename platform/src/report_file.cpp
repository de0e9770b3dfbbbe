#include "depthtouch/platform/report_file.h"

#include <cstdarg>
#include <filesystem>
#include <system_error>
#include <utility>

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

ReportFile::ReportFile(const std::string &path)
{
    if (auto f = OutputFile::open(path))
        file_ = std::move(*f);
}

void ReportFile::print(const char *format, ...) noexcept
{
    if (!file_.isOpen())
        return;
    std::va_list args;
    va_start(args, format);
    std::vfprintf(file_.stream(), format, args);
    va_end(args);
}

TextReportFile::TextReportFile(std::string path, std::string &error)
    : path_(std::move(path)), error_(error)
{
}

TextReportFile::~TextReportFile()
{
    (void)close();
}

bool TextReportFile::close()
{
    if (closed_)
        return written_;
    closed_ = true;
    auto w = writeOutputFile(path_, str());
    written_ = w.has_value();
    if (!written_ && error_.empty()) {
        char why[160];
        error_ = "cannot write '" + path_ + "': " + w.error().format(why, sizeof why);
    }
    return written_;
}

bool ReportFile::close() noexcept
{
    if (!file_.isOpen())
        return false;
    return file_.commit().has_value();
}

} // namespace depthtouch::platform
