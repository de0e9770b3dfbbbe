/// \file
/// \brief Output paths: see output_paths.h.

#include "output_paths.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

#include "commands.h"
#include "message_text.h"

namespace depthtouch::cli {

namespace {

OutputPathCheck refuse(int code, std::string_view option, const std::string &path,
                       const std::string &why)
{
    return {code, std::string(option) + " " + quotedText(path) + ": " + why};
}

} // namespace

OutputPathCheck checkOutputPath(std::string_view option, const std::string &path,
                                bool directoryIsLost)
{
    if (path.empty())
        return {};
    const std::filesystem::path p(path);
    const std::filesystem::path folder = p.has_parent_path() ? p.parent_path() : ".";
    struct stat st{};
    if (::stat(folder.c_str(), &st) != 0)
        return refuse(kExitBadInput, option, path,
                      "no folder " + quotedText(folder.string()) + " (" + std::strerror(errno) +
                          ")");
    if (!S_ISDIR(st.st_mode))
        return refuse(kExitBadInput, option, path,
                      quotedText(folder.string()) + " is not a folder");
    if (::stat(path.c_str(), &st) != 0)
        return {}; // a new file in an existing folder
    if (S_ISDIR(st.st_mode))
        return refuse(directoryIsLost ? kExitFailure : kExitBadInput, option, path,
                      "is a directory, not a file");
    if (S_ISREG(st.st_mode) || S_ISFIFO(st.st_mode))
        return {}; // a FIFO is left alone: opening it for writing would wait for a reader
    // A device: does it take a write at all? (/dev/null does, /dev/full does not.)
    const int fd = ::open(path.c_str(), O_WRONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0)
        return refuse(kExitFailure, option, path,
                      std::string("cannot write: ") + std::strerror(errno));
    const char none = 0;
    const bool writable = ::write(fd, &none, 0) >= 0;
    const int err = errno;
    ::close(fd);
    if (!writable)
        return refuse(kExitFailure, option, path,
                      std::string("cannot write: ") + std::strerror(err));
    return {};
}

} // namespace depthtouch::cli
