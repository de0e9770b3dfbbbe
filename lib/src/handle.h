#pragma once
/// \file
/// \brief The dt_handle of depthtouch/client.h, shared by the client API (client.cpp) and the
/// render API (render_gl.cpp): the options until dt_initialize(), then the player thread.
/// Thread-safety: its fields are guarded by its mutex (not what the player runs).

#include <memory>
#include <mutex>
#include <vector>

#include "client_options.h"
#include "event_queue.h"
#include "host_frames.h"
#include "player_thread.h"
#include "session.h"

/// The handle: the options until dt_initialize(), then the player thread.
struct dt_handle {
    std::mutex mutex; ///< Guards options, observers, render and player.
    depthtouch::cli::PlayOptions options = depthtouch::client::libraryDefaults();
    std::vector<depthtouch::client::ObserverSpec> observers; ///< Asked for before dt_initialize().
    depthtouch::client::EventQueue events;
    /// The render API's frames (dt_render_context_create() before dt_initialize()): the player
    /// draws for the host instead of opening its own display.
    std::shared_ptr<depthtouch::client::HostFrames> render;
    std::unique_ptr<depthtouch::client::PlayerThread> player;
};
