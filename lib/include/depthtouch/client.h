/*
 * depthtouch/client.h: the C client API of libdepthtouch (libdepthtouch.so.0): the player of
 * `depthtouch play` (stereo video and the 1 kHz haptic task) embedded in another program.
 *
 * Modelled on libmpv's client API (mpv's include/mpv/client.h, mpv 0.38, MPV_CLIENT_API_VERSION
 * 2.3): a handle made with dt_create(), options set before dt_initialize(), then commands,
 * properties and events. Names are the player's own: options are the long option names of
 * `depthtouch play` (docs/playing.md: "stiffness", "haptic", "display", "audio-device",
 * "no-audio", ...), checked by the same option table with the same ranges; properties and
 * commands are those of the control socket (docs/devices.md: "time-pos", "pause", "stiffness",
 * "haptic-force"; "loadfile", "seek", "play", "stop", ...). See docs/embedding.md.
 *
 * Conventions (as libmpv's):
 * - Every function that returns int returns >= 0 (DT_ERROR_SUCCESS) on success and a negative
 *   dt_error code otherwise. A NULL handle or a NULL/invalid argument is
 *   DT_ERROR_INVALID_PARAMETER; no call crashes on one and no C++ exception leaves the library.
 * - Strings are UTF-8, NUL-terminated. Strings the library returns (dt_get_property_string) are
 *   owned by the caller and must be freed with dt_free(). Strings passed in are copied; the caller
 *   keeps ownership.
 * - Thread-safety: every function may be called from any thread, concurrently, on the same handle
 *   (a mutex per handle serialises them), except: dt_terminate_destroy() must be the last call on
 *   a handle (no other call on it may run or follow), and dt_wait_event() should be called by one
 *   thread (the event it returns stays valid until the next dt_wait_event() or the destroy).
 *   The player runs on a thread of its own (and its render, decode and real-time haptic threads);
 *   a call that talks to the player waits for that thread to carry it out (a few milliseconds).
 * - Units: seconds for times and time-outs, N/m for stiffness, N for forces, percent for volume.
 *
 * This header is C99 and C++ compatible and declares nothing but dt_* names.
 */
#ifndef DEPTHTOUCH_CLIENT_H
#define DEPTHTOUCH_CLIENT_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#if defined(__GNUC__) || defined(__clang__)
#define DT_EXPORT __attribute__((visibility("default")))
#else
#define DT_EXPORT
#endif

/* The API version: major << 16 | minor. Minor grows when functions or enum values are added,
 * major when something changes incompatibly (as MPV_MAKE_VERSION). */
#define DT_MAKE_VERSION(major, minor) (((major) << 16) | (minor) | 0UL)
#define DT_CLIENT_API_VERSION DT_MAKE_VERSION(0, 1)

/* \return DT_CLIENT_API_VERSION of the library loaded (it may be newer than the header's). */
DT_EXPORT unsigned long dt_client_api_version(void);

/* The player: opaque. Made by dt_create(), ended by dt_terminate_destroy(). */
typedef struct dt_handle dt_handle;

/* Error codes: mpv's (mpv_error), same order and values, renamed; DT_ERROR_HAPTIC_INIT_FAILED is
 * the player's own. */
typedef enum dt_error {
    DT_ERROR_SUCCESS = 0,
    DT_ERROR_EVENT_QUEUE_FULL = -1,   /* the event queue overflowed (see DT_EVENT_QUEUE_OVERFLOW) */
    DT_ERROR_NOMEM = -2,              /* out of memory */
    DT_ERROR_UNINITIALIZED = -3,      /* needs dt_initialize(), or the player has shut down */
    DT_ERROR_INVALID_PARAMETER = -4,  /* NULL handle, NULL or malformed argument, unknown command */
    DT_ERROR_OPTION_NOT_FOUND = -5,   /* no such option */
    DT_ERROR_OPTION_FORMAT = -6,      /* the value does not parse or is out of the option's range */
    DT_ERROR_OPTION_ERROR = -7,       /* the option cannot be set now (after dt_initialize) */
    DT_ERROR_PROPERTY_NOT_FOUND = -8, /* no such property */
    DT_ERROR_PROPERTY_FORMAT = -9,    /* another format (a text read as a double) */
    DT_ERROR_PROPERTY_UNAVAILABLE = -10, /* no value now (time-pos, nothing open), read-only */
    DT_ERROR_PROPERTY_ERROR = -11,       /* the player refused the new value */
    DT_ERROR_COMMAND = -12,        /* the player refused the command (not valid in its state) */
    DT_ERROR_LOADING_FAILED = -13, /* the file or stream did not open (DT_EVENT_END_FILE) */
    DT_ERROR_AO_INIT_FAILED = -14, /* the sound output could not be opened */
    DT_ERROR_VO_INIT_FAILED = -15, /* the display could not be opened */
    DT_ERROR_NOTHING_TO_PLAY = -16,
    DT_ERROR_UNKNOWN_FORMAT = -17,
    DT_ERROR_UNSUPPORTED = -18,
    DT_ERROR_NOT_IMPLEMENTED = -19,
    DT_ERROR_GENERIC = -20,           /* any other failure */
    DT_ERROR_HAPTIC_INIT_FAILED = -21 /* the haptic device could not be opened */
} dt_error;

