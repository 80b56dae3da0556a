/* Checkpoint checksums (format 4, issue 20): the layout is in
 * io.h and docs/results-files.md. A CRC-64 finds every change
 * of up to 64 bits in a row and any other with probability 1 - 2^-64;
 * this is against damage, not against a crafted file with a fresh CRC. */
#define _POSIX_C_SOURCE 200809L
#include "io/io.h"

#include <errno.h>
#include <fcntl.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define MAGIC "MPS2PCHK"
#define LAYOUT 1u
#define CRC_AT 24
#define CHUNK (1u << 16)

static const unsigned char hdf5_signature[8] = {0x89, 'H', 'D', 'F', '\r', '\n', 0x1a, '\n'};

/* CRC-64/XZ (ECMA-182 polynomial, reflected): the table is built per call
 * (2 KB, microseconds), so nothing is kept between calls. */
static void crc_table(uint64_t table[256])
{
    for (unsigned i = 0; i < 256; i++) {
        uint64_t c = i;
        for (int k = 0; k < 8; k++)
            c = c & 1 ? (c >> 1) ^ UINT64_C(0xC96C5795D7870F42) : c >> 1;
        table[i] = c;
    }
}

static uint64_t crc_update(uint64_t crc, const unsigned char *p, size_t n,
                           const uint64_t table[256])
{
    while (n--)
        crc = table[(crc ^ *p++) & 0xff] ^ (crc >> 8);
    return crc;
}

static void put_le(unsigned char *out, uint64_t value, int bytes)
{
    for (int i = 0; i < bytes; i++)
        out[i] = (unsigned char)(value >> (8 * i));
}

static uint64_t get_le(const unsigned char *in, int bytes)
{
    uint64_t value = 0;
    for (int i = bytes - 1; i >= 0; i--)
        value = value << 8 | in[i];
    return value;
}

/* CRC of the file behind fd, size bytes, with header (its first
 * CHECKPOINT_HEADER_SIZE bytes as they should read, CRC field zero) in
 * place of the file's own first bytes when header is non-NULL. -1 on a
 * read error or a file that is not size bytes long. */
static int file_crc(int fd, off_t size, const unsigned char *header, uint64_t *crc,
                    char *reason, size_t reason_size)
{
    uint64_t table[256];
    crc_table(table);
    unsigned char *buffer = malloc(CHUNK);
    if (!buffer) {
        snprintf(reason, reason_size, "out of memory");
        return -1;
    }
    uint64_t c = ~UINT64_C(0);
    off_t at = 0;
    int status = 0;
    for (;;) {
        ssize_t got = pread(fd, buffer, CHUNK, at);
        if (got < 0 && errno == EINTR)
            continue;
        if (got < 0) {
            describe_errno(errno, reason, reason_size);
            status = -1;
            break;
        }
        if (got == 0)
            break;
        for (ssize_t k = 0; k < got; k++) { /* the header as it should read */
            off_t position = at + k;
            if (position >= CHECKPOINT_HEADER_SIZE)
                break;
            if (header)
                buffer[k] = header[position];
            else if (position >= CRC_AT && position < CRC_AT + 8)
                buffer[k] = 0;
        }
        c = crc_update(c, buffer, (size_t)got, table);
        at += got;
    }
    free(buffer);
    if (status == 0 && at != size) {
        snprintf(reason, reason_size, "the file changed size while being read");
        status = -1;
    }
    *crc = ~c;
    return status;
}

int checkpoint_seal(const char *path, char *reason, size_t size)
{
    int fd = open(path, O_RDWR | O_CLOEXEC);
    struct stat st;
    if (fd < 0 || fstat(fd, &st) != 0) {
        describe_errno(errno, reason, size);
        if (fd >= 0)
            close(fd);
        return -1;
    }
    unsigned char header[CHECKPOINT_HEADER_SIZE] = {0};
    memcpy(header, MAGIC, 8);
    put_le(header + 8, LAYOUT, 4);
    put_le(header + 12, CHECKPOINT_HEADER_SIZE, 4);
    put_le(header + 16, (uint64_t)st.st_size, 8);
    snprintf((char *)header + 32, sizeof header - 32,
             "libmps2p checkpoint: bytes 24-31 hold the CRC-64/XZ of this file with those "
             "bytes as zeros; HDF5 data from byte %d\n", CHECKPOINT_HEADER_SIZE);
    uint64_t crc = 0;
    int status = file_crc(fd, st.st_size, header, &crc, reason, size);
    put_le(header + CRC_AT, crc, 8);
    if (status == 0 && pwrite(fd, header, sizeof header, 0) != (ssize_t)sizeof header) {
        describe_errno(errno, reason, size);
        status = -1;
    }
    if (close(fd) != 0 && status == 0) {
        describe_errno(errno, reason, size);
        status = -1;
    }
    return status;
}

