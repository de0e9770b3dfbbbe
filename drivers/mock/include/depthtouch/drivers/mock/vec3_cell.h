#pragma once
/// \file
/// \brief Vec3Cell: a hal::Vec3 that one thread publishes and others read whole, on a
/// platform::SeqLockArray (the simulated haptic devices' output force and fingertip position).
///
/// Thread-safety: one writer thread at a time, any number of concurrent readers; store() is
/// wait-free, load() lock-free, neither allocates (real-time safe).

#include "depthtouch/hal/types.h"
#include "depthtouch/platform/seqlock.h"

namespace depthtouch::drivers {

class Vec3Cell {
public:
    /// Publishes \a v (single writer).
    void store(const hal::Vec3 &v) noexcept { cell_.store({v.x, v.y, v.z}); }
    /// \return the last complete store (zero before the first).
    [[nodiscard]] hal::Vec3 load() const noexcept
    {
        const auto a = cell_.load();
        return {a[0], a[1], a[2]};
    }

private:
    platform::SeqLockArray<3> cell_;
};

} // namespace depthtouch::drivers
