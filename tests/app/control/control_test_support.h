#pragma once
// What the control tests share: the player they drive (a StateMachine over FakePlayerActions) and
// a client on a control socket.

#include <cstring>
#include <string>
#include <string_view>

#include <sys/socket.h>
#include <sys/un.h>

#include <gtest/gtest.h>

#include "app/player/fake_player_actions.h"
#include "depthtouch/platform/unique_fd.h"

namespace depthtouch::control {

/// A player of movie.mkv whose pipeline is a FakePlayerActions (it records every call).
struct FakePlayer {
    player::test::FakePlayerActions fake;
    player::StateMachine m{fake, player::test::movieSettings()};
};

/// \return a client connected to the Unix stream socket at \a path (a failed connect is a test
/// failure).
inline platform::UniqueFd connectClient(const std::string &path)
{
    platform::UniqueFd fd(::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0));
    sockaddr_un addr{};
    addr.sun_family = AF_UNIX;
    std::strncpy(addr.sun_path, path.c_str(), sizeof addr.sun_path - 1);
    EXPECT_EQ(::connect(fd.get(), reinterpret_cast<const sockaddr *>(&addr), sizeof addr), 0)
        << path;
    return fd;
}

/// Sends \a data on \a fd in one call (a shorter send is a test failure).
inline void sendAll(const platform::UniqueFd &fd, std::string_view data)
{
    ASSERT_EQ(::send(fd.get(), data.data(), data.size(), MSG_NOSIGNAL),
              static_cast<ssize_t>(data.size()));
}

} // namespace depthtouch::control
