// Compiled with dt_render's usage requirements only: the renderer's headers build on the scene
// layer, and the haptic renderer's headers are not on the include path
// (layering_render_does_not_carry_haptics).
#include "depthtouch/render/renderer.h"
#include "depthtouch/scene/surface_mapping.h"

#if __has_include("depthtouch/haptics/height_field.h")
#error "dt_render carries dt_haptics: the renderer must depend on the scene layer only"
#endif

int dtLayeringRenderWithoutHaptics()
{
    return sizeof(depthtouch::scene::SurfaceMapping) > 0 ? 0 : 1;
}
