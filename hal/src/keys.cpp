#include "depthtouch/hal/remote_input.h"

#include <strings.h>

#include <array>
#include <cctype>
#include <cstddef>

#include "depthtouch/platform/enum_names.h"

namespace depthtouch::hal {

namespace {

struct KeyEntry {
    Key key;
    const char *name; ///< Linux name, with the "KEY_" prefix.
};

// In code order (the Key values). keyFromCode() and allKeys() rely on the order.
constexpr KeyEntry kKeys[] = {
    {Key::Digit1, "KEY_1"},
    {Key::Digit2, "KEY_2"},
    {Key::Digit3, "KEY_3"},
    {Key::Digit4, "KEY_4"},
    {Key::Digit5, "KEY_5"},
    {Key::Digit6, "KEY_6"},
    {Key::Digit7, "KEY_7"},
    {Key::Digit8, "KEY_8"},
    {Key::Digit9, "KEY_9"},
    {Key::Digit0, "KEY_0"},
    {Key::Enter, "KEY_ENTER"},
    {Key::Up, "KEY_UP"},
    {Key::Left, "KEY_LEFT"},
    {Key::Right, "KEY_RIGHT"},
    {Key::Down, "KEY_DOWN"},
    {Key::Mute, "KEY_MUTE"},
    {Key::VolumeDown, "KEY_VOLUMEDOWN"},
    {Key::VolumeUp, "KEY_VOLUMEUP"},
    {Key::Power, "KEY_POWER"},
    {Key::Pause, "KEY_PAUSE"},
    {Key::Stop, "KEY_STOP"},
    {Key::Menu, "KEY_MENU"},
    {Key::Back, "KEY_BACK"},
    {Key::PlayPause, "KEY_PLAYPAUSE"},
    {Key::Rewind, "KEY_REWIND"},
    {Key::Exit, "KEY_EXIT"},
    {Key::Play, "KEY_PLAY"},
    {Key::FastForward, "KEY_FASTFORWARD"},
    {Key::Ok, "KEY_OK"},
    {Key::Info, "KEY_INFO"},
    {Key::Red, "KEY_RED"},
    {Key::Green, "KEY_GREEN"},
    {Key::Yellow, "KEY_YELLOW"},
    {Key::Blue, "KEY_BLUE"},
    {Key::ChannelUp, "KEY_CHANNELUP"},
    {Key::ChannelDown, "KEY_CHANNELDOWN"},
    {Key::Mode3d, "KEY_3D_MODE"},
};

constexpr std::size_t kKeyCount = sizeof(kKeys) / sizeof(kKeys[0]);

constexpr auto kKeyList = [] {
    std::array<Key, kKeyCount> out{};
    for (std::size_t i = 0; i < kKeyCount; ++i)
        out[i] = kKeys[i].key;
    return out;
}();

constexpr bool sortedByCode() noexcept
{
    for (std::size_t i = 1; i < kKeyCount; ++i)
        if (static_cast<int>(kKeys[i - 1].key) >= static_cast<int>(kKeys[i].key))
            return false;
    return true;
}
static_assert(sortedByCode(), "kKeys must be sorted by key code");

/// Compares \a name with a table name ignoring case, the "KEY_" prefix (optional in \a name) and
/// underscores (so "PlayPause" and "3d_mode" match).
bool nameMatches(const char *name, const char *tableName) noexcept
{
    if (strncasecmp(name, "KEY_", 4) == 0)
        name += 4;
    tableName += 4;
    for (;;) {
        while (*name == '_')
            ++name;
        while (*tableName == '_')
            ++tableName;
        if (*name == '\0' || *tableName == '\0')
            return *name == *tableName;
        const auto a = static_cast<unsigned char>(*name);
        const auto b = static_cast<unsigned char>(*tableName);
        if (std::tolower(a) != std::tolower(b))
            return false;
        ++name;
        ++tableName;
    }
}

} // namespace

const char *keyName(Key key) noexcept
{
    for (const KeyEntry &e : kKeys)
        if (e.key == key)
            return e.name;
    return "KEY_RESERVED";
}

Key keyFromName(const char *name) noexcept
{
    if (name == nullptr || *name == '\0')
        return Key::Unknown;
    for (const KeyEntry &e : kKeys)
        if (nameMatches(name, e.name))
            return e.key;
    return Key::Unknown;
}

Key keyFromCode(int code) noexcept
{
    for (const KeyEntry &e : kKeys)
        if (static_cast<int>(e.key) == code)
            return e.key;
    return Key::Unknown;
}

const char *keyActionName(KeyAction action) noexcept
{
    static constexpr std::array<const char *, 3> kNames = {"press", "release", "repeat"};
    return platform::enumName(action, kNames, "press");
}

const Key *allKeys(std::size_t &count) noexcept
{
    count = kKeyList.size();
    return kKeyList.data();
}

} // namespace depthtouch::hal
