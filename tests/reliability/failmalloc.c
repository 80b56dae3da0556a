/* An allocator that fails on purpose, for tests/reliability/test_alloc_failure.c.
 * Loaded with LD_PRELOAD into a plain (non-ASan) build: it wraps malloc,
 * calloc and realloc, and, while armed, counts their calls and makes the
 * n-th one return NULL (with errno ENOMEM), n read from the environment
 * variable MPS2P_FAIL_MALLOC_AT when the test program arms it; 0 or unset
 * only counts. Only that one call fails; the ones after it succeed, so the
 * code under test must cope with a failure anywhere, then carry on.
 *
 * The test program finds failmalloc_arm / failmalloc_disarm with
 * dlsym(RTLD_DEFAULT, ...) and arms around the calls under test, so that
 * its own allocations (and the loader's) are not counted.
 *
 * MPS2P_FAIL_MALLOC_SKIP=name: calls made from a loaded object whose file
 * name contains name (e.g. "libhdf5"), directly or through the C library
 * (strdup, fopen...), are neither counted nor failed.
 * MPS2P_FAIL_MALLOC_TRACE=1: prints the stack of the failed call to stderr. */
#define _GNU_SOURCE
#include <errno.h>
#include <execinfo.h>
#include <link.h>
#include <stdatomic.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* glibc's own entry points: no dlsym(RTLD_NEXT) bootstrapping needed. */
extern void *__libc_malloc(size_t size);
extern void *__libc_calloc(size_t count, size_t size);
extern void *__libc_realloc(void *pointer, size_t size);

static atomic_int armed;
static atomic_long calls;    /* counted while armed */
static atomic_long fail_at;  /* 1-based index of the call to fail; 0 = none */
static atomic_int failed;    /* the failure has happened */
static int trace;

/* Address ranges of the skipped objects' loaded segments. */
#define MAX_RANGES 16
typedef struct ranges {
    uintptr_t lo[MAX_RANGES], hi[MAX_RANGES];
    int count;
    const char *name;
} ranges;
static ranges skip, libc;

static int add_ranges(struct dl_phdr_info *info, size_t size, void *data)
{
    (void)size;
    ranges *r = data;
    if (!info->dlpi_name || !strstr(info->dlpi_name, r->name))
        return 0;
    for (int i = 0; i < info->dlpi_phnum && r->count < MAX_RANGES; i++) {
        const ElfW(Phdr) *ph = &info->dlpi_phdr[i];
        if (ph->p_type != PT_LOAD)
            continue;
        r->lo[r->count] = info->dlpi_addr + ph->p_vaddr;
        r->hi[r->count] = r->lo[r->count] + ph->p_memsz;
        r->count++;
    }
    return 0;
}

static int inside(const ranges *r, const void *address)
{
    uintptr_t a = (uintptr_t)address;
    for (int i = 0; i < r->count; i++)
        if (a >= r->lo[i] && a < r->hi[i])
            return 1;
    return 0;
}

static int skipped(const void *caller)
{
    if (skip.count == 0)
        return 0;
    if (inside(&skip, caller))
        return 1;
    if (!inside(&libc, caller))
        return 0;
    /* called by the C library: by whom? */
    void *frames[8];
    int depth = backtrace(frames, 8);
    for (int i = 2; i < depth; i++) {
        if (inside(&skip, frames[i]))
            return 1;
        if (!inside(&libc, frames[i]))
            return 0;
    }
    return 0;
}

__attribute__((visibility("default"))) void failmalloc_arm(void)
{
    const char *text = getenv("MPS2P_FAIL_MALLOC_AT"); /* getenv does not allocate */
    long at = text ? strtol(text, NULL, 10) : 0;
    const char *skip_name = getenv("MPS2P_FAIL_MALLOC_SKIP");
    skip.count = libc.count = 0;
    if (skip_name && skip_name[0]) {
        skip.name = skip_name;
        libc.name = "libc.so";
        dl_iterate_phdr(add_ranges, &skip);
        dl_iterate_phdr(add_ranges, &libc);
    }
    const char *tracing = getenv("MPS2P_FAIL_MALLOC_TRACE");
    trace = tracing && tracing[0] == '1';
    if (trace || skip.count) { /* the first backtrace() loads libgcc_s: not while armed */
        void *frames[2];
        backtrace(frames, 2);
    }
    atomic_store(&calls, 0);
    atomic_store(&failed, 0);
    atomic_store(&fail_at, at > 0 ? at : 0);
    atomic_store(&armed, 1);
}

/* Stops counting; returns the number of calls counted since arming. */
__attribute__((visibility("default"))) long failmalloc_disarm(void)
{
    atomic_store(&armed, 0);
    return atomic_load(&calls);
}

/* Whether the armed failure has happened. */
__attribute__((visibility("default"))) int failmalloc_failed(void)
{
    return atomic_load(&failed);
}

static int should_fail(const void *caller)
{
    if (!atomic_load(&armed) || skipped(caller))
        return 0;
    long n = atomic_fetch_add(&calls, 1) + 1;
    if (n == atomic_load(&fail_at)) {
        atomic_store(&failed, 1);
        if (trace) {
            void *frames[32];
            int depth = backtrace(frames, 32);
            static const char header[] = "failmalloc: failing this call:\n";
            if (write(2, header, sizeof header - 1) < 0)
                return 1;
            backtrace_symbols_fd(frames, depth, 2);
        }
        return 1;
    }
    return 0;
}

__attribute__((visibility("default"))) void *malloc(size_t size)
{
    if (should_fail(__builtin_return_address(0))) {
        errno = ENOMEM;
        return NULL;
    }
    return __libc_malloc(size);
}

__attribute__((visibility("default"))) void *calloc(size_t count, size_t size)
{
    if (should_fail(__builtin_return_address(0))) {
        errno = ENOMEM;
        return NULL;
    }
    return __libc_calloc(count, size);
}

__attribute__((visibility("default"))) void *realloc(void *pointer, size_t size)
{
    if (should_fail(__builtin_return_address(0))) {
        errno = ENOMEM;
        return NULL;
    }
    return __libc_realloc(pointer, size);
}
