/* File-system helpers for the output files (files.c). */
#ifndef MPS2P_FILES_H
#define MPS2P_FILES_H

#include <stddef.h>

/* The first keep characters of path followed by suffix; malloc'ed, NULL when
 * out of memory. */
char *path_join_suffix(const char *path, size_t keep, const char *suffix);
/* The part after the last '/'. */
const char *path_basename(const char *path);
/* Thread-safe text of an errno value. */
void describe_errno(int error, char *out, size_t size);
/* fsync of a closed file, by name. 0 or -1 with a reason. */
int file_sync(const char *path, char *reason, size_t size);
/* Flushes temporary to disk and renames it over path; on failure removes
 * temporary and returns -1 with a reason (reason must start empty). */
int file_replace(const char *temporary, const char *path, char *reason, size_t size);

#endif
