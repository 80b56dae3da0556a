/* libFuzzer target: mps2p_solver_load_checkpoint on arbitrary bytes. The
 * bytes are written to a temporary file and loaded; a checkpoint that loads
 * is stepped twice, saved and loaded again. Bytes with a checksum header
 * (format 4) are then given a fresh checksum (checkpoint_seal.h) and loaded
 * again: the first load tests the checksum, which refuses nearly every
 * mutation, the second the checks behind it (a crafted file). Every refusal must be
 * MPS2P_ERR_IO (or MPS2P_ERR_NOMEM) with a message; nothing may crash,
 * leak or trip a sanitizer, and no HDF5 object may stay open after a call
 * (a leaked handle keeps the whole file and its metadata cache in memory,
 * H5F_CLOSE_WEAK). Seeds: real checkpoints from
 * make_checkpoint_seeds.c, in tests/fuzz/corpus/checkpoint. */
#define _POSIX_C_SOURCE 200809L
#include <mps2p.h>

#include <hdf5.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "../checkpoint_seal.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static char input_path[256], output_path[300];

static void remove_files(void)
{
    remove(input_path);
    remove(output_path);
}

static void check(int status, int allowed_failure)
{
    if (status == MPS2P_OK)
        return;
    if ((status != allowed_failure && status != MPS2P_ERR_NOMEM) ||
        mps2p_last_error()[0] == '\0') {
        fprintf(stderr, "unexpected %s: \"%s\"\n", mps2p_status_string(status),
                mps2p_last_error());
        abort();
    }
}

/* Every HDF5 file, group, dataset, attribute and type of the process. */
static void check_nothing_open(const char *after)
{
    ssize_t open_objects = H5Fget_obj_count((hid_t)H5F_OBJ_ALL, H5F_OBJ_ALL);
    if (open_objects != 0) {
        fprintf(stderr, "%zd HDF5 objects still open after %s\n", open_objects, after);
        abort();
    }
}

static void load_bytes(const uint8_t *data, size_t size)
{
    FILE *f = fopen(input_path, "wb");
    if (!f)
        return;
    size_t written = fwrite(data, 1, size, f);
    if (fclose(f) != 0 || written != size)
        return;
    mps2p_solver *solver = NULL;
    int status = mps2p_solver_load_checkpoint(input_path, &solver);
    check(status, MPS2P_ERR_IO);
    check_nothing_open("loading");
    if (status != MPS2P_OK)
        return;
    for (int k = 0; k < 2 && status == MPS2P_OK; k++) {
        status = mps2p_solver_step(solver);
        /* a loaded state may be one that cannot go on */
        if (status != MPS2P_ERR_SOLVE && status != MPS2P_ERR_DIVERGED &&
            status != MPS2P_ERR_STATE)
            check(status, MPS2P_OK);
    }
    check(mps2p_solver_save_checkpoint(solver, output_path), MPS2P_ERR_IO);
    mps2p_solver *again = NULL;
    status = mps2p_solver_load_checkpoint(output_path, &again);
    check(status, MPS2P_ERR_IO);
    check_nothing_open("saving and loading again");
    mps2p_solver_destroy(again);
    mps2p_solver_destroy(solver);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (!input_path[0]) {
        const char *dir = getenv("TMPDIR");
        snprintf(input_path, sizeof input_path, "%s/mps2p-fuzz-%ld.chk", dir ? dir : "/tmp",
                 (long)getpid());
        snprintf(output_path, sizeof output_path, "%s.out", input_path);
        atexit(remove_files);
    }
    load_bytes(data, size);
    if (seal_has_header(data, size)) {
        uint8_t *copy = malloc(size);
        if (copy) {
            memcpy(copy, data, size);
            reseal_bytes(copy, size);
            load_bytes(copy, size);
            free(copy);
        }
    }
    return 0;
}
