/* file.h — reading a whole file into memory, the one way every reader of
 * the project does it (scenes, OBJ, streams, vector manifests, fuzz inputs). */
#ifndef ALBATROS_FILE_H
#define ALBATROS_FILE_H

#include "diag.h"

#include <stddef.h>
#include <stdio.h>

/* The library exports what its public headers declare, nothing else. */
#pragma GCC visibility push(default)

/* The rest of stream f into a malloc'd buffer *buf of *len bytes, plus a
 * NUL after them (text readers may treat it as a string).  0; -1 on a read
 * error (errno says which); -2 out of memory.  *buf is NULL on failure.  f
 * stays open. */
int alb_file_read_all(FILE *f, char **buf, size_t *len);
/* The whole file at path the same way, with the error described in d
 * ("cannot open: ...", "read error: ...", "too large for memory"). */
alb_err alb_file_load(const char *path, char **buf, size_t *len, alb_diag *d);

#pragma GCC visibility pop

#endif