int checkpoint_verify(const char *path, struct stat *checked, char *reason, size_t size)
{
    /* O_NONBLOCK: opening a FIFO must not wait for a writer */
    int fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) {
        describe_errno(errno, reason, size);
        return -1;
    }
    int result = -1;
    unsigned char header[CHECKPOINT_HEADER_SIZE];
    ssize_t got = 0;
    if (fstat(fd, checked) != 0) {
        describe_errno(errno, reason, size);
    } else if (!S_ISREG(checked->st_mode)) {
        snprintf(reason, size, "not a regular file (%s)",
                 S_ISDIR(checked->st_mode)    ? "a directory"
                 : S_ISFIFO(checked->st_mode) ? "a FIFO"
                 : S_ISSOCK(checked->st_mode) ? "a socket"
                 : S_ISCHR(checked->st_mode) || S_ISBLK(checked->st_mode) ? "a device"
                                                                         : "not a file");
    } else if ((got = pread(fd, header, sizeof header, 0)) < 8) {
        if (got < 0)
            describe_errno(errno, reason, size);
        else
            snprintf(reason, size, "not an HDF5 file (%lld bytes)", (long long)checked->st_size);
    } else if (memcmp(header, hdf5_signature, 8) == 0) {
        result = CHECKPOINT_UNSEALED; /* format 3 or older: read without a checksum */
    } else if (memcmp(header, MAGIC, 8) != 0) {
        snprintf(reason, size, "not an HDF5 file or a libmps2p checkpoint (neither's "
                 "signature at byte 0)");
    } else if (got < CHECKPOINT_HEADER_SIZE) {
        snprintf(reason, size, "damaged: %lld bytes, shorter than its header",
                 (long long)checked->st_size);
    } else if (get_le(header + 8, 4) != LAYOUT || get_le(header + 12, 4) != CHECKPOINT_HEADER_SIZE) {
        snprintf(reason, size, "damaged, or of a newer library: checksum header layout %llu "
                 "of %llu bytes (this library reads layout %u of %d)",
                 (unsigned long long)get_le(header + 8, 4),
                 (unsigned long long)get_le(header + 12, 4), LAYOUT, CHECKPOINT_HEADER_SIZE);
    } else if (get_le(header + 16, 8) != (uint64_t)checked->st_size) {
        snprintf(reason, size, "damaged: its header says %llu bytes, the file has %lld "
                 "(cut short or appended to)", (unsigned long long)get_le(header + 16, 8),
                 (long long)checked->st_size);
    } else {
        uint64_t crc = 0;
        if (file_crc(fd, checked->st_size, NULL, &crc, reason, size) == 0) {
            if (crc == get_le(header + CRC_AT, 8))
                result = CHECKPOINT_SEALED;
            else
                snprintf(reason, size, "damaged: its checksum does not match (CRC-64 %016llx, "
                         "the header says %016llx)", (unsigned long long)crc,
                         (unsigned long long)get_le(header + CRC_AT, 8));
        }
    }
    close(fd);
    return result;
}

int checkpoint_same_file(int fd, const struct stat *checked)
{
    struct stat now;
    if (fstat(fd, &now) != 0)
        return -1;
    return now.st_dev == checked->st_dev && now.st_ino == checked->st_ino &&
                   now.st_size == checked->st_size &&
                   now.st_mtim.tv_sec == checked->st_mtim.tv_sec &&
                   now.st_mtim.tv_nsec == checked->st_mtim.tv_nsec
               ? 0
               : -1;
}
