/* File-system helpers for the output files: derived paths, and replacing a
 * file atomically (write a temporary next to it, flush it to disk, rename). */
#define _XOPEN_SOURCE 700 /* realpath, lstat, strdup */
#include "io/io.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

char *path_join_suffix(const char *path, size_t keep, const char *suffix)
{
    size_t extra = strlen(suffix);
    char *out = malloc(keep + extra + 1);
    if (!out)
        return NULL;
    memcpy(out, path, keep);
    memcpy(out + keep, suffix, extra + 1);
    return out;
}

const char *path_basename(const char *path)
{
    const char *slash = strrchr(path, '/');
    return slash ? slash + 1 : path;
}

void describe_errno(int error, char *out, size_t size)
{
    /* strerror_r (the POSIX one), not strerror: threads must not share a buffer */
    if (strerror_r(error, out, size) != 0)
        snprintf(out, size, "error %d", error);
}

int file_sync(const char *path, char *reason, size_t size)
{
    int fd = open(path, O_RDONLY);
    if (fd < 0 || fsync(fd) != 0) {
        describe_errno(errno, reason, size);
        if (fd >= 0)
            close(fd);
        return -1;
    }
    close(fd);
    return 0;
}

int file_replace(const char *temporary, const char *path, char *reason, size_t size)
{
    if (file_sync(temporary, reason, size) != 0 || rename(temporary, path) != 0) {
        if (!reason[0])
            describe_errno(errno, reason, size);
        remove(temporary);
        return -1;
    }
    return 0;
}

int file_replace_target(const char *path, char **target, char *reason, size_t size)
{
    *target = NULL;
    struct stat seen;
    if (lstat(path, &seen) != 0) {
        if (errno != ENOENT) {
            describe_errno(errno, reason, size);
            return MPS2P_ERR_IO;
        }
        *target = strdup(path); /* nothing there yet */
    } else if (S_ISLNK(seen.st_mode)) {
        *target = realpath(path, NULL);
        if (!*target) {
            describe_errno(errno, reason, size);
            snprintf(reason + strlen(reason), size - strlen(reason),
                     " (a symbolic link whose target cannot be resolved)");
            return MPS2P_ERR_IO;
        }
        if (stat(*target, &seen) != 0 || !S_ISREG(seen.st_mode)) {
            snprintf(reason, size, "a symbolic link to \"%s\", which is not a regular file",
                     *target);
            free(*target);
            *target = NULL;
            return MPS2P_ERR_IO;
        }
    } else if (!S_ISREG(seen.st_mode)) {
        snprintf(reason, size, "not a regular file (%s): it is not replaced",
                 S_ISDIR(seen.st_mode) ? "a directory" : S_ISFIFO(seen.st_mode) ? "a FIFO"
                 : S_ISCHR(seen.st_mode) || S_ISBLK(seen.st_mode) ? "a device" : "a socket");
        return MPS2P_ERR_IO;
    } else {
        *target = strdup(path);
    }
    if (!*target) {
        snprintf(reason, size, "out of memory");
        return MPS2P_ERR_NOMEM;
    }
    return MPS2P_OK;
}
