/* The files: HDF5 results with their XDMF sidecar (results_file.c,
 * xdmf.c), checkpoints with their checksum (checkpoint.c,
 * checkpoint_seal.c), and what they share: HDF5 inside libmps2p (a guard
 * around every entry point that calls HDF5, messages that name the file,
 * typed read/write helpers: hdf5_io.c), the run's parameters and fluids
 * (run_metadata.c) and file-system helpers (files.c). */
#ifndef MPS2P_IO_H
#define MPS2P_IO_H

#include "core/core.h"

#include <hdf5.h>
#include <stddef.h>
#include <sys/stat.h>

/* ---- HDF5 (hdf5_io.c) ---- */

#define H5_DETAIL_SIZE 256

/* Held for the duration of one public call that uses HDF5. */
typedef struct h5_guard {
    int locked;        /* our mutex, taken only if HDF5 is not thread-safe */
    int saved_v2;      /* which kind of automatic error handler was installed */
    H5E_auto2_t func2;
    void *data;
#ifndef H5_NO_DEPRECATED_SYMBOLS
    H5E_auto1_t func1;
#endif
} h5_guard;

/* Serialises HDF5 if the loaded library is not thread-safe, and switches
 * HDF5's automatic error printing off for the calling thread. */
void h5_enter(h5_guard *guard);
/* Restores the thread's error printing and releases the lock. */
void h5_leave(h5_guard *guard);

/* What one public call is working on, for its messages. */
typedef struct h5_context {
    const char *role;               /* "results file", "checkpoint" */
    const char *path;
    char detail[H5_DETAIL_SIZE];    /* first failure's reason (HDF5's or ours) */
} h5_context;

void h5_context_init(h5_context *ctx, const char *role, const char *path);
/* Records HDF5's innermost error message as the detail, unless one is
 * recorded already. Call right after the failing HDF5 call: any later HDF5
 * API call clears the error stack. */
void h5_note(h5_context *ctx);
/* Records a detail of our own (wrong shape, missing attribute...). */
void h5_note_text(h5_context *ctx, const char *format, ...)
    __attribute__((format(printf, 2, 3)));
/* MPS2P_ERR_IO with "<role> \"<path>\": <what>: <detail>". */
int h5_fail(h5_context *ctx, char *handle_error, const char *format, ...)
    __attribute__((format(printf, 3, 4)));

/* Writers: 0 on success, -1 on failure with the detail noted.
 * count 1 writes a scalar attribute, otherwise a 1-D one. */
int h5_write_attribute(h5_context *ctx, hid_t object, const char *name, hid_t type,
                       size_t count, const void *value);
int h5_write_attribute_string(h5_context *ctx, hid_t object, const char *name,
                              const char *value);
/* A contiguous dataset of rank 1 or 2 (dims[0] x dims[1]). */
int h5_write_dataset(h5_context *ctx, hid_t location, const char *name, hid_t type,
                     int rank, const hsize_t *dims, const void *data);
/* A scalar dataset holding one string (of any length). */
int h5_write_string_dataset(h5_context *ctx, hid_t location, const char *name,
                            const char *text);
/* A 1-D dataset of count fixed-length strings. */
int h5_write_string_array(h5_context *ctx, hid_t location, const char *name,
                          size_t count, const char *const *strings);

/* Readers: 0 on success, -1 with a noted detail when the object is missing,
 * of the wrong class or shape. */
int h5_read_attribute(h5_context *ctx, hid_t object, const char *name, hid_t memory_type,
                      size_t count, void *value);
int h5_read_attribute_string(h5_context *ctx, hid_t object, const char *name, char *out,
                             size_t size);
/* Reads exactly rank and dims; anything else is a wrong shape. */
int h5_read_dataset(h5_context *ctx, hid_t location, const char *name, hid_t memory_type,
                    int rank, const hsize_t *dims, void *data);
/* Length of a 1-D dataset, to size the arrays before reading. */
int h5_dataset_length(h5_context *ctx, hid_t location, const char *name, hsize_t *length);
/* Reads the i-th string of a 1-D fixed-length string dataset into out. */
int h5_read_string_array(h5_context *ctx, hid_t location, const char *name, size_t count,
                         char *out, size_t width);

