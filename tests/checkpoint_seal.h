/* For tests and fuzzers: the checksum header of a format 4 checkpoint as
 * docs/results-files.md describes it, written independently of the
 * library's code. reseal_bytes() puts a fresh CRC into a file image, so that
 * a test can edit a checkpoint "as a crafted file would" and still reach
 * the checks behind the checksum. */
#ifndef MPS2P_TEST_CHECKPOINT_SEAL_H
#define MPS2P_TEST_CHECKPOINT_SEAL_H

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define SEAL_HEADER 512
#define SEAL_CRC_AT 24

/* CRC-64/XZ, bit by bit (slow and obviously right). */
static inline uint64_t seal_crc64(const unsigned char *p, size_t n)
{
    uint64_t crc = ~UINT64_C(0);
    for (size_t i = 0; i < n; i++) {
        unsigned char byte = (i >= SEAL_CRC_AT && i < SEAL_CRC_AT + 8) ? 0 : p[i];
        crc ^= byte;
        for (int k = 0; k < 8; k++)
            crc = crc & 1 ? (crc >> 1) ^ UINT64_C(0xC96C5795D7870F42) : crc >> 1;
    }
    return ~crc;
}

static inline int seal_has_header(const unsigned char *p, size_t n)
{
    return n >= SEAL_HEADER && memcmp(p, "MPS2PCHK", 8) == 0;
}

/* Rewrites length and CRC of an image with the header's magic; 0 if it has none. */
static inline int reseal_bytes(unsigned char *p, size_t n)
{
    if (!seal_has_header(p, n))
        return 0;
    for (int i = 0; i < 8; i++)
        p[16 + i] = (unsigned char)((uint64_t)n >> (8 * i));
    uint64_t crc = seal_crc64(p, n);
    for (int i = 0; i < 8; i++)
        p[SEAL_CRC_AT + i] = (unsigned char)(crc >> (8 * i));
    return 1;
}

static inline unsigned char *read_whole(const char *path, size_t *size)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    fseek(f, 0, SEEK_END);
    long length = ftell(f);
    fseek(f, 0, SEEK_SET);
    unsigned char *p = malloc(length > 0 ? (size_t)length : 1);
    if (p && fread(p, 1, (size_t)length, f) != (size_t)length) {
        free(p);
        p = NULL;
    }
    fclose(f);
    *size = (size_t)length;
    return p;
}

static inline int write_whole(const char *path, const unsigned char *p, size_t size)
{
    FILE *f = fopen(path, "wb");
    if (!f)
        return -1;
    int ok = fwrite(p, 1, size, f) == size;
    return fclose(f) == 0 && ok ? 0 : -1;
}

/* reseal_bytes on a file; -1 when it cannot be read or has no header. */
static inline int reseal_file(const char *path)
{
    size_t size = 0;
    unsigned char *p = read_whole(path, &size);
    int status = p && reseal_bytes(p, size) && write_whole(path, p, size) == 0 ? 0 : -1;
    free(p);
    return status;
}

#endif
