/* The C scenario of libdepthtouch's client API (client_c_scenario.c), called by client_test.cpp.
 * C and C++ compatible. */
#ifndef DT_TESTS_CLIENT_C_SCENARIO_H
#define DT_TESTS_CLIENT_C_SCENARIO_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Plays \a clip (a mock: URL) through the C API with the mock backends: options (refused ones
 * too), initialize, loadfile, observe and send pause, read time-pos, seek asynchronously, stop,
 * destroy. \return 0, or the failing line's number with its description in \a why (\a n bytes). */
int dt_test_c_scenario(const char *clip, char *why, size_t n);

#ifdef __cplusplus
}
#endif

#endif
