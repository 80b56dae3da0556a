/* Regression (issue 7): the neighbour list's index failing to grow during a
 * step. neighbours_update had already written the new pair counts into
 * start[], then returned MPS2P_ERR_NOMEM with index[] too short; the failed
 * step put the particles back where the last build saw them, so the next
 * update saw no reason to rebuild and every stage read past index[].
 * Run with libfailmalloc.so preloaded (see failmalloc.c). */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <stdio.h>
#include <stdlib.h>
#include "internal.h"
#include "../check.h"

int main(void)
{
    void (*arm)(void);
    long (*disarm)(void);
    *(void **)&arm = dlsym(RTLD_DEFAULT, "failmalloc_arm");
    *(void **)&disarm = dlsym(RTLD_DEFAULT, "failmalloc_disarm");
    if (!arm || !disarm) {
        fprintf(stderr, "test_neighbours_nomem: run with LD_PRELOAD=libfailmalloc.so\n");
        return 77;
    }
    const double domain[4] = {-10, -10, 10, 10};
    double apart[4] = {0.0, 0.0, 5.0, 0.0}, close[4] = {0.0, 0.0, 0.5, 0.0};
    neighbour_list list;
    CHECK(neighbours_init(&list, 2, 1.0, 0.2, 0.6, domain) == MPS2P_OK, "init");
    list.threads = 1; /* one run of rows: the allocations below come in this order */
    CHECK(neighbours_update(&list, apart) == MPS2P_OK, "first build");
    CHECK(list.start[2] == 0, "no pairs apart");

    setenv("MPS2P_FAIL_MALLOC_AT", "1", 1);
    arm();
    int status = neighbours_update(&list, close); /* needs room for 2 entries */
    disarm();
    CHECK(status == MPS2P_ERR_NOMEM, "the growing list returned %s",
          mps2p_status_string(status));
    CHECK(list.start[list.count] <= list.capacity,
          "after the failure start[] counts %zu entries, index[] holds %zu",
          list.start[list.count], list.capacity);

    /* the failed step puts the particles back; then the next step */
    CHECK(neighbours_update(&list, apart) == MPS2P_OK, "update after the failure");
    CHECK(list.start[list.count] <= list.capacity,
          "back in place, start[] counts %zu entries, index[] holds %zu",
          list.start[list.count], list.capacity);
    CHECK(list.start[2] == 0, "apart again: %zu pairs", list.start[2]);
    CHECK(neighbours_update(&list, close) == MPS2P_OK, "update close");
    CHECK(list.start[2] == 2 && list.index[0] == 1 && list.index[1] == 0,
          "close: the pair is listed");
    CHECK(list.short_start[2] == 2 && list.short_index[0] == 1 && list.short_index[1] == 0,
          "close: the pair is in the short list");
    neighbours_free(&list);

    /* The short list failing to grow (the long one's growth succeeds):
     * both lists left empty and consistent, rebuilt at the next update.
     * Six particles: 30 pairs, more than the short index's first room. */
    double apart6[12], close6[12];
    for (int p = 0; p < 6; p++) {
        apart6[2 * p] = -9.0 + 3.0 * p;
        close6[2 * p] = 0.1 * p;
        apart6[2 * p + 1] = close6[2 * p + 1] = 0.0;
    }
    CHECK(neighbours_init(&list, 6, 1.0, 0.2, 0.6, domain) == MPS2P_OK, "init six");
    list.threads = 1;
    CHECK(neighbours_update(&list, apart6) == MPS2P_OK, "first build of six");
    setenv("MPS2P_FAIL_MALLOC_AT", "2", 1);
    arm();
    status = neighbours_update(&list, close6); /* long, then short index grow */
    disarm();
    CHECK(status == MPS2P_ERR_NOMEM, "the growing short list returned %s",
          mps2p_status_string(status));
    CHECK(list.start[6] == 0 && list.short_start[6] == 0 && list.stale,
          "after the short list's failure: %zu and %zu pairs, stale %d", list.start[6],
          list.short_start[6], list.stale);
    CHECK(list.short_start[list.count] <= list.short_capacity, "short start[] within index[]");
    CHECK(neighbours_update(&list, apart6) == MPS2P_OK, "update after the short failure");
    CHECK(list.start[6] == 0 && list.short_start[6] == 0, "apart again, short list empty");
    CHECK(neighbours_update(&list, close6) == MPS2P_OK, "update close again");
    CHECK(list.start[6] == 30 && list.short_start[6] == 30 && list.short_index[0] == 1 &&
          list.short_index[29] == 4, "close again: the 30 pairs in the short list");
    neighbours_free(&list);
    return check_summary("test_neighbours_nomem");
}
