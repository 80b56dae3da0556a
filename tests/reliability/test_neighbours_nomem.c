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
    CHECK(neighbours_init(&list, 2, 1.0, 0.2, domain) == MPS2P_OK, "init");
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
    neighbours_free(&list);
    return check_summary("test_neighbours_nomem");
}
