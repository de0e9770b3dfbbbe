/// \file
/// \brief The bounded event queue: see event_queue.h.

#include "event_queue.h"

#include <utility>

namespace depthtouch::client {

void EventQueue::push(QueuedEvent event)
{
    const std::lock_guard<std::mutex> lock(mutex_);
    if (queue_.size() >= kCapacity) {
        queue_.pop_front();
        ++dropped_;
        ++droppedUnsaid_;
    }
    queue_.push_back(std::move(event));
    cv_.notify_all();
    if (callback_ != nullptr)
        callback_(callbackData_);
}

dt_event *EventQueue::pop(double timeoutS)
{
    std::unique_lock<std::mutex> lock(mutex_);
    const auto ready = [this] { return !queue_.empty() || woken_ || droppedUnsaid_ > 0; };
    if (timeoutS < 0.0) {
        cv_.wait(lock, ready);
    } else if (timeoutS > 0.0) {
        // Bounded (a year): a duration beyond the clock's range would overflow.
        const double s = timeoutS < 3.15e7 ? timeoutS : 3.15e7;
        cv_.wait_for(lock, std::chrono::duration<double>(s), ready);
    }
    woken_ = false;
    current_ = QueuedEvent{};
    if (droppedUnsaid_ > 0) {
        current_.id = DT_EVENT_QUEUE_OVERFLOW;
        overflowCount_ = droppedUnsaid_;
        droppedUnsaid_ = 0;
    } else if (!queue_.empty()) {
        current_ = std::move(queue_.front());
        queue_.pop_front();
    }
    return present();
}

dt_event *EventQueue::present()
{
    event_ = dt_event{};
    event_.event_id = current_.id;
    event_.error = current_.error;
    event_.reply_userdata = current_.userdata;
    switch (current_.id) {
    case DT_EVENT_END_FILE:
        event_.data = &current_.endFile;
        break;
    case DT_EVENT_QUEUE_OVERFLOW:
        event_.data = &overflowCount_;
        break;
    case DT_EVENT_PROPERTY_CHANGE:
        property_.name = current_.name.c_str();
        property_.format = current_.format;
        property_.data = nullptr;
        if (current_.format == DT_FORMAT_STRING) {
            textPointer_ = current_.text.data();
            property_.data = &textPointer_;
        } else if (current_.format == DT_FORMAT_FLAG) {
            property_.data = &current_.flag;
        } else if (current_.format == DT_FORMAT_DOUBLE) {
            property_.data = &current_.number;
        }
        event_.data = &property_;
        break;
    default:
        break;
    }
    return &event_;
}

void EventQueue::wakeup()
{
    const std::lock_guard<std::mutex> lock(mutex_);
    woken_ = true;
    cv_.notify_all();
}

void EventQueue::setCallback(void (*cb)(void *), void *data)
{
    const std::lock_guard<std::mutex> lock(mutex_);
    callback_ = cb;
    callbackData_ = data;
}

std::uint64_t EventQueue::dropped() const
{
    const std::lock_guard<std::mutex> lock(mutex_);
    return dropped_;
}

} // namespace depthtouch::client
