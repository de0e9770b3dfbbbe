#pragma once
/// \file
/// \brief runGnuplot(): draws the charts of the benchmark programs by running `gnuplot SCRIPT`,
/// the one place where a program is started for that (no shell: the script path is passed as is).
///
/// Thread-safety: reentrant (each call starts and waits for its own child process). Not real-time
/// safe (fork/exec and wait).

#include <cstdint>
#include <string>

namespace depthtouch::platform {

/// \brief How a gnuplot run went.
enum class PlotStatus : std::uint8_t {
    Drawn,     ///< gnuplot ran the script and exited with status 0.
    NoGnuplot, ///< No gnuplot on the PATH (install gnuplot-nox).
    Failed,    ///< gnuplot ran but failed (its messages went to stderr), or could not be started.
};

/// \brief Runs `gnuplot SCRIPT` and waits for it. The script names its own output files.
/// \param[in] script path of a gnuplot script file.
/// \return the outcome; gnuplot's own messages go to this process's stderr.
PlotStatus runGnuplot(const std::string &script) noexcept;

/// \brief Runs `gnuplot SCRIPT` as runGnuplot(script), its stderr appended to the file \a messages
/// (created if missing) instead of this process's, so its warnings cannot land amid a printed
/// table. \return the outcome; Failed also when \a messages cannot be opened.
PlotStatus runGnuplot(const std::string &script, const std::string &messages) noexcept;

/// \return a one-line remark for the user about \a status ("" for Drawn), e.g. "gnuplot not found:
/// no PNG chart (install gnuplot-nox)". Static string.
const char *plotStatusNote(PlotStatus status) noexcept;

} // namespace depthtouch::platform