/* \return a static English text of \a error ("success", "invalid parameter", "property not
 * found", ... as mpv_error_string()); "unknown error" for a value that is no dt_error. Never NULL;
 * thread-safe. */
DT_EXPORT const char *dt_error_string(int error);

/* Frees memory the library returned (dt_get_property_string's text). NULL does nothing. */
DT_EXPORT void dt_free(void *data);

/* Value formats (mpv_format's values; the ones the player's properties take). */
typedef enum dt_format {
    DT_FORMAT_NONE = 0,   /* no value (an event of a property that is unavailable) */
    DT_FORMAT_STRING = 1, /* char *: "yes"/"no" for flags, "%.6f" for numbers, as mpv */
    DT_FORMAT_FLAG = 3,   /* int: 0 or 1 */
    DT_FORMAT_DOUBLE = 5  /* double */
} dt_format;

/* \brief Makes a player handle with play's defaults, not yet running (options may be set).
 * Differences from `depthtouch play`: no remote control by default (option "remote" = "none";
 * the terminal's keys are the host program's) and no summary or state lines on stderr.
 * \return the handle, or NULL when out of memory. Thread-safe. */
DT_EXPORT dt_handle *dt_create(void);

/* \brief Opens the backends the options name (display, haptic device, sound output, remote, the
 * control socket of option "control", the key map file of option "input-conf") and starts the
 * player's thread, idle: nothing plays until a "loadfile" or "play URL" command. Options are
 * checked as `play` checks them, and the player is `play`'s own (one player core): its outputs
 * (options "stats", "force-log", "record", ...) are written as `play` writes them, the stats JSON
 * at dt_terminate_destroy() or quit, of the last file opened.
 * \return DT_ERROR_SUCCESS; DT_ERROR_INVALID_PARAMETER (NULL handle, already initialized, a bad
 * output path, a control socket that cannot be made), DT_ERROR_VO_INIT_FAILED,
 * DT_ERROR_HAPTIC_INIT_FAILED, DT_ERROR_AO_INIT_FAILED, DT_ERROR_OPTION_FORMAT (a backend name or
 * its options refused, a key map file that does not read), DT_ERROR_GENERIC. On an error
 * the handle stays uninitialized (it may be destroyed, or initialized again). */
DT_EXPORT int dt_initialize(dt_handle *ctx);

/* \brief Stops the player (zero force first, as `play` does), joins its threads and frees the
 * handle. Events not read are lost. \a ctx must not be used afterwards; NULL does nothing. */
DT_EXPORT void dt_terminate_destroy(dt_handle *ctx);

/* \brief Sets option \a name (a long option name of `depthtouch play`, without dashes) to \a data
 * (its text as on the command line; flags take "yes"/"no", "true"/"false", "1"/"0" or "").
 * Before dt_initialize() only; afterwards an option that is also a property (stiffness, volume,
 * mute, loop) is set as dt_set_property_string() does.
 * \return DT_ERROR_SUCCESS; DT_ERROR_OPTION_NOT_FOUND (no such option, or one of the command line
 * only: url, config, no-config, show-config), DT_ERROR_OPTION_FORMAT (does not parse, or out of
 * the option's range: "stiffness" = "5000" refused as `play --stiffness 5000` is),
 * DT_ERROR_OPTION_ERROR (after dt_initialize, an option that is no property). */