/* ---- the run's parameters and fluids (run_metadata.c) ---- */

/* Group "parameters": one attribute per numeric parameter (double) and per
 * option (string); group "fluids": datasets name, density,
 * kinematic_viscosity. */
int h5_write_parameters(h5_context *ctx, hid_t file, const mps2p_solver *s);
int h5_write_fluids(h5_context *ctx, hid_t file, const mps2p_solver *s);
/* Reads and validates every parameter and option through params_set. */
int h5_read_parameters(h5_context *ctx, hid_t file, params *out);
int h5_read_fluid_count(h5_context *ctx, hid_t file, int *count);
int h5_read_fluids(h5_context *ctx, hid_t file, int count, fluid *out);

/* ---- the XDMF sidecar (xdmf.c) ---- */

/* Writes the XDMF sidecar for count snapshots of a results file whose name
 * (relative to the sidecar) is h5_name; atomic. */
int xdmf_write(const char *xdmf_path, const char *h5_name, size_t count, const double *times,
               const size_t *particles, char *handle_error);

/* ---- checkpoint checksums (checkpoint_seal.c) ---- */

/* The checksum of a checkpoint file: HDF5 user block of
 * CHECKPOINT_HEADER_SIZE bytes before the HDF5 data, holding
 *   bytes  0-7   magic "MPS2PCHK"
 *   bytes  8-11  layout of this header, 1 (uint32, little-endian)
 *   bytes 12-15  its size, 512 (uint32, little-endian)
 *   bytes 16-23  length of the whole file in bytes (uint64, little-endian)
 *   bytes 24-31  CRC-64/XZ of the whole file, these 8 bytes read as zeros
 *                (uint64, little-endian)
 *   bytes 32-    a line of text saying so, then zeros.
 * Checked by reading the raw bytes before HDF5 parses anything: HDF5 1.10
 * crashes or allocates without bound on some damaged files. */
#define CHECKPOINT_HEADER_SIZE 512

/* Writes the header into a closed HDF5 file created with a user block of
 * CHECKPOINT_HEADER_SIZE. 0, or -1 with a reason. */
int checkpoint_seal(const char *path, char *reason, size_t size);

enum { CHECKPOINT_SEALED = 0, CHECKPOINT_UNSEALED = 1 };

/* Checks path before HDF5 opens it: a regular file (a FIFO would block),
 * then either the header with the right length and checksum
 * (CHECKPOINT_SEALED) or HDF5's signature at byte 0, as files of format 3
 * and older have (CHECKPOINT_UNSEALED: nothing to check them by). -1 with
 * a reason otherwise. *checked: the file's identity when it was read. */
int checkpoint_verify(const char *path, struct stat *checked, char *reason, size_t size);

/* 0 when the open file descriptor fd is still the file verify checked. */
int checkpoint_same_file(int fd, const struct stat *checked);

/* ---- file-system helpers (files.c) ---- */

char *path_join_suffix(const char *path, size_t keep, const char *suffix);
/* The part after the last '/'. */
const char *path_basename(const char *path);
/* Thread-safe text of an errno value. */
void describe_errno(int error, char *out, size_t size);
/* fsync of a closed file, by name. 0 or -1 with a reason. */
int file_sync(const char *path, char *reason, size_t size);
/* The file an atomic replace of path should replace, in *target (freed by
 * the caller): path itself when nothing is there or a regular file is, the
 * file a symbolic link leads to (the link stays a link). MPS2P_OK, or
 * MPS2P_ERR_IO with a reason when something else is there (a device, a
 * FIFO, a directory: a rename would put a regular file in its place), or
 * MPS2P_ERR_NOMEM. */
int file_replace_target(const char *path, char **target, char *reason, size_t size);
/* Flushes temporary to disk and renames it over path; on failure removes
 * temporary and returns -1 with a reason (reason must start empty). */
int file_replace(const char *temporary, const char *path, char *reason, size_t size);

#endif
