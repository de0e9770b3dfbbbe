#pragma once
/// \file
/// \brief The table of haptic renderers: one row per method, the one place that lists them.
/// `touch --method`, `play --method` (and its config file and control socket), `bench haptics`,
/// `bench feel` and `haptics_cost` read it; methodName(), parseMethod(),
/// RendererConfig::forMethod() and makeRenderer() (renderer.h) are answered from it. A new method
/// is one row here and its own files (docs/architecture.md §2, "The renderer table"), as a new
/// backend is one row of drivers/backends.cpp.
///
/// Thread-safety: the table is immutable (constant initialised); every function is reentrant.

#include <memory>
#include <span>
#include <string>
#include <string_view>

#include "depthtouch/haptics/renderer.h"

namespace depthtouch::haptics {

/// \brief One renderer method (what it is: the comment of its row in renderer_table.cpp).
struct RendererEntry {
    Method method;
    /// Its name on every command line, in config files and in outputs ("finger").
    const char *name;
    /// The paper's fixes (a), (b), (c) on (RendererConfig::correction, interpolation, safety):
    /// the methods that render depth video; off for the baselines.
    bool fixes;
    /// It renders friction and material tracks (RendererConfig::staticFriction, friction.h).
    bool friction;
    /// `bench feel` measures it when no --methods are named.
    bool feelByDefault;
    /// Constructs the renderer; \a maxWidth × \a maxHeight (pixels) is the largest frame it will
    /// see. May throw std::bad_alloc (makeRenderer() turns it into Errc::OutOfResources).
    std::unique_ptr<HapticRenderer> (*make)(const RendererConfig &config, int maxWidth,
                                            int maxHeight);
};

/// \return the rows, the default method (RendererConfig's player and `touch` default) first.
std::span<const RendererEntry> rendererTable() noexcept;
/// \return the row of \a method (every Method has one).
const RendererEntry &rendererEntry(Method method) noexcept;
/// \return the row named \a name, or null.
const RendererEntry *findRenderer(std::string_view name) noexcept;
/// \return the names joined for a message: "finger, ball, modified, proxy-graph or mesh-bvh"
/// (\a last "or"), or with \a separator only ("finger ball modified proxy-graph mesh-bvh" for a
/// choice list) when \a last is empty.
std::string rendererNames(std::string_view separator = ", ", std::string_view last = " or ");
/// \return the names separated by spaces, "finger ball modified proxy-graph mesh-bvh", in storage
/// that lives as long as the program (an option table's choice list). Allocates on the first call.
std::string_view rendererChoiceWords();

} // namespace depthtouch::haptics
