#pragma once
/// \file
/// \brief Writing a benchmark's output folder: createReportFolder() makes the folder and
/// ReportFile writes one text file of it (CSV, gnuplot script) with printf-style calls, then says
/// whether every byte reached the file. The bench programs use them next to runGnuplot()
/// (gnuplot.h).
///
/// Thread-safety: createReportFolder() is reentrant; a ReportFile is thread-bound. Not real-time
/// safe (file system calls, allocation).

#include <cstdio>
#include <sstream>
#include <string>

#include "depthtouch/platform/file_access.h"
#include "depthtouch/platform/macros.h"

namespace depthtouch::platform {

/// \brief Creates the folder \a dir and its missing parents; an existing folder is fine.
/// \param[in] dir the folder's path.
/// \return "" on success, else the system's reason (std::error_code message, e.g. "Permission
/// denied"), for the caller to put into its own message.
std::string createReportFolder(const std::string &dir);

/// \brief createReportFolder() for a writer that reports failures through an error text.
/// \param[in] dir the folder's path.
/// \param[in] what how the message names the failure, e.g. "cannot create 'out'".
/// \param[out] error on failure: "WHAT: REASON" (REASON as createReportFolder() gives it).
/// \return true when the folder exists.
bool createReportFolder(const std::string &dir, const std::string &what, std::string &error);

/// \brief One text file, written under a temporary name beside it and renamed into place by a
/// successful close() (OutputFile): never a cut file under its name. Writes after a failed open or
/// a failed write are skipped; close() reports either.
class ReportFile {
public:
    /// \brief Opens \a path for writing (a failure shows in isOpen() and close()).
    explicit ReportFile(const std::string &path);
    /// \brief Drops the file if close() was not called (its temporary file is removed).
    ~ReportFile() = default;
    DT_DISABLE_COPY_AND_MOVE(ReportFile)

    /// \return true while the file is open for writing.
    [[nodiscard]] bool isOpen() const noexcept { return file_.isOpen(); }

    /// \brief Appends printf-formatted text; does nothing when the file is not open.
    /// \param[in] format a printf format string (checked by the compiler), then its arguments.
    void print(const char *format, ...) noexcept __attribute__((format(printf, 2, 3)));

    /// \brief Closes the file and renames it into place.
    /// \return true when it had opened, every write went through and the close and rename
    /// succeeded; false otherwise (also on a second call).
    [[nodiscard]] bool close() noexcept;

private:
    OutputFile file_;
};

/// \brief One text file of a report, made in memory (it is an std::ostream) and written whole by
/// close() or the destructor (writeOutputFile(): under a temporary name, renamed when complete):
/// a full disk never leaves a cut file under its name. A failure goes into the error text given
/// to the constructor (when it is still empty), for the writer to report.
class TextReportFile : public std::ostringstream {
public:
    /// \param[in] path the file's path. \param[out] error where a failure is said.
    TextReportFile(std::string path, std::string &error);
    /// \brief close(), if it was not called.
    ~TextReportFile() override;
    DT_DISABLE_COPY_AND_MOVE(TextReportFile)

    /// \brief Writes the file (once; later calls return the first outcome).
    /// \return true when it was written whole; false with the error text "cannot write 'PATH':
    /// REASON" set (unless it held an earlier failure).
    bool close();

private:
    std::string path_;
    std::string &error_;
    bool closed_ = false;
    bool written_ = false;
};

} // namespace depthtouch::platform