DT_EXPORT int dt_set_option_string(dt_handle *ctx, const char *name, const char *data);

/* \brief Sends command \a args to the player: a NULL-terminated array of strings, the command's
 * name first, as on the control socket ({"seek", "10", NULL}, {"loadfile", "clip.mkv", NULL},
 * {"play", "clip.mkv", NULL}, {"pause", NULL}, {"stiffness", "1200", NULL}; mpv's verbs
 * get_property, set_property, cycle, add and keypress too). Waits until the player carried it out.
 * \return DT_ERROR_SUCCESS; DT_ERROR_INVALID_PARAMETER (NULL, an empty array, an unknown command
 * or bad arguments), DT_ERROR_COMMAND (refused in the player's state: "pause" while stopped),
 * DT_ERROR_UNINITIALIZED, or the property errors of mpv's verbs. */
DT_EXPORT int dt_command(dt_handle *ctx, const char **args);

/* \brief As dt_command(), without waiting: its outcome comes as a DT_EVENT_COMMAND_REPLY event
 * with \a reply_userdata and the error code. \return DT_ERROR_SUCCESS when it was queued. */
DT_EXPORT int dt_command_async(dt_handle *ctx, uint64_t reply_userdata, const char **args);

/* \brief Sets property \a name (a control socket property: "pause", "stiffness", "volume", "mute",
 * "loop", "loop-file", "haptics", "stereo-mode", "time-pos" (seeks), "percent-pos").
 * Before dt_initialize(), a name that is an option is set as dt_set_option_string() does.
 * \return DT_ERROR_SUCCESS; DT_ERROR_PROPERTY_NOT_FOUND, DT_ERROR_PROPERTY_FORMAT (the value does
 * not fit: "pause" = "maybe"), DT_ERROR_PROPERTY_UNAVAILABLE (read-only, or no value to set it
 * against), DT_ERROR_PROPERTY_ERROR (the player refused it: a stiffness out of range),
 * DT_ERROR_UNINITIALIZED, DT_ERROR_INVALID_PARAMETER. */
DT_EXPORT int dt_set_property_string(dt_handle *ctx, const char *name, const char *data);
DT_EXPORT int dt_set_property_double(dt_handle *ctx, const char *name, double data);
DT_EXPORT int dt_set_property_flag(dt_handle *ctx, const char *name, int data);

/* \brief Reads property \a name into \a out (a control socket property).
 * _string: a new text the caller frees with dt_free() (numbers as "%.6f", flags "yes"/"no");
 * _double: a number (time-pos, duration, percent-pos in s, s, %; stiffness N/m; haptic-force N;
 * volume %); _flag: 0 or 1 (pause, mute, loop, haptics, contact, idle-active, eof-reached,
 * haptic-device-connected, remote-connected).
 * \return DT_ERROR_SUCCESS; DT_ERROR_PROPERTY_NOT_FOUND, DT_ERROR_PROPERTY_FORMAT (another
 * format: "state" read as a double), DT_ERROR_PROPERTY_UNAVAILABLE (no value now: time-pos with
 * nothing open), DT_ERROR_UNINITIALIZED, DT_ERROR_INVALID_PARAMETER. \a out is unchanged on error.
 */
DT_EXPORT int dt_get_property_string(dt_handle *ctx, const char *name, char **out);
DT_EXPORT int dt_get_property_double(dt_handle *ctx, const char *name, double *out);
DT_EXPORT int dt_get_property_flag(dt_handle *ctx, const char *name, int *out);

/* \brief Asks for a DT_EVENT_PROPERTY_CHANGE event, with \a reply_userdata, each time property
 * \a name changes, in \a format (DT_FORMAT_STRING, _FLAG or _DOUBLE; DT_FORMAT_NONE: no value),
 * the first one at once. The player's thread samples it every 10 ms (a value that changes and
 * changes back between two samples sends nothing). At most 64 observers per handle. May be called
 * before dt_initialize(). \return DT_ERROR_SUCCESS; DT_ERROR_PROPERTY_NOT_FOUND,
 * DT_ERROR_INVALID_PARAMETER (NULL, a bad format, too many observers). */
DT_EXPORT int dt_observe_property(dt_handle *ctx, uint64_t reply_userdata, const char *name,
                                  dt_format format);

