#include "depthtouch/haptics/renderer_table.h"

#include <new>

#include "depthtouch/haptics/ball_renderer.h"
#include "depthtouch/haptics/finger_renderer.h"
#include "depthtouch/haptics/mesh_bvh.h"

namespace depthtouch::haptics {

namespace {

std::unique_ptr<HapticRenderer> makeFinger(const RendererConfig &c, int, int)
{
    return std::make_unique<FingerRenderer>(c);
}

std::unique_ptr<HapticRenderer> makeBall(const RendererConfig &c, int, int)
{
    return std::make_unique<BallRenderer>(c);
}

std::unique_ptr<HapticRenderer> makeProxyGraph(const RendererConfig &c, int, int)
{
    return std::make_unique<ProxyGraphRenderer>(c);
}

std::unique_ptr<HapticRenderer> makeMeshBvh(const RendererConfig &c, int maxWidth, int maxHeight)
{
    return std::make_unique<MeshBvhRenderer>(c, maxWidth, maxHeight);
}

// The rows. The default first; the order is the one outputs list them in.
constexpr RendererEntry kTable[] = {
    // The fingertip proxy on the finger-scale surface (finger_renderer.h): the default.
    {Method::Finger, "finger", true, true, true, makeFinger},
    // The fingertip as a ball, one proxy solve on the ball-swept surface (ball_renderer.h).
    {Method::Ball, "ball", true, true, false, makeBall},
    // The paper's modified proxy graph, fixes (a)(b)(c) on (paper IV; renderer.h).
    {Method::Modified, "modified", true, true, true, makeProxyGraph},
    // Baseline: Walker & Salisbury's proxy graph on sample-and-hold frames, fixes off.
    {Method::ProxyGraph, "proxy-graph", false, true, true, makeProxyGraph},
    // Baseline: a triangle mesh and AABB tree rebuilt every frame (mesh_bvh.h), no friction.
    {Method::MeshBvh, "mesh-bvh", false, false, false, makeMeshBvh},
};

} // namespace

std::span<const RendererEntry> rendererTable() noexcept
{
    return kTable;
}

const RendererEntry &rendererEntry(Method method) noexcept
{
    for (const RendererEntry &e : kTable)
        if (e.method == method)
            return e;
    return kTable[0]; // every Method has a row (renderer_table_test)
}

const RendererEntry *findRenderer(std::string_view name) noexcept
{
    for (const RendererEntry &e : kTable)
        if (name == e.name)
            return &e;
    return nullptr;
}

std::string rendererNames(std::string_view separator, std::string_view last)
{
    std::string out;
    const std::size_t n = std::size(kTable);
    for (std::size_t i = 0; i < n; ++i) {
        if (i > 0)
            out += i + 1 == n && !last.empty() ? last : separator;
        out += kTable[i].name;
    }
    return out;
}

std::string_view rendererChoiceWords()
{
    static const std::string words = rendererNames(" ", "");
    return words;
}

const char *methodName(Method method) noexcept
{
    return rendererEntry(method).name;
}

Result<Method> parseMethod(std::string_view text) noexcept
{
    if (const RendererEntry *e = findRenderer(text))
        return e->method;
    return unexpected(Errc::InvalidArgument,
                      "unknown method (finger, ball, modified, proxy-graph or mesh-bvh)");
}

RendererConfig RendererConfig::forMethod(Method method) noexcept
{
    RendererConfig c;
    const bool fixes = rendererEntry(method).fixes;
    c.correction = fixes;
    c.interpolation = fixes;
    c.safety = fixes;
    return c;
}

Result<std::unique_ptr<HapticRenderer>> makeRenderer(Method method, const RendererConfig &config,
                                                     int maxWidth, int maxHeight)
{
    DT_TRY(config.validate());
    if (maxWidth < 2 || maxHeight < 2)
        return unexpected(Errc::InvalidArgument, "frame size must be at least 2x2");
    try {
        return rendererEntry(method).make(config, maxWidth, maxHeight);
    } catch (const std::bad_alloc &) { // only mesh-bvh allocates
        return unexpected(Errc::OutOfResources, "not enough memory for the mesh and its tree");
    }
}

} // namespace depthtouch::haptics
