/// \file
/// \brief The C client API of libdepthtouch (depthtouch/client.h): the boundary. Every function
/// checks its arguments, catches every exception (std::bad_alloc: DT_ERROR_NOMEM, any other:
/// DT_ERROR_GENERIC) and hands the work to the handle's options (before dt_initialize) or to its
/// player thread (player_thread.h), which carries it out on the state machine (session.h).
/// Reference: libmpv's client.h (mpv 0.38) for the shape, the error codes and their texts.

#include "depthtouch/client.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <mutex>
#include <new>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "client_options.h"
#include "depthtouch/platform/log.h"
#include "event_queue.h"
#include "handle.h"
#include "player_thread.h"
#include "session.h"

using depthtouch::client::EventQueue;
using depthtouch::client::ObserverSpec;
using depthtouch::client::PlayerThread;
using depthtouch::client::PropertyValue;
using depthtouch::client::Session;

namespace {

/// The most arguments of a command (mpv's MP_CMD_MAX_ARGS).
constexpr std::size_t kMaxArgs = 100;
/// The most observers asked for before dt_initialize() (as after: session.cpp).
constexpr std::size_t kMaxObservers = 64;

/// \return \a f(), or the code of the exception it threw.
template <class F> int guarded(F &&f) noexcept
{
    try {
        return f();
    } catch (const std::bad_alloc &) {
        return DT_ERROR_NOMEM;
    } catch (...) {
        return DT_ERROR_GENERIC;
    }
}

/// \return the player thread of \a h, or nullptr before dt_initialize().
PlayerThread *playerOf(dt_handle *h)
{
    const std::lock_guard<std::mutex> lock(h->mutex);
    return h->player.get();
}

/// \return DT_ERROR_UNINITIALIZED for a property before dt_initialize(), else
/// DT_ERROR_PROPERTY_NOT_FOUND.
int notRunning(const std::string &name)
{
    return depthtouch::client::isPropertyName(name) ? DT_ERROR_UNINITIALIZED
                                                    : DT_ERROR_PROPERTY_NOT_FOUND;
}

/// dt_set_property_*() with \a value, or before dt_initialize() the option \a name set to \a text.
int setProperty(dt_handle *h, const char *name, const nlohmann::json &value,
                const std::string &text)
{
    const std::string n(name);
    PlayerThread *p = nullptr;
    {
        const std::lock_guard<std::mutex> lock(h->mutex);
        p = h->player.get();
        if (p == nullptr) {
            if (depthtouch::client::isOption(n))
                return depthtouch::client::setOptionString(h->options, n, text);
            return notRunning(n);
        }
    }
    return p->call([n, value](Session &s) { return s.setProperty(n, value); });
}

/// dt_get_property_*(): \a name in \a format into \a out.
int getProperty(dt_handle *h, const char *name, dt_format format, PropertyValue &out)
{
    const std::string n(name);
    PlayerThread *p = playerOf(h);
    if (p == nullptr)
        return notRunning(n);
    return p->call([n, format, &out](Session &s) { return s.getProperty(n, format, out); });
}

/// \return the words of \a args, or an empty list when there are none or too many.
std::vector<std::string> words(const char **args)
{
    std::vector<std::string> out;
    for (std::size_t i = 0; args[i] != nullptr; ++i) {
        if (i >= kMaxArgs)
            return {};
        out.emplace_back(args[i]);
    }
    return out;
}

bool isFormat(dt_format format)
{
    return format == DT_FORMAT_NONE || format == DT_FORMAT_STRING || format == DT_FORMAT_FLAG ||
           format == DT_FORMAT_DOUBLE;
}

} // namespace