/* \brief Removes every observer of \a reply_userdata. \return how many were removed (>= 0), or
 * DT_ERROR_INVALID_PARAMETER. */
DT_EXPORT int dt_unobserve_property(dt_handle *ctx, uint64_t reply_userdata);

/* Events (mpv_event_id's values for the ones mpv has). */
typedef enum dt_event_id {
    DT_EVENT_NONE = 0,          /* dt_wait_event() timed out */
    DT_EVENT_SHUTDOWN = 1,      /* the player quit ("quit" command): call dt_terminate_destroy() */
    DT_EVENT_COMMAND_REPLY = 5, /* a dt_command_async() finished: error, reply_userdata */
    DT_EVENT_START_FILE = 6,    /* a file or stream starts opening */
    DT_EVENT_END_FILE = 7,      /* it ended: data is a dt_event_end_file */
    DT_EVENT_FILE_LOADED = 8,   /* it opened and plays (or is paused) */
    DT_EVENT_SEEK = 20,         /* a seek was carried out */
    DT_EVENT_PROPERTY_CHANGE = 22, /* an observed property changed: data is a dt_event_property */
    DT_EVENT_QUEUE_OVERFLOW = 24 /* events were dropped (oldest first): data is a uint64_t count */
} dt_event_id;

/* \return the name of \a event ("shutdown", "start-file", "end-file", "file-loaded",
 * "property-change", ... as mpv_event_name()), or NULL for an unknown value. */
DT_EXPORT const char *dt_event_name(dt_event_id event);

/* Why a file ended (mpv_end_file_reason's values). */
typedef enum dt_end_file_reason {
    DT_END_FILE_REASON_EOF = 0,  /* the end of the stream (or a live stream fell silent) */
    DT_END_FILE_REASON_STOP = 2, /* "stop", or another file loaded */
    DT_END_FILE_REASON_QUIT = 3, /* "quit" */
    DT_END_FILE_REASON_ERROR = 4 /* a failure: error says which (DT_ERROR_LOADING_FAILED, ...) */
} dt_end_file_reason;

typedef struct dt_event_end_file {
    int reason; /* dt_end_file_reason */
    int error;  /* with DT_END_FILE_REASON_ERROR: a dt_error; else 0 */
} dt_event_end_file;

typedef struct dt_event_property {
    const char *name; /* the property's name as observed */
    dt_format format; /* the observer's format, or DT_FORMAT_NONE when there is no value */
    void *data;       /* char ** (STRING), int * (FLAG), double * (DOUBLE), NULL (NONE) */
} dt_event_property;

typedef struct dt_event {
    dt_event_id event_id;
    int error;               /* COMMAND_REPLY: the command's result; else 0 */
    uint64_t reply_userdata; /* COMMAND_REPLY, PROPERTY_CHANGE: the caller's value; else 0 */
    void *data;              /* END_FILE, PROPERTY_CHANGE, QUEUE_OVERFLOW; else NULL */
} dt_event;

/* \brief Waits up to \a timeout_s seconds (0: do not wait; negative: without end) for the next
 * event. The queue holds at most 1000 events; when full, the oldest is dropped and a
 * DT_EVENT_QUEUE_OVERFLOW event (with the count) comes before the next one.
 * \return the event (DT_EVENT_NONE when none came), owned by the handle and valid until the next
 * dt_wait_event() or dt_terminate_destroy(); never NULL, also for a NULL handle (DT_EVENT_NONE with
 * error DT_ERROR_INVALID_PARAMETER, a static event). */
DT_EXPORT dt_event *dt_wait_event(dt_handle *ctx, double timeout_s);

/* \brief Makes a dt_wait_event() that waits return now (with DT_EVENT_NONE when nothing came).
 * Thread-safe. */
DT_EXPORT void dt_wakeup(dt_handle *ctx);

/* \brief Sets the function called, with \a d, whenever an event is queued (to wake the host's
 * own loop, which then calls dt_wait_event(ctx, 0) until DT_EVENT_NONE). It is called on any of
 * the library's threads, with the handle's event lock held: it must return quickly and call no
 * dt_* function. NULL removes it. */
DT_EXPORT void dt_set_wakeup_callback(dt_handle *ctx, void (*cb)(void *d), void *d);

#ifdef __cplusplus
}
#endif

#endif /* DEPTHTOUCH_CLIENT_H */
