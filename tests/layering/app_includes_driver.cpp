// Layering probe: an app-layer translation unit that includes a driver header. It must NOT compile,
// because app libraries link only dt_hal and dt_platform (see tests/layering/CMakeLists.txt).
#include "depthtouch/drivers/backends.h"

int layeringProbe() { return 0; }
