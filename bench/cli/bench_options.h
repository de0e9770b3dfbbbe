#pragma once
/// \file
/// \brief What several `depthtouch bench` commands share: the option rows (option_table.h) that
/// mean the same in each, written once (a bench's table takes the row for its own options struct,
/// which must have the field the row names), and the folder their `--data` names.
/// Thread-safety: reentrant (constant rows; sharedDataFolder() reads the environment).

#include <cstdlib>
#include <string>

#include "option_table.h"

namespace depthtouch::cli {

/// \return the `--out DIR` row: the folder a bench writes its CSV, JSON and charts into
/// (Options::out, a std::string).
template <class Options> constexpr OptionRow<Options> benchOutRow()
{
    return {"out", &Options::out, "Output directory"};
}

/// \return the `--data DIR` row: the shared RGB-D data folder, $DT_SHARED_DATA or ../shared/data
/// when empty (Options::data, a std::string).
template <class Options> constexpr OptionRow<Options> sharedDataRow()
{
    return {"data", &Options::data,
            "Shared RGB-D data folder (default: $DT_SHARED_DATA or ../shared/data)"};
}

/// \return the shared RGB-D data folder: \a data (a bench's `--data`) when given, else
/// $DT_SHARED_DATA when set, else "../shared/data".
inline std::string sharedDataFolder(const std::string &data)
{
    if (!data.empty())
        return data;
    const char *env = std::getenv("DT_SHARED_DATA");
    return env != nullptr ? env : "../shared/data";
}

/// \return the `--no-fifo` row: time the haptic work on a normal thread; sets Options::fifo (a
/// bool, true by default) false.
template <class Options> constexpr OptionRow<Options> noFifoRow()
{
    return {"no-fifo",
            &Options::fifo,
            "Time on a normal thread instead of a SCHED_FIFO one at the haptic priority",
            {},
            kNegated};
}

} // namespace depthtouch::cli
