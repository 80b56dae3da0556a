/* The checksum of a checkpoint file (checkpoint_seal.c): HDF5 user block of
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
#ifndef MPS2P_CHECKPOINT_SEAL_H
#define MPS2P_CHECKPOINT_SEAL_H

#include <stddef.h>
#include <sys/stat.h>

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

#endif
