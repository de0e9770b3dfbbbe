/* The real-time discipline of the haptic thread inside a process the tests do not build
 * (gst-launch-1.0 with the DepthTouch plugin), proven by interposition, as
 * tests/app/haptic_task/discipline_test.cpp proves it in its own program: loaded with LD_PRELOAD,
 * this library replaces malloc, calloc, realloc, free, aligned_alloc, posix_memalign and memalign
 * (forwarded to glibc's __libc_ functions), pthread_mutex_lock and _trylock, and write (forwarded
 * to the next definition). A thread named "dt-haptic" (platform::kHapticThread) is watched from its
 * first clock_nanosleep on, the servo loop's first wait for its period (platform/src/clock.cpp):
 * its start-up before that may allocate. At exit one line goes to stderr:
 *
 *   rt-watch: dt-haptic after its first wait: 0 allocations, 0 frees, 0 locks, 0 writes (1 thread)
 *
 * Thread-safety: the counters are atomic, the watch flag is per thread. glibc only; never loaded
 * under AddressSanitizer (it has its own allocator). */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <errno.h>
#include <pthread.h>
#include <stdio.h>
#include <string.h>
#include <sys/prctl.h>
#include <time.h>
#include <unistd.h>

void *__libc_malloc(size_t);
void *__libc_calloc(size_t, size_t);
void *__libc_realloc(void *, size_t);
void __libc_free(void *);
void *__libc_memalign(size_t, size_t);

static __thread int tWatched;
static unsigned long gAllocations, gFrees, gLocks, gWrites, gThreads;

static void countIf(unsigned long *counter)
{
    if (tWatched)
        __atomic_fetch_add(counter, 1, __ATOMIC_RELAXED);
}

typedef int (*MutexFn)(pthread_mutex_t *);
typedef ssize_t (*WriteFn)(int, const void *, size_t);
typedef int (*SleepFn)(clockid_t, int, const struct timespec *, struct timespec *);
static void *gRealLock, *gRealTryLock;
static void *gRealWrite;
static void *gRealSleep;

/* Looked up on first use: another library's constructor may lock a mutex before this one's runs. */
static void *next(void **slot, const char *name)
{
    void *f = __atomic_load_n(slot, __ATOMIC_ACQUIRE);
    if (f == NULL) {
        f = dlsym(RTLD_NEXT, name);
        __atomic_store_n(slot, f, __ATOMIC_RELEASE);
    }
    return f;
}
#define NEXT(slot, type, name) ((type)next(&(slot), name))

__attribute__((destructor)) static void report(void)
{
    char line[200];
    const int n = snprintf(
        line, sizeof line,
        "rt-watch: dt-haptic after its first wait: %lu allocations, %lu frees, "
        "%lu locks, %lu writes (%lu thread%s)\n",
        __atomic_load_n(&gAllocations, __ATOMIC_RELAXED),
        __atomic_load_n(&gFrees, __ATOMIC_RELAXED), __atomic_load_n(&gLocks, __ATOMIC_RELAXED),
        __atomic_load_n(&gWrites, __ATOMIC_RELAXED), __atomic_load_n(&gThreads, __ATOMIC_RELAXED),
        __atomic_load_n(&gThreads, __ATOMIC_RELAXED) == 1 ? "" : "s");
    tWatched = 0;
    if (n > 0)
        (void)NEXT(gRealWrite, WriteFn,
                   "write")(2, line, (size_t)n < sizeof line ? (size_t)n : sizeof line - 1);
}

int clock_nanosleep(clockid_t clock, int flags, const struct timespec *t, struct timespec *rest)
{
    if (!tWatched) {
        char name[16] = {0};
        if (prctl(PR_GET_NAME, name, 0, 0, 0) == 0 && strcmp(name, "dt-haptic") == 0) {
            tWatched = 1;
            __atomic_fetch_add(&gThreads, 1, __ATOMIC_RELAXED);
        }
    }
    return NEXT(gRealSleep, SleepFn, "clock_nanosleep")(clock, flags, t, rest);
}

void *malloc(size_t size)
{
    countIf(&gAllocations);
    return __libc_malloc(size);
}

void *calloc(size_t n, size_t size)
{
    countIf(&gAllocations);
    return __libc_calloc(n, size);
}

void *realloc(void *p, size_t size)
{
    countIf(&gAllocations);
    return __libc_realloc(p, size);
}

void free(void *p)
{
    if (p != NULL)
        countIf(&gFrees);
    __libc_free(p);
}

void *memalign(size_t alignment, size_t size)
{
    countIf(&gAllocations);
    return __libc_memalign(alignment, size);
}

void *aligned_alloc(size_t alignment, size_t size)
{
    countIf(&gAllocations);
    return __libc_memalign(alignment, size);
}

int posix_memalign(void **out, size_t alignment, size_t size)
{
    countIf(&gAllocations);
    void *p = __libc_memalign(alignment, size);
    if (p == NULL)
        return ENOMEM;
    *out = p;
    return 0;
}

int pthread_mutex_lock(pthread_mutex_t *m)
{
    countIf(&gLocks);
    return NEXT(gRealLock, MutexFn, "pthread_mutex_lock")(m);
}

int pthread_mutex_trylock(pthread_mutex_t *m)
{
    countIf(&gLocks);
    return NEXT(gRealTryLock, MutexFn, "pthread_mutex_trylock")(m);
}

ssize_t write(int fd, const void *buf, size_t n)
{
    countIf(&gWrites);
    return NEXT(gRealWrite, WriteFn, "write")(fd, buf, n);
}
