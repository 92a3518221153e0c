/* file.h — files a user can trust (docs/files.md): reading inputs with a
 * bound and without blocking on what is not a regular file, writing outputs
 * that never destroy a path (a temporary file in the same directory, fsync,
 * rename into place; straight through, never removed, to a device or FIFO),
 * and telling whether two paths name one file (device and inode). */
#ifndef ALBATROS_FILE_H
#define ALBATROS_FILE_H

#include "diag.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>

/* The library exports what its public headers declare, nothing else. */
#pragma GCC visibility push(default)
#ifdef __cplusplus
extern "C" {
#endif

/* ---- inputs ---- */

/* The rest of stream f into a malloc'd buffer *buf of *len bytes, plus a
 * NUL after them (text readers may treat it as a string).  0; -1 on a read
 * error (errno says which); -2 out of memory.  *buf is NULL on failure.  f
 * stays open. */
int alb_file_read_all(FILE *f, char **buf, size_t *len);
/* The same for a text format, which no NUL byte belongs to: reading stops
 * after the first block holding one, so that /dev/zero or a binary file is
 * refused at its first bytes rather than read to the end.  The NUL is in
 * the buffer: the parser reports it at its line and column. */
int alb_file_read_text(FILE *f, char **buf, size_t *len);

/* Open path for reading ("rb").  regular_only: refuse anything that is not
 * a regular file — a FIFO would block, a device might never end — without
 * blocking on a FIFO's open; what files name (textures, material libraries)
 * is read so.  Otherwise only a directory is refused.  NULL on failure,
 * *why (static text) says why: the system's reason, "is a directory",
 * "is a FIFO, not a regular file", ... */
FILE *alb_file_open_input(const char *path, bool regular_only, const char **why);
/* The whole file at path as alb_file_read_all reads it, with the error
 * described in d ("cannot open: ...", "read error: ...", "too large for
 * memory"). */
alb_err alb_file_load(const char *path, char **buf, size_t *len, alb_diag *d);

/* ---- outputs ---- */

/* One output being written.  A regular file, or a name that does not exist
 * yet, is written under a temporary name beside it (".NAME.XXXXXX.tmp", mode
 * and owner taken from the file it replaces) that alb_out_commit fsyncs and
 * renames over the name: a reader, a crash or a full disk sees the old file
 * or the complete new one, never a part.  A symbolic link is followed: the
 * file it names is replaced, the link stays.  Anything else that exists (a
 * character device, a FIFO, a socket) is opened without O_CREAT or O_TRUNC
 * and written straight through; it is never removed, whatever fails.  A
 * directory, a dangling link or a read-only file is refused. */
typedef struct {
    int fd;                  /* where the bytes go */
    FILE *fp;                /* alb_out_stdio's stream on fd, or NULL */
    const char *path;        /* as given, for messages (borrowed) */
    int dirfd;               /* the target's directory; -1: straight through */
    char *tmp, *base;        /* the temporary name and the target's, in dirfd */
    char *dir;               /* dirfd's path, as the target's name gives it */
    int slot;                /* in the list alb_out_remove_temps empties; -1 none */
    bool is_stdout;          /* "-" with ALB_OUT_DASH: stdout, left open */
    bool seekable;           /* fd takes pwrite and lseek (EXR needs it) */
} alb_out;

enum {
    ALB_OUT_DASH = 1         /* "-" means stdout */
};

/* Open an output; ALB_ERR_IO with the reason in d ("cannot create: ..."). */
alb_err alb_out_open(alb_out *o, const char *path, unsigned flags, alb_diag *d);
/* A stdio stream on the output ("wb"; stdout for "-"); NULL if out of memory
 * (the output is then aborted and d says so). */
FILE *alb_out_stdio(alb_out *o, alb_diag *d);
/* The temporary file's path (malloc'd; NULL straight through or out of
 * memory): for a program that writes the file itself (gnuplot) before
 * alb_out_commit puts it in place. */
char *alb_out_temp_path(const alb_out *o);
/* Write all of buf to the output's descriptor (retrying short writes). */
alb_err alb_out_write(alb_out *o, const void *buf, size_t n, alb_diag *d);
/* Finish: flush, fsync, close and rename into place.  On any failure the
 * temporary file is removed and the old file, if any, is untouched; a
 * straight-through target is closed and left as it is.  stdout is flushed,
 * not closed.  The output is closed either way. */
alb_err alb_out_commit(alb_out *o, alb_diag *d);
/* Give up: close, and remove the temporary file (never the target). */
void alb_out_abort(alb_out *o);
/* alb_out_commit from a signal handler (async-signal-safe: no stdio, no
 * allocation); for writers that keep their own buffer on o->fd (VCD).
 * 0, or -1 if the file could not be put in place. */
int alb_out_commit_in_signal(alb_out *o);
/* Remove every temporary file of an output not committed yet: for a
 * handler of SIGINT/SIGTERM about to end the process.  Async-signal-safe. */
void alb_out_remove_temps(void);

/* ---- which file a path names ---- */

/* The identity of the file a path names, by device and inode, whatever the
 * spelling ("x", "./x", "d/../x", a symbolic link): the file's own if it
 * exists, and the directory entry it is (or would be) — the directory's
 * device and inode and the name in it — either way, so that two names of
 * a file not yet written compare equal too. */
typedef struct {
    bool exists;
    unsigned long long dev, ino;           /* the file, if it exists */
    unsigned long long dir_dev, dir_ino;   /* its directory */
    char *name;                            /* its name there (malloc'd) */
} alb_file_id;

/* 0, or -1 with errno set (a missing directory, say); *id is then empty. */
int alb_file_identify(const char *path, alb_file_id *id);
bool alb_file_id_same(const alb_file_id *a, const alb_file_id *b);
void alb_file_id_free(alb_file_id *id);

/* A string built like printf, malloc'd (paths have no fixed limit); NULL if
 * out of memory. */
char *alb_strprintf(const char *fmt, ...) __attribute__((format(printf, 1, 2)));

#ifdef __cplusplus
}
#endif
#pragma GCC visibility pop

#endif