extern "C" {

unsigned long dt_client_api_version(void)
{
    return DT_CLIENT_API_VERSION;
}

const char *dt_error_string(int error)
{
    switch (error) {
    case DT_ERROR_SUCCESS:
        return "success";
    case DT_ERROR_EVENT_QUEUE_FULL:
        return "event queue full";
    case DT_ERROR_NOMEM:
        return "memory allocation failed";
    case DT_ERROR_UNINITIALIZED:
        return "core not initialized";
    case DT_ERROR_INVALID_PARAMETER:
        return "invalid parameter";
    case DT_ERROR_OPTION_NOT_FOUND:
        return "option not found";
    case DT_ERROR_OPTION_FORMAT:
        return "unsupported format for accessing option";
    case DT_ERROR_OPTION_ERROR:
        return "error setting option";
    case DT_ERROR_PROPERTY_NOT_FOUND:
        return "property not found";
    case DT_ERROR_PROPERTY_FORMAT:
        return "unsupported format for accessing property";
    case DT_ERROR_PROPERTY_UNAVAILABLE:
        return "property unavailable";
    case DT_ERROR_PROPERTY_ERROR:
        return "error accessing property";
    case DT_ERROR_COMMAND:
        return "error running command";
    case DT_ERROR_LOADING_FAILED:
        return "loading failed";
    case DT_ERROR_AO_INIT_FAILED:
        return "audio output initialization failed";
    case DT_ERROR_VO_INIT_FAILED:
        return "video output initialization failed";
    case DT_ERROR_NOTHING_TO_PLAY:
        return "no audio or video data played";
    case DT_ERROR_UNKNOWN_FORMAT:
        return "unrecognized file format";
    case DT_ERROR_UNSUPPORTED:
        return "not supported";
    case DT_ERROR_NOT_IMPLEMENTED:
        return "operation not implemented";
    case DT_ERROR_GENERIC:
        return "something happened";
    case DT_ERROR_HAPTIC_INIT_FAILED:
        return "haptic device initialization failed";
    default:
        return "unknown error";
    }
}

void dt_free(void *data)
{
    std::free(data);
}

dt_handle *dt_create(void)
{
    try {
        return new dt_handle();
    } catch (...) {
        return nullptr;
    }
}

int dt_initialize(dt_handle *ctx)
{
    if (ctx == nullptr)
        return DT_ERROR_INVALID_PARAMETER;
    return guarded([ctx]() -> int {
        const std::lock_guard<std::mutex> lock(ctx->mutex);
        if (ctx->player)
            return DT_ERROR_INVALID_PARAMETER;
        // As `play`: the log's lines only when asked for (option verbose, or DT_LOG's levels).
        if (std::getenv("DT_LOG") == nullptr)
            depthtouch::platform::setLogLevel(ctx->options.verbose
                                                  ? depthtouch::platform::LogLevel::Info
                                                  : depthtouch::platform::LogLevel::Off);
        return PlayerThread::start(ctx->options, ctx->observers, ctx->render, ctx->events,
                                   ctx->player);
    });
}

void dt_terminate_destroy(dt_handle *ctx)
{
    if (ctx == nullptr)
        return;
    try {
        ctx->player.reset(); // quits, stops playback, joins
    } catch (...) {
        // A thread that cannot be joined: nothing more can be done here.
    }
    delete ctx;
}

int dt_set_option_string(dt_handle *ctx, const char *name, const char *data)
{
    if (ctx == nullptr || name == nullptr || data == nullptr)
        return DT_ERROR_INVALID_PARAMETER;
    return guarded([&]() -> int {
        const std::string n(name);
        {
            const std::lock_guard<std::mutex> lock(ctx->mutex);
            if (!ctx->player)
                return depthtouch::client::setOptionString(ctx->options, n, data);
        }
        if (!depthtouch::client::isOption(n))
            return DT_ERROR_OPTION_NOT_FOUND;
        if (!depthtouch::client::isPropertyName(n))
            return DT_ERROR_OPTION_ERROR;
        return dt_set_property_string(ctx, name, data);
    });
}

int dt_command(dt_handle *ctx, const char **args)
{
    if (ctx == nullptr || args == nullptr || args[0] == nullptr)
        return DT_ERROR_INVALID_PARAMETER;
    return guarded([&]() -> int {
        std::vector<std::string> w = words(args);
        if (w.empty())
            return DT_ERROR_INVALID_PARAMETER;
        PlayerThread *p = playerOf(ctx);
        if (p == nullptr)
            return DT_ERROR_UNINITIALIZED;
        return p->call([w = std::move(w)](Session &s) { return s.command(w); });
    });
}

int dt_command_async(dt_handle *ctx, uint64_t reply_userdata, const char **args)
{
    if (ctx == nullptr || args == nullptr || args[0] == nullptr)
        return DT_ERROR_INVALID_PARAMETER;
    return guarded([&]() -> int {
        std::vector<std::string> w = words(args);
        if (w.empty())
            return DT_ERROR_INVALID_PARAMETER;
        PlayerThread *p = playerOf(ctx);
        if (p == nullptr)
            return DT_ERROR_UNINITIALIZED;
        return p->post(reply_userdata, [w = std::move(w)](Session &s) { return s.command(w); });
    });
}

int dt_set_property_string(dt_handle *ctx, const char *name, const char *data)
{
    if (ctx == nullptr || name == nullptr || data == nullptr)
        return DT_ERROR_INVALID_PARAMETER;
    return guarded([&]() -> int { return setProperty(ctx, name, nlohmann::json(data), data); });
}

int dt_set_property_double(dt_handle *ctx, const char *name, double data)
{
    if (ctx == nullptr || name == nullptr || !std::isfinite(data))
        return DT_ERROR_INVALID_PARAMETER;
    return guarded([&]() -> int {
        char text[64];
        std::snprintf(text, sizeof text, "%.17g", data);
        return setProperty(ctx, name, nlohmann::json(data), text);
    });
}

int dt_set_property_flag(dt_handle *ctx, const char *name, int data)
{
    if (ctx == nullptr || name == nullptr)
        return DT_ERROR_INVALID_PARAMETER;
    return guarded([&]() -> int {
        return setProperty(ctx, name, nlohmann::json(data != 0), data != 0 ? "yes" : "no");
    });
}

int dt_get_property_string(dt_handle *ctx, const char *name, char **out)
{
    if (ctx == nullptr || name == nullptr || out == nullptr)
        return DT_ERROR_INVALID_PARAMETER;
    return guarded([&]() -> int {
        PropertyValue v;
        if (const int rc = getProperty(ctx, name, DT_FORMAT_STRING, v); rc < 0)
            return rc;
        char *copy = static_cast<char *>(std::malloc(v.text.size() + 1));
        if (copy == nullptr)
            return DT_ERROR_NOMEM;
        std::memcpy(copy, v.text.c_str(), v.text.size() + 1);
        *out = copy;
        return DT_ERROR_SUCCESS;
    });
}

int dt_get_property_double(dt_handle *ctx, const char *name, double *out)
{
    if (ctx == nullptr || name == nullptr || out == nullptr)
        return DT_ERROR_INVALID_PARAMETER;
    return guarded([&]() -> int {
        PropertyValue v;
        const int rc = getProperty(ctx, name, DT_FORMAT_DOUBLE, v);
        if (rc >= 0)
            *out = v.number;
        return rc;
    });
}

int dt_get_property_flag(dt_handle *ctx, const char *name, int *out)
{
    if (ctx == nullptr || name == nullptr || out == nullptr)
        return DT_ERROR_INVALID_PARAMETER;
    return guarded([&]() -> int {
        PropertyValue v;
        const int rc = getProperty(ctx, name, DT_FORMAT_FLAG, v);
        if (rc >= 0)
            *out = v.flag;
        return rc;
    });
}

int dt_observe_property(dt_handle *ctx, uint64_t reply_userdata, const char *name, dt_format format)
{
    if (ctx == nullptr || name == nullptr || !isFormat(format))
        return DT_ERROR_INVALID_PARAMETER;
    return guarded([&]() -> int {
        ObserverSpec spec;
        spec.userdata = reply_userdata;
        spec.name = name;
        spec.format = format;
        if (!depthtouch::client::isPropertyName(spec.name))
            return DT_ERROR_PROPERTY_NOT_FOUND;
        PlayerThread *p = nullptr;
        {
            const std::lock_guard<std::mutex> lock(ctx->mutex);
            p = ctx->player.get();
            if (p == nullptr) {
                if (ctx->observers.size() >= kMaxObservers)
                    return DT_ERROR_INVALID_PARAMETER;
                ctx->observers.push_back(std::move(spec));
                return DT_ERROR_SUCCESS;
            }
        }
        return p->call([spec](Session &s) { return s.observe(spec); });
    });
}

int dt_unobserve_property(dt_handle *ctx, uint64_t reply_userdata)
{
    if (ctx == nullptr)
        return DT_ERROR_INVALID_PARAMETER;
    return guarded([&]() -> int {
        PlayerThread *p = nullptr;
        {
            const std::lock_guard<std::mutex> lock(ctx->mutex);
            p = ctx->player.get();
            if (p == nullptr) {
                const auto before = ctx->observers.size();
                std::erase_if(ctx->observers, [reply_userdata](const ObserverSpec &o) {
                    return o.userdata == reply_userdata;
                });
                return static_cast<int>(before - ctx->observers.size());
            }
        }
        return p->call([reply_userdata](Session &s) { return s.unobserve(reply_userdata); });
    });
}

const char *dt_event_name(dt_event_id event)
{
    switch (event) {
    case DT_EVENT_NONE:
        return "none";
    case DT_EVENT_SHUTDOWN:
        return "shutdown";
    case DT_EVENT_COMMAND_REPLY:
        return "command-reply";
    case DT_EVENT_START_FILE:
        return "start-file";
    case DT_EVENT_END_FILE:
        return "end-file";
    case DT_EVENT_FILE_LOADED:
        return "file-loaded";
    case DT_EVENT_SEEK:
        return "seek";
    case DT_EVENT_PROPERTY_CHANGE:
        return "property-change";
    case DT_EVENT_QUEUE_OVERFLOW:
        return "event-queue-overflow";
    }
    return nullptr;
}

dt_event *dt_wait_event(dt_handle *ctx, double timeout_s)
{
    if (ctx == nullptr) {
        // Per thread: a caller that writes into it changes no other thread's answer.
        static thread_local dt_event invalid{};
        invalid = dt_event{};
        invalid.event_id = DT_EVENT_NONE;
        invalid.error = DT_ERROR_INVALID_PARAMETER;
        return &invalid;
    }
    try {
        return ctx->events.pop(std::isnan(timeout_s) ? 0.0 : timeout_s);
    } catch (...) {
        static thread_local dt_event failed{};
        failed = dt_event{};
        failed.error = DT_ERROR_GENERIC;
        return &failed;
    }
}

void dt_wakeup(dt_handle *ctx)
{
    if (ctx != nullptr)
        ctx->events.wakeup();
}

void dt_set_wakeup_callback(dt_handle *ctx, void (*cb)(void *d), void *d)
{
    if (ctx != nullptr)
        ctx->events.setCallback(cb, d);
}

} // extern "C"
