/// \file
/// \brief Output paths: see output_paths.h.

#include "depthtouch/platform/output_paths.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <optional>

#include "depthtouch/platform/file_access.h"
#include "depthtouch/platform/message_text.h"

namespace depthtouch::platform {

namespace {

OutputPathCheck refuse(int code, std::string_view option, const std::string &path,
                       const std::string &why)
{
    return {code, std::string(option) + " " + quotedText(path) + ": " + why};
}

/// Checks that the existing folder \a folder takes new files.
OutputPathCheck folderTakesFiles(std::string_view option, const std::string &path,
                                 const std::string &folder)
{
    auto w = checkFolderWritable(folder);
    if (w)
        return {};
    std::string why = "cannot make a file in " + quotedText(folder);
    if (w.error().sysErrno != 0)
        why += std::string(" (") + std::strerror(w.error().sysErrno) + ")";
    return refuse(w.error().code == Errc::InvalidArgument ? kOutputBadInput : kOutputLost, option,
                  path, why);
}

bool isUrl(const std::string &path)
{
    return path.find("://") != std::string::npos;
}

/// The identity of \a p when it takes part in the comparison (see checkDistinctPaths()).
std::optional<FileIdentity> comparedIdentity(const NamedPath &p, bool input)
{
    if (p.path.empty() || isUrl(p.path))
        return std::nullopt;
    auto id = fileIdentity(p.path);
    if (!id)
        return std::nullopt;
    const bool newPath = !id->name.empty();
    if (input ? !id->regular : !(id->regular || newPath))
        return std::nullopt;
    return id;
}

} // namespace

OutputPathCheck checkOutputFolder(std::string_view option, const std::string &dir)
{
    if (dir.empty())
        return {};
    std::error_code ec;
    std::filesystem::path existing = std::filesystem::absolute(dir, ec);
    if (ec)
        return refuse(kOutputBadInput, option, dir, ec.message());
    // The folder is made with its missing parents: the nearest one that exists must take them.
    while (!std::filesystem::exists(existing, ec) && existing.has_parent_path() &&
           existing.parent_path() != existing)
        existing = existing.parent_path();
    if (!std::filesystem::is_directory(existing, ec))
        return refuse(kOutputBadInput, option, dir,
                      quotedText(existing.string()) + " is not a folder");
    return folderTakesFiles(option, dir, existing.string());
}

OutputPathCheck checkDistinctPaths(const std::vector<NamedPath> &inputs,
                                   const std::vector<NamedPath> &outputs)
{
    for (std::size_t i = 0; i < outputs.size(); ++i) {
        const NamedPath &out = outputs[i];
        const auto id = comparedIdentity(out, false);
        if (!id)
            continue;
        auto same = [&](const NamedPath &other) {
            return refuse(kOutputBadInput, out.option, out.path,
                          "is the same file as " + other.option + " " + quotedText(other.path));
        };
        for (const NamedPath &in : inputs)
            if (comparedIdentity(in, true) == id)
                return same(in);
        for (std::size_t j = 0; j < i; ++j)
            if (comparedIdentity(outputs[j], false) == id)
                return same(outputs[j]);
    }
    return {};
}

OutputPathCheck checkOutputPath(std::string_view option, const std::string &path,
                                bool directoryIsLost)
{
    if (path.empty())
        return {};
    const std::filesystem::path p(path);
    const std::filesystem::path folder = p.has_parent_path() ? p.parent_path() : ".";
    struct stat st {};
    if (::stat(folder.c_str(), &st) != 0)
        return refuse(kOutputBadInput, option, path,
                      "no folder " + quotedText(folder.string()) + " (" + std::strerror(errno) +
                          ")");
    if (!S_ISDIR(st.st_mode))
        return refuse(kOutputBadInput, option, path,
                      quotedText(folder.string()) + " is not a folder");
    if (::stat(path.c_str(), &st) != 0 || S_ISREG(st.st_mode))
        return folderTakesFiles(option, path, folder.string()); // written beside, then renamed
    if (S_ISDIR(st.st_mode))
        return refuse(directoryIsLost ? kOutputLost : kOutputBadInput, option, path,
                      "is a directory, not a file");
    if (S_ISFIFO(st.st_mode))
        return {}; // a FIFO is left alone: opening it for writing would wait for a reader
    // A device: does it take a write at all? (/dev/null does, /dev/full does not.)
    const int fd = ::open(path.c_str(), O_WRONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0)
        return refuse(kOutputLost, option, path,
                      std::string("cannot write: ") + std::strerror(errno));
    const char none = 0;
    const bool writable = ::write(fd, &none, 0) >= 0;
    const int err = errno;
    ::close(fd);
    if (!writable)
        return refuse(kOutputLost, option, path,
                      std::string("cannot write: ") + std::strerror(err));
    return {};
}

} // namespace depthtouch::platform
