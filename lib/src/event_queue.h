#pragma once
/// \file
/// \brief The bounded event queue of a dt_handle (depthtouch/client.h): the player's thread pushes,
/// dt_wait_event() pops into storage the returned dt_event points into. When full the oldest event
/// is dropped and counted; the next pop returns DT_EVENT_QUEUE_OVERFLOW with the count first (as
/// mpv's MPV_EVENT_QUEUE_OVERFLOW). Reference: libmpv's mpv_wait_event(), mpv_wakeup(),
/// mpv_set_wakeup_callback().
/// Thread-safety: thread-safe (one mutex); the popped event belongs to the caller of pop() until
/// its next pop().

#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <mutex>
#include <string>

#include "depthtouch/client.h"

namespace depthtouch::client {

/// One queued event with the values its data points to.
struct QueuedEvent {
    dt_event_id id = DT_EVENT_NONE;
    int error = 0;
    std::uint64_t userdata = 0;
    dt_event_end_file endFile{};
    std::string name;                  ///< PROPERTY_CHANGE: the property.
    dt_format format = DT_FORMAT_NONE; ///< PROPERTY_CHANGE: the value's format (NONE: none).
    std::string text;                  ///< DT_FORMAT_STRING.
    int flag = 0;                      ///< DT_FORMAT_FLAG.
    double number = 0.0;               ///< DT_FORMAT_DOUBLE.
};

class EventQueue {
public:
    /// The most events held.
    static constexpr std::size_t kCapacity = 1000;

    /// Queues \a event (dropping the oldest when full) and calls the wakeup callback.
    void push(QueuedEvent event);
    /// \brief Waits up to \a timeoutS s (negative: without end) for an event or a wakeup().
    /// \return the event in storage owned by the queue, valid until the next pop().
    dt_event *pop(double timeoutS);
    /// Makes a waiting pop() return now.
    void wakeup();
    /// Sets the callback called by push() (under the queue's lock).
    void setCallback(void (*cb)(void *), void *data);
    /// Events dropped since the start.
    [[nodiscard]] std::uint64_t dropped() const;

private:
    /// Fills event_ from current_ (the pointers into it).
    dt_event *present();

    mutable std::mutex mutex_;
    std::condition_variable cv_;
    std::deque<QueuedEvent> queue_;
    std::uint64_t dropped_ = 0;       ///< All dropped.
    std::uint64_t droppedUnsaid_ = 0; ///< Dropped since the last QUEUE_OVERFLOW event.
    bool woken_ = false;
    void (*callback_)(void *) = nullptr;
    void *callbackData_ = nullptr;
    // The event last popped and what its data points to.
    QueuedEvent current_;
    dt_event event_{};
    dt_event_property property_{};
    char *textPointer_ = nullptr;
    std::uint64_t overflowCount_ = 0;
};

} // namespace depthtouch::client
