#pragma once
/// \file
/// \brief Small macros shared by every layer. Thread-safety: not applicable (compile-time only).

/// Deletes the copy and move operations of \a Class (use in the private or protected section).
#define DT_DISABLE_COPY_AND_MOVE(Class)                                                            \
    Class(const Class &) = delete;                                                                 \
    Class &operator=(const Class &) = delete;                                                      \
    Class(Class &&) = delete;                                                                      \
    Class &operator=(Class &&) = delete;

/// Deletes the copy operations of \a Class, keeping the move operations.
#define DT_DISABLE_COPY(Class)                                                                     \
    Class(const Class &) = delete;                                                                 \
    Class &operator=(const Class &) = delete;
