/// \file
/// \brief libdepthtouch's C client API (depthtouch/client.h), linked as the shared library: every
/// call on a NULL handle or a bad argument answers an error code with mpv's text; options before
/// dt_initialize() are play's (names, ranges); the C program of client_c_scenario.c plays a mock
/// clip; the event queue is bounded; quit ends in DT_EVENT_SHUTDOWN. No judgement by the wall
/// clock: waits are bounded polls for a state.

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "depthtouch/client.h"
#include "lib/client_c_scenario.h"

namespace {

/// A handle on the mock backends (no GL, no sound card, no device), initialized.
dt_handle *mockPlayer()
{
    dt_handle *h = dt_create();
    for (const char *name : {"display", "haptic", "source", "decoder"})
        EXPECT_EQ(dt_set_option_string(h, name, "mock"), 0) << name;
    EXPECT_EQ(dt_set_option_string(h, "no-audio", ""), 0);
    EXPECT_EQ(dt_initialize(h), 0);
    return h;
}

TEST(ClientApiTest, everyCallOnANullHandleIsAnError)
{
    const char *args[] = {"pause", nullptr};
    double d = 0.0;
    int flag = 0;
    char *text = nullptr;
    EXPECT_EQ(dt_initialize(nullptr), DT_ERROR_INVALID_PARAMETER);
    EXPECT_EQ(dt_set_option_string(nullptr, "stiffness", "800"), DT_ERROR_INVALID_PARAMETER);
    EXPECT_EQ(dt_command(nullptr, args), DT_ERROR_INVALID_PARAMETER);
    EXPECT_EQ(dt_command_async(nullptr, 1, args), DT_ERROR_INVALID_PARAMETER);
    EXPECT_EQ(dt_set_property_string(nullptr, "pause", "yes"), DT_ERROR_INVALID_PARAMETER);
    EXPECT_EQ(dt_set_property_double(nullptr, "stiffness", 800.0), DT_ERROR_INVALID_PARAMETER);
    EXPECT_EQ(dt_set_property_flag(nullptr, "pause", 1), DT_ERROR_INVALID_PARAMETER);
    EXPECT_EQ(dt_get_property_string(nullptr, "state", &text), DT_ERROR_INVALID_PARAMETER);
    EXPECT_EQ(dt_get_property_double(nullptr, "time-pos", &d), DT_ERROR_INVALID_PARAMETER);
    EXPECT_EQ(dt_get_property_flag(nullptr, "pause", &flag), DT_ERROR_INVALID_PARAMETER);
    EXPECT_EQ(dt_observe_property(nullptr, 1, "pause", DT_FORMAT_FLAG), DT_ERROR_INVALID_PARAMETER);
    EXPECT_EQ(dt_unobserve_property(nullptr, 1), DT_ERROR_INVALID_PARAMETER);
    const dt_event *e = dt_wait_event(nullptr, 0.0);
    ASSERT_NE(e, nullptr);
    EXPECT_EQ(e->event_id, DT_EVENT_NONE);
    EXPECT_EQ(e->error, DT_ERROR_INVALID_PARAMETER);
    dt_wakeup(nullptr);
    dt_set_wakeup_callback(nullptr, nullptr, nullptr);
    dt_terminate_destroy(nullptr);
    dt_free(nullptr);
    EXPECT_EQ(text, nullptr);
}

TEST(ClientApiTest, everyNullArgumentIsAnError)
{
    dt_handle *h = dt_create();
    ASSERT_NE(h, nullptr);
    const char *empty[] = {nullptr};
    double d = 0.0;
    EXPECT_EQ(dt_set_option_string(h, nullptr, "1"), DT_ERROR_INVALID_PARAMETER);
    EXPECT_EQ(dt_set_option_string(h, "stiffness", nullptr), DT_ERROR_INVALID_PARAMETER);
    EXPECT_EQ(dt_command(h, nullptr), DT_ERROR_INVALID_PARAMETER);
    EXPECT_EQ(dt_command(h, empty), DT_ERROR_INVALID_PARAMETER);
    EXPECT_EQ(dt_command_async(h, 1, empty), DT_ERROR_INVALID_PARAMETER);
    EXPECT_EQ(dt_set_property_string(h, nullptr, "x"), DT_ERROR_INVALID_PARAMETER);
    EXPECT_EQ(dt_set_property_string(h, "pause", nullptr), DT_ERROR_INVALID_PARAMETER);
    EXPECT_EQ(dt_set_property_double(h, nullptr, 1.0), DT_ERROR_INVALID_PARAMETER);
    EXPECT_EQ(dt_get_property_string(h, "state", nullptr), DT_ERROR_INVALID_PARAMETER);
    EXPECT_EQ(dt_get_property_double(h, nullptr, &d), DT_ERROR_INVALID_PARAMETER);
    EXPECT_EQ(dt_get_property_flag(h, "pause", nullptr), DT_ERROR_INVALID_PARAMETER);
    EXPECT_EQ(dt_observe_property(h, 1, nullptr, DT_FORMAT_FLAG), DT_ERROR_INVALID_PARAMETER);
    EXPECT_EQ(dt_observe_property(h, 1, "pause", static_cast<dt_format>(2)),
              DT_ERROR_INVALID_PARAMETER);
    EXPECT_EQ(dt_observe_property(h, 1, "no-such-property", DT_FORMAT_FLAG),
              DT_ERROR_PROPERTY_NOT_FOUND);
    // Before dt_initialize: commands and properties wait for the player.
    const char *pause[] = {"pause", nullptr};
    EXPECT_EQ(dt_command(h, pause), DT_ERROR_UNINITIALIZED);
    EXPECT_EQ(dt_get_property_double(h, "time-pos", &d), DT_ERROR_UNINITIALIZED);
    EXPECT_EQ(dt_get_property_double(h, "no-such-property", &d), DT_ERROR_PROPERTY_NOT_FOUND);
    EXPECT_EQ(dt_set_property_string(h, "pause", "yes"), DT_ERROR_UNINITIALIZED);
    EXPECT_EQ(dt_wait_event(h, 0.0)->event_id, DT_EVENT_NONE);
    dt_terminate_destroy(h);
}

TEST(ClientApiTest, errorStringsAreMpvs)
{
    EXPECT_STREQ(dt_error_string(DT_ERROR_SUCCESS), "success");
    EXPECT_STREQ(dt_error_string(DT_ERROR_INVALID_PARAMETER), "invalid parameter");
    EXPECT_STREQ(dt_error_string(DT_ERROR_UNINITIALIZED), "core not initialized");
    EXPECT_STREQ(dt_error_string(DT_ERROR_OPTION_NOT_FOUND), "option not found");
    EXPECT_STREQ(dt_error_string(DT_ERROR_PROPERTY_NOT_FOUND), "property not found");
    EXPECT_STREQ(dt_error_string(DT_ERROR_PROPERTY_UNAVAILABLE), "property unavailable");
    EXPECT_STREQ(dt_error_string(DT_ERROR_PROPERTY_FORMAT),
                 "unsupported format for accessing property");
    EXPECT_STREQ(dt_error_string(DT_ERROR_COMMAND), "error running command");
    EXPECT_STREQ(dt_error_string(DT_ERROR_LOADING_FAILED), "loading failed");
    for (int code = DT_ERROR_SUCCESS; code >= DT_ERROR_HAPTIC_INIT_FAILED; --code)
        EXPECT_STRNE(dt_error_string(code), "unknown error") << code;
    EXPECT_STREQ(dt_error_string(1), "unknown error");
    EXPECT_STREQ(dt_error_string(-1000), "unknown error");
    EXPECT_STREQ(dt_event_name(DT_EVENT_PROPERTY_CHANGE), "property-change");
    EXPECT_STREQ(dt_event_name(DT_EVENT_END_FILE), "end-file");
    EXPECT_EQ(dt_client_api_version(), DT_CLIENT_API_VERSION);
}

TEST(ClientApiTest, optionsAreThoseOfPlayWithItsRanges)
{
    dt_handle *h = dt_create();
    EXPECT_EQ(dt_set_option_string(h, "stiffness", "3000"), 0);
    EXPECT_EQ(dt_set_option_string(h, "stiffness", "3000.5"), DT_ERROR_OPTION_FORMAT);
    EXPECT_EQ(dt_set_option_string(h, "stiffness", "99"), DT_ERROR_OPTION_FORMAT);
    EXPECT_EQ(dt_set_option_string(h, "stiffness", "1e999"), DT_ERROR_OPTION_FORMAT);
    EXPECT_EQ(dt_set_option_string(h, "stiffness", "800 N/m"), DT_ERROR_OPTION_FORMAT);
    EXPECT_EQ(dt_set_option_string(h, "rate", "99"), DT_ERROR_OPTION_FORMAT);
    EXPECT_EQ(dt_set_option_string(h, "reengage", "sometimes"), DT_ERROR_OPTION_FORMAT);
    EXPECT_EQ(dt_set_option_string(h, "reengage", "release"), 0);
    EXPECT_EQ(dt_set_option_string(h, "snapshot-every", "-1"), DT_ERROR_OPTION_FORMAT);
    EXPECT_EQ(dt_set_option_string(h, "record-crf", "52"), DT_ERROR_OPTION_FORMAT);
    EXPECT_EQ(dt_set_option_string(h, "no-audio", "maybe"), DT_ERROR_OPTION_FORMAT);
    EXPECT_EQ(dt_set_option_string(h, "no-audio", "no"), 0);
    EXPECT_EQ(dt_set_option_string(h, "duration", "-1"), DT_ERROR_OPTION_FORMAT);
    EXPECT_EQ(dt_set_option_string(h, "audio-device", "null"), 0);
    EXPECT_EQ(dt_set_option_string(h, "--stiffness", "800"), DT_ERROR_OPTION_NOT_FOUND);
    // The command line's own: the input is loadfile's, config files are the host's business.
    for (const char *name : {"url", "config", "no-config", "show-config"})
        EXPECT_EQ(dt_set_option_string(h, name, "x"), DT_ERROR_OPTION_NOT_FOUND) << name;
    // A property that is an option, before dt_initialize: the option.
    EXPECT_EQ(dt_set_property_double(h, "stiffness", 5000.0), DT_ERROR_OPTION_FORMAT);
    EXPECT_EQ(dt_set_property_double(h, "volume", 50.0), 0);
    EXPECT_EQ(dt_set_property_flag(h, "mute", 1), 0);
    dt_terminate_destroy(h);
}

TEST(ClientApiTest, aBackendThatIsNotThereFailsInitialize)
{
    dt_handle *h = dt_create();
    EXPECT_EQ(dt_set_option_string(h, "display", "no-such-display"), 0);
    const int rc = dt_initialize(h);
    EXPECT_LT(rc, 0);
    EXPECT_STRNE(dt_error_string(rc), "unknown error");
    // Still usable: a good option, and it starts.
    EXPECT_EQ(dt_set_option_string(h, "display", "mock"), 0);
    EXPECT_EQ(dt_set_option_string(h, "haptic", "none"), 0);
    EXPECT_EQ(dt_set_option_string(h, "no-audio", "yes"), 0);
    EXPECT_EQ(dt_initialize(h), 0);
    dt_terminate_destroy(h);
}

TEST(ClientApiTest, aCProgramPlaysAMockClip)
{
    char why[256] = "";
    const int line = dt_test_c_scenario("mock://clip?frames=60&fps=30", why, sizeof why);
    EXPECT_EQ(line, 0) << "client_c_scenario.c:" << line << ": " << why;
}

/// \return the first END_FILE within 60 waits of 1 s (other events skipped), or nullptr.
const dt_event_end_file *waitForEndFile(dt_handle *h)
{
    for (int waits = 0; waits < 60;) {
        const dt_event *e = dt_wait_event(h, 1.0);
        if (e->event_id == DT_EVENT_END_FILE)
            return static_cast<const dt_event_end_file *>(e->data);
        if (e->event_id == DT_EVENT_NONE)
            ++waits;
    }
    return nullptr;
}

TEST(ClientApiTest, endFileSaysWhyAndThePlayerStaysUp)
{
    dt_handle *h = mockPlayer();
    // A clip of a third of a second, without loop: its end.
    const char *shortClip[] = {"loadfile", "mock://clip?frames=10&fps=30", nullptr};
    ASSERT_EQ(dt_command(h, shortClip), 0);
    const dt_event_end_file *end = waitForEndFile(h);
    ASSERT_NE(end, nullptr);
    EXPECT_EQ(end->reason, DT_END_FILE_REASON_EOF);
    EXPECT_EQ(end->error, 0);
    int eof = 0;
    EXPECT_EQ(dt_get_property_flag(h, "eof-reached", &eof), 0);
    EXPECT_EQ(eof, 1);
    // An input that does not open: an error, and the player takes the next one.
    const char *missing[] = {"loadfile", "/nonexistent/clip.mkv", nullptr};
    ASSERT_EQ(dt_command(h, missing), 0);
    end = waitForEndFile(h);
    ASSERT_NE(end, nullptr);
    EXPECT_EQ(end->reason, DT_END_FILE_REASON_ERROR);
    EXPECT_EQ(end->error, DT_ERROR_LOADING_FAILED);
    ASSERT_EQ(dt_command(h, shortClip), 0);
    end = waitForEndFile(h);
    ASSERT_NE(end, nullptr);
    EXPECT_EQ(end->reason, DT_END_FILE_REASON_EOF);
    dt_terminate_destroy(h);
}

TEST(ClientApiTest, callsFromManyThreadsAtOnceAreEachCarriedOut)
{
    dt_handle *h = mockPlayer();
    ASSERT_EQ(dt_observe_property(h, 3, "stiffness", DT_FORMAT_DOUBLE), 0);
    constexpr int kThreads = 4;
    constexpr int kCalls = 200;
    std::vector<int> failures(kThreads, 0);
    std::vector<std::thread> threads;
    for (int t = 0; t < kThreads; ++t) {
        threads.emplace_back([h, t, &failures] {
            for (int i = 0; i < kCalls; ++i) {
                double d = 0.0;
                const double k = 200.0 + 100.0 * t;
                failures[static_cast<std::size_t>(t)] +=
                    (dt_set_property_double(h, "stiffness", k) != 0) +
                    (dt_get_property_double(h, "stiffness", &d) != 0);
                const char *get[] = {"get_property", "state", nullptr};
                failures[static_cast<std::size_t>(t)] +=
                    dt_command_async(h, static_cast<std::uint64_t>(i), get) != 0;
            }
        });
    }
    int events = 0;
    for (int i = 0; i < 100; ++i)
        events += dt_wait_event(h, 0.0)->event_id != DT_EVENT_NONE;
    for (std::thread &t : threads)
        t.join();
    for (int t = 0; t < kThreads; ++t)
        EXPECT_EQ(failures[static_cast<std::size_t>(t)], 0) << "thread " << t;
    double k = 0.0;
    EXPECT_EQ(dt_get_property_double(h, "stiffness", &k), 0);
    EXPECT_GE(k, 200.0);
    EXPECT_LE(k, 500.0);
    (void)events;
    dt_terminate_destroy(h);
}

TEST(ClientApiTest, theEventQueueIsBoundedAndSaysWhatItDropped)
{
    dt_handle *h = mockPlayer();
    const char *get[] = {"get_property", "state", nullptr};
    constexpr int kSent = 1500;
    for (int i = 0; i < kSent; ++i)
        ASSERT_EQ(dt_command_async(h, static_cast<std::uint64_t>(i + 1), get), 0);
    // A synchronous call runs after every queued one: all replies are queued by now.
    double d = 0.0;
    EXPECT_EQ(dt_get_property_double(h, "stiffness", &d), 0);
    dt_event *e = dt_wait_event(h, 0.0);
    ASSERT_EQ(e->event_id, DT_EVENT_QUEUE_OVERFLOW);
    const std::uint64_t dropped = *static_cast<const std::uint64_t *>(e->data);
    EXPECT_GE(dropped, 500u);
    int replies = 0;
    std::uint64_t last = 0;
    for (e = dt_wait_event(h, 0.0); e->event_id != DT_EVENT_NONE; e = dt_wait_event(h, 0.0)) {
        if (e->event_id != DT_EVENT_COMMAND_REPLY)
            continue;
        EXPECT_EQ(e->error, 0);
        EXPECT_GT(e->reply_userdata, last); // in order, the oldest dropped
        last = e->reply_userdata;
        ++replies;
    }
    EXPECT_LE(replies, 1000);
    EXPECT_EQ(last, static_cast<std::uint64_t>(kSent));
    dt_terminate_destroy(h);
}

/// A folder of its own under the temporary one, removed at the end.
struct TempDir {
    TempDir()
    {
        char pattern[] = "/tmp/dt_client_XXXXXX";
        path = ::mkdtemp(pattern) != nullptr ? pattern : "";
    }
    ~TempDir()
    {
        std::error_code ec;
        std::filesystem::remove_all(path, ec);
    }
    TempDir(const TempDir &) = delete;
    TempDir &operator=(const TempDir &) = delete;
    std::string path;
};

// The player is play's own (one player core): option "stats" writes play's stats JSON when the
// player ends, of the last file it opened (the library accepted the option and wrote nothing).
TEST(ClientApiTest, theStatsOptionWritesPlaysStatsJsonOfTheLastFile)
{
    TempDir dir;
    ASSERT_FALSE(dir.path.empty());
    const std::string stats = dir.path + "/stats.json";
    dt_handle *h = dt_create();
    for (const char *name : {"display", "haptic", "source", "decoder"})
        ASSERT_EQ(dt_set_option_string(h, name, "mock"), 0) << name;
    ASSERT_EQ(dt_set_option_string(h, "no-audio", ""), 0);
    ASSERT_EQ(dt_set_option_string(h, "stats", stats.c_str()), 0);
    ASSERT_EQ(dt_initialize(h), 0);
    const char *url = "mock://clip?frames=10&fps=30";
    const char *load[] = {"loadfile", url, nullptr};
    ASSERT_EQ(dt_command(h, load), 0);
    const dt_event_end_file *end = waitForEndFile(h);
    ASSERT_NE(end, nullptr);
    EXPECT_EQ(end->reason, DT_END_FILE_REASON_EOF);
    EXPECT_FALSE(std::filesystem::exists(stats)) << "written when the player ends";
    dt_terminate_destroy(h);
    std::ifstream in(stats);
    ASSERT_TRUE(in.good()) << stats;
    const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
    ASSERT_FALSE(j.is_discarded());
    EXPECT_EQ(j.value("url", ""), url);
    EXPECT_EQ(j.value("display", ""), "mock");
    EXPECT_EQ(j.value("haptic_device", ""), "mock");
    EXPECT_EQ(j.value("frames_received", 0), 10) << "the clip's frames (its url's frames=10)";
    EXPECT_GT(j.value("frames_presented", 0), 0);
}

// Option "input-conf" is play's key map file: one that does not read fails dt_initialize() as a
// bad option, as `play --input-conf` exits 2 (the library ignored it).
TEST(ClientApiTest, theInputConfOptionIsReadAtInitialize)
{
    TempDir dir;
    ASSERT_FALSE(dir.path.empty());
    const std::string good = dir.path + "/good.conf";
    const std::string bad = dir.path + "/bad.conf";
    std::ofstream(good) << "# OK pauses\nKEY_SELECT cycle pause\n";
    std::ofstream(bad) << "KEY_FOO quit\n";
    for (const auto &[file, expected] :
         {std::pair{good, 0}, std::pair{bad, static_cast<int>(DT_ERROR_OPTION_FORMAT)},
          std::pair{dir.path + "/missing.conf", static_cast<int>(DT_ERROR_OPTION_FORMAT)}}) {
        dt_handle *h = dt_create();
        for (const char *name : {"display", "haptic", "source", "decoder"})
            ASSERT_EQ(dt_set_option_string(h, name, "mock"), 0) << name;
        ASSERT_EQ(dt_set_option_string(h, "no-audio", ""), 0);
        ASSERT_EQ(dt_set_option_string(h, "input-conf", file.c_str()), 0);
        EXPECT_EQ(dt_initialize(h), expected) << file;
        dt_terminate_destroy(h);
    }
}

TEST(ClientApiTest, theWakeupCallbackIsCalledForEachEvent)
{
    dt_handle *h = mockPlayer();
    int calls = 0;
    dt_set_wakeup_callback(
        h, [](void *d) { ++*static_cast<int *>(d); }, &calls);
    const char *get[] = {"get_property", "state", nullptr};
    ASSERT_EQ(dt_command_async(h, 9, get), 0);
    double d = 0.0;
    EXPECT_EQ(dt_get_property_double(h, "stiffness", &d), 0); // after the reply was queued
    dt_set_wakeup_callback(h, nullptr, nullptr);
    EXPECT_GE(calls, 1);
    dt_wakeup(h);
    dt_terminate_destroy(h);
}

TEST(ClientApiTest, quitEndsInShutdownAndLaterCallsAreRefused)
{
    dt_handle *h = mockPlayer();
    const char *quit[] = {"quit", nullptr};
    EXPECT_EQ(dt_command(h, quit), 0);
    bool shutdown = false;
    for (int waits = 0; waits < 60 && !shutdown; ++waits)
        shutdown = dt_wait_event(h, 1.0)->event_id == DT_EVENT_SHUTDOWN;
    EXPECT_TRUE(shutdown);
    double d = 0.0;
    EXPECT_EQ(dt_get_property_double(h, "stiffness", &d), DT_ERROR_UNINITIALIZED);
    EXPECT_EQ(dt_command(h, quit), DT_ERROR_UNINITIALIZED);
    dt_terminate_destroy(h);
}

} // namespace
