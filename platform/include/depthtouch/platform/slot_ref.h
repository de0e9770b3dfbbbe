#pragma once
/// \file
/// \brief SlotRef: the owning part of a handle to one slot of a pool (FixedPool::Handle, the
/// receiver's FrameHandle). Move-only; gives the slot back to its owner when reset or destroyed.
///
/// The header is C++17-clean.
///
/// Thread-safety: a SlotRef is thread-bound (hand it to another thread by moving it); reset() and
/// the destructor are as thread-safe and real-time safe as the owner's release().

#include <cstdint>
#include <utility>

#include "depthtouch/platform/macros.h"

namespace depthtouch::platform {

/// \brief A reference to slot \a slot() of an \a Owner, which gets it back through
/// `Owner::release(std::uint32_t slot) noexcept` (the owner befriends SlotRef<Owner> when that is
/// private). The owner must outlive the reference.
template <class Owner> class SlotRef {
public:
    /// An empty reference.
    SlotRef() noexcept = default;
    /// A reference to slot \a slot of \a owner.
    SlotRef(Owner *owner, std::uint32_t slot) noexcept : owner_(owner), slot_(slot) {}
    SlotRef(SlotRef &&other) noexcept
        : owner_(std::exchange(other.owner_, nullptr)), slot_(other.slot_)
    {
    }
    SlotRef &operator=(SlotRef &&other) noexcept
    {
        if (this != &other) {
            reset();
            owner_ = std::exchange(other.owner_, nullptr);
            slot_ = other.slot_;
        }
        return *this;
    }
    DT_DISABLE_COPY(SlotRef)
    ~SlotRef() { reset(); }

    /// Gives the slot back to its owner now; the reference becomes empty. No-op when empty.
    void reset() noexcept
    {
        if (owner_ != nullptr) {
            owner_->release(slot_);
            owner_ = nullptr;
        }
    }

    /// \return true when the reference holds a slot.
    explicit operator bool() const noexcept { return owner_ != nullptr; }
    /// \return the owner, or nullptr when empty.
    [[nodiscard]] Owner *owner() const noexcept { return owner_; }
    /// \return the slot. \pre not empty.
    [[nodiscard]] std::uint32_t slot() const noexcept { return slot_; }

private:
    Owner *owner_ = nullptr;
    std::uint32_t slot_ = 0;
};

} // namespace depthtouch::platform
