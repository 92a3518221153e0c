/* file.c — reading inputs and writing outputs so that no path is destroyed
 * (file.h, docs/files.md): bounded text reads, inputs that must be regular
 * files, outputs replaced atomically or written straight through, and the
 * identity of the file a path names. */
/* realpath is XSI */
#define _XOPEN_SOURCE 700
#include "albatros/file.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <pthread.h>
#include <signal.h>
#include <stdarg.h>
#include <stdatomic.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

/* ---- reading ---- */

static int read_stream(FILE *f, char **buf, size_t *len, bool text)
{
    size_t cap = (size_t)1 << 16, n = 0;
    char *b = malloc(cap);
    *buf = NULL;
    *len = 0;
    if (!b)
        return -2;
    for (;;) {
        if (n + 1 == cap) {   /* always room for the NUL */
            char *nb = cap <= SIZE_MAX / 2 ? realloc(b, cap * 2) : NULL;
            if (!nb) {
                free(b);
                return -2;
            }
            b = nb;
            cap *= 2;
        }
        size_t got = fread(b + n, 1, cap - n - 1, f);
        /* a text has no NUL: what follows one is not read (the parser
         * reports the NUL itself, at its line and column) */
        bool nul = text && got && memchr(b + n, 0, got);
        n += got;
        if (!got || nul)
            break;
    }
    if (ferror(f)) {
        free(b);
        return -1;
    }
    b[n] = 0;
    *buf = b;
    *len = n;
    return 0;
}

int alb_file_read_all(FILE *f, char **buf, size_t *len) { return read_stream(f, buf, len, false); }

int alb_file_read_text(FILE *f, char **buf, size_t *len) { return read_stream(f, buf, len, true); }

static const char *kind_of(mode_t m)
{
    if (S_ISFIFO(m))
        return "is a FIFO, not a regular file";
    if (S_ISCHR(m))
        return "is a character device, not a regular file";
    if (S_ISBLK(m))
        return "is a block device, not a regular file";
    if (S_ISSOCK(m))
        return "is a socket, not a regular file";
    return "is not a regular file";
}

FILE *alb_file_open_input(const char *path, bool regular_only, const char **why)
{
    /* O_NONBLOCK: opening a FIFO without a writer would otherwise wait */
    int fd = open(path, O_RDONLY | O_CLOEXEC | O_NOCTTY | (regular_only ? O_NONBLOCK : 0));
    if (fd < 0) {
        *why = strerror(errno);
        return NULL;
    }
    struct stat st;
    const char *bad = NULL;
    if (fstat(fd, &st) != 0)
        bad = strerror(errno);
    else if (S_ISDIR(st.st_mode))
        bad = "is a directory";
    else if (regular_only && !S_ISREG(st.st_mode))
        bad = kind_of(st.st_mode);
    else if (regular_only && fcntl(fd, F_SETFL, fcntl(fd, F_GETFL) & ~O_NONBLOCK) != 0)
        bad = strerror(errno);
    FILE *f = bad ? NULL : fdopen(fd, "rb");
    if (!f) {
        *why = bad ? bad : strerror(errno);
        close(fd);
    }
    return f;
}

alb_err alb_file_load(const char *path, char **buf, size_t *len, alb_diag *d)
{
    *buf = NULL;
    const char *why;
    FILE *f = alb_file_open_input(path, false, &why);
    if (!f)
        return alb_diag_at(d, ALB_ERR_IO, path, 0, 0, "cannot open: %s", why);
    int rc = alb_file_read_all(f, buf, len);
    int err = errno;
    fclose(f);
    if (rc == -2)
        return alb_diag_at(d, ALB_ERR_NOMEM, path, 0, 0, "too large for memory");
    if (rc)
        return alb_diag_at(d, ALB_ERR_IO, path, 0, 0, "read error: %s", strerror(err));
    return ALB_OK;
}

/* ---- paths ---- */

char *alb_strprintf(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(NULL, 0, fmt, ap);
    va_end(ap);
    if (n < 0)
        return NULL;
    char *s = malloc((size_t)n + 1);
    if (!s)
        return NULL;
    va_start(ap, fmt);
    vsnprintf(s, (size_t)n + 1, fmt, ap);
    va_end(ap);
    return s;
}

/* path as a directory and a name in it: "a/b" -> "a", "b"; "b" -> ".", "b";
 * "/b" -> "/", "b".  Trailing slashes belong to the name's directory-ness:
 * "a/b/" -> "a", "b" with *trailing set.  -1 if out of memory. */
static int split_path(const char *path, char **dir, char **name, bool *trailing)
{
    size_t len = strlen(path);
    *trailing = false;
    while (len > 1 && path[len - 1] == '/') {
        len--;
        *trailing = true;
    }
    size_t slash = len;
    while (slash > 0 && path[slash - 1] != '/')
        slash--;
    if (slash == 0)
        *dir = alb_strprintf(".");
    else if (slash == 1)
        *dir = alb_strprintf("/");
    else
        *dir = alb_strprintf("%.*s", (int)(slash - 1), path);
    *name = alb_strprintf("%.*s", (int)(len - slash), path + slash);
    if (!*dir || !*name) {
        free(*dir);
        free(*name);
        return -1;
    }
    return 0;
}

int alb_file_identify(const char *path, alb_file_id *id)
{
    memset(id, 0, sizeof *id);
    struct stat st, lst, dst;
    char *resolved = NULL;
    const char *entry = path;
    if (stat(path, &st) == 0) {
        id->exists = true;
        id->dev = (unsigned long long)st.st_dev;
        id->ino = (unsigned long long)st.st_ino;
        /* a link's entry is the file it leads to */
        if (lstat(path, &lst) == 0 && S_ISLNK(lst.st_mode) && (resolved = realpath(path, NULL)))
            entry = resolved;
    } else if (errno != ENOENT) {
        return -1;
    }
    char *dir, *name;
    bool trailing;
    if (split_path(entry, &dir, &name, &trailing)) {
        free(resolved);
        errno = ENOMEM;
        return -1;
    }
    free(resolved);
    int rc = stat(dir, &dst);
    int err = errno;
    free(dir);
    if (rc != 0) {
        free(name);
        errno = err;
        return -1;
    }
    id->dir_dev = (unsigned long long)dst.st_dev;
    id->dir_ino = (unsigned long long)dst.st_ino;
    id->name = name;
    return 0;
}

bool alb_file_id_same(const alb_file_id *a, const alb_file_id *b)
{
    if (a->exists && b->exists && a->dev == b->dev && a->ino == b->ino)
        return true;
    return a->name && b->name && a->dir_dev == b->dir_dev && a->dir_ino == b->dir_ino &&
           strcmp(a->name, b->name) == 0 && strcmp(a->name, ".") && strcmp(a->name, "..");
}

void alb_file_id_free(alb_file_id *id)
{
    free(id->name);
    memset(id, 0, sizeof *id);
}

/* ---- temporary files a signal handler may remove ---- */

#define MAX_TEMPS 64

static struct {
    volatile sig_atomic_t live;
    int dirfd;
    char name[NAME_MAX + 1];
} temps[MAX_TEMPS];
static pthread_mutex_t temps_mu = PTHREAD_MUTEX_INITIALIZER;

static int temp_register(int dirfd, const char *name)
{
    int slot = -1;
    if (strlen(name) > NAME_MAX)
        return -1;
    pthread_mutex_lock(&temps_mu);
    for (int i = 0; i < MAX_TEMPS && slot < 0; i++)
        if (!temps[i].live) {
            temps[i].dirfd = dirfd;
            strcpy(temps[i].name, name);
            temps[i].live = 1;
            slot = i;
        }
    pthread_mutex_unlock(&temps_mu);
    return slot;   /* none free: the file is simply not removed on a signal */
}

static void temp_unregister(int slot)
{
    if (slot >= 0)
        temps[slot].live = 0;
}

void alb_out_remove_temps(void)
{
    for (int i = 0; i < MAX_TEMPS; i++)
        if (temps[i].live) {
            unlinkat(temps[i].dirfd, temps[i].name, 0);
            temps[i].live = 0;
        }
}

/* ---- outputs ---- */

static alb_err out_fail(alb_diag *d, const char *path, const char *what, int err)
{
    return alb_diag_at(d, ALB_ERR_IO, path, 0, 0, "%s: %s", what, strerror(err));
}

static void out_reset(alb_out *o, const char *path)
{
    memset(o, 0, sizeof *o);
    o->fd = o->dirfd = o->slot = -1;
    o->path = path;
}

static void out_free_names(alb_out *o)
{
    temp_unregister(o->slot);
    o->slot = -1;
    if (o->dirfd >= 0)
        close(o->dirfd);
    o->dirfd = -1;
    free(o->tmp);
    free(o->base);
    free(o->dir);
    o->tmp = o->base = o->dir = NULL;
}

/* Six letters that make a temporary name unlikely to be taken; a taken one
 * is tried again (O_EXCL), so they need not be unpredictable. */
static void temp_letters(char out[7])
{
    static const char set[] = "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789";
    static atomic_uint counter;
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    uint64_t x = (uint64_t)ts.tv_nsec ^ (uint64_t)ts.tv_sec << 30 ^ (uint64_t)getpid() << 40 ^
                 (uint64_t)(atomic_fetch_add(&counter, 1) + 1) * 0x9E3779B97F4A7C15u;
    for (int i = 0; i < 6; i++) {
        x ^= x >> 31;
        x *= 0xBF58476D1CE4E5B9u;
        x ^= x >> 29;
        out[i] = set[x % (sizeof set - 1)];
    }
    out[6] = 0;
}

/* A temporary file beside the target, with the mode (and, as root, the
 * owner) of the file it will replace. */
static alb_err open_temp(alb_out *o, const struct stat *old, alb_diag *d)
{
    bool long_name = strlen(o->base) + 12 > NAME_MAX;
    for (int tries = 0; tries < 100; tries++) {
        char letters[7];
        temp_letters(letters);
        free(o->tmp);
        o->tmp = long_name ? alb_strprintf(".albatros.%s.tmp", letters)
                           : alb_strprintf(".%s.%s.tmp", o->base, letters);
        if (!o->tmp)
            return alb_diag_at(d, ALB_ERR_NOMEM, o->path, 0, 0, "out of memory");
        o->fd = openat(o->dirfd, o->tmp, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC | O_NOCTTY,
                       old ? 0600 : 0666);
        if (o->fd >= 0)
            break;
        if (errno != EEXIST)
            return out_fail(d, o->path, "cannot create", errno);
    }
    if (o->fd < 0)
        return out_fail(d, o->path, "cannot create a temporary file", EEXIST);
    o->slot = temp_register(o->dirfd, o->tmp);
    if (old) {
        if (geteuid() == 0 && fchown(o->fd, old->st_uid, old->st_gid) != 0) {
            /* kept as root's: the file's contents matter more */
        }
        if (fchmod(o->fd, old->st_mode & 07777) != 0) {
            int err = errno;
            alb_out_abort(o);
            return out_fail(d, o->path, "cannot set the mode of the new file", err);
        }
    }
    o->seekable = true;
    return ALB_OK;
}

/* Not a regular file: write to it as it is (a device, a FIFO, a socket). */
static alb_err open_through(alb_out *o, alb_diag *d)
{
    o->fd = open(o->path, O_WRONLY | O_CLOEXEC | O_NOCTTY);
    if (o->fd < 0)
        return out_fail(d, o->path, "cannot open", errno);
    o->seekable = lseek(o->fd, 0, SEEK_CUR) >= 0;
    return ALB_OK;
}

alb_err alb_out_open(alb_out *o, const char *path, unsigned flags, alb_diag *d)
{
    out_reset(o, path);
    if ((flags & ALB_OUT_DASH) && strcmp(path, "-") == 0) {
        o->path = "stdout";   /* for messages */
        o->fd = STDOUT_FILENO;
        o->is_stdout = true;
        o->seekable = lseek(o->fd, 0, SEEK_CUR) >= 0;
        return ALB_OK;
    }
    if (!*path)
        return alb_diag_at(d, ALB_ERR_IO, path, 0, 0, "cannot create a file with an empty name");
    struct stat st, lst;
    bool exists = stat(path, &st) == 0;
    if (!exists && errno != ENOENT)
        return out_fail(d, path, "cannot create", errno);
    if (!exists && lstat(path, &lst) == 0 && S_ISLNK(lst.st_mode))
        return alb_diag_at(d, ALB_ERR_IO, path, 0, 0, "cannot create: a symbolic link to a "
                           "file that does not exist");
    if (exists && S_ISDIR(st.st_mode))
        return alb_diag_at(d, ALB_ERR_IO, path, 0, 0, "cannot create: is a directory");
    if (exists && !S_ISREG(st.st_mode))
        return open_through(o, d);
    if (exists && access(path, W_OK) != 0)   /* replacing it would bypass its mode */
        return out_fail(d, path, "cannot write", errno);
    char *target = NULL, *dir = NULL;
    if (exists && lstat(path, &lst) == 0 && S_ISLNK(lst.st_mode) &&
        !(target = realpath(path, NULL)))
        return out_fail(d, path, "cannot follow the symbolic link", errno);
    bool trailing;
    int rc = split_path(target ? target : path, &dir, &o->base, &trailing);
    free(target);
    if (rc)
        return alb_diag_at(d, ALB_ERR_NOMEM, path, 0, 0, "out of memory");
    if (trailing || !strcmp(o->base, ".") || !strcmp(o->base, "..")) {
        free(dir);
        out_free_names(o);
        return alb_diag_at(d, ALB_ERR_IO, path, 0, 0, "cannot create: names a directory");
    }
    o->dirfd = open(dir, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    int err = errno;
    o->dir = dir;
    if (o->dirfd < 0) {
        out_free_names(o);
        return out_fail(d, path, "cannot create", err);
    }
    alb_err e = open_temp(o, exists ? &st : NULL, d);
    if (e && o->dirfd >= 0)
        out_free_names(o);
    return e;
}

char *alb_out_temp_path(const alb_out *o)
{
    return o->dirfd >= 0 && o->tmp ? alb_strprintf("%s/%s", o->dir, o->tmp) : NULL;
}

FILE *alb_out_stdio(alb_out *o, alb_diag *d)
{
    if (!o->fp)
        o->fp = o->is_stdout ? stdout : fdopen(o->fd, "wb");
    if (!o->fp) {
        int err = errno;
        alb_out_abort(o);
        out_fail(d, o->path, "cannot write", err);
    }
    return o->fp;
}

alb_err alb_out_write(alb_out *o, const void *buf, size_t n, alb_diag *d)
{
    const char *p = buf;
    while (n) {
        ssize_t k = write(o->fd, p, n);
        if (k < 0 && errno == EINTR)
            continue;
        if (k <= 0)
            return out_fail(d, o->path, "write error", k < 0 ? errno : ENOSPC);
        p += k;
        n -= (size_t)k;
    }
    return ALB_OK;
}

alb_err alb_out_commit(alb_out *o, alb_diag *d)
{
    int err = 0;
    const char *what = "write error";
    errno = 0;
    if (o->fp && (fflush(o->fp) != 0 || ferror(o->fp)))
        err = errno ? errno : EIO;
    if (o->is_stdout) {
        o->fp = NULL;
        o->fd = -1;
        return err ? out_fail(d, o->path, what, err) : ALB_OK;
    }
    /* the data reaches the disk before the name does: a crash after the
     * rename cannot leave the name on an empty or partial file */
    if (!err && o->dirfd >= 0 && fsync(o->fd) != 0)
        err = errno;
    int c = o->fp ? fclose(o->fp) : o->fd >= 0 ? close(o->fd) : 0;
    if (c != 0 && !err)
        err = errno;
    o->fp = NULL;
    o->fd = -1;
    if (o->dirfd >= 0) {
        if (!err && renameat(o->dirfd, o->tmp, o->dirfd, o->base) != 0) {
            err = errno;
            what = "cannot rename the new file into place";
        }
        if (err)
            unlinkat(o->dirfd, o->tmp, 0);
        else
            fsync(o->dirfd);   /* the rename itself; some file systems refuse, harmlessly */
    }
    out_free_names(o);
    return err ? out_fail(d, o->path, what, err) : ALB_OK;
}

void alb_out_abort(alb_out *o)
{
    if (o->is_stdout) {
        if (o->fp)
            fflush(o->fp);
    } else if (o->fp) {
        fclose(o->fp);
    } else if (o->fd >= 0) {
        close(o->fd);
    }
    o->fp = NULL;
    o->fd = -1;
    if (o->dirfd >= 0 && o->tmp)
        unlinkat(o->dirfd, o->tmp, 0);
    out_free_names(o);
}

int alb_out_commit_in_signal(alb_out *o)
{
    int bad = 0;
    if (o->is_stdout || o->fd < 0)
        return 0;
    if (o->dirfd >= 0)
        bad |= fsync(o->fd) != 0;
    bad |= close(o->fd) != 0;
    o->fd = -1;
    if (o->dirfd >= 0 && o->tmp) {
        if (bad || renameat(o->dirfd, o->tmp, o->dirfd, o->base) != 0) {
            unlinkat(o->dirfd, o->tmp, 0);
            bad = 1;
        }
        temp_unregister(o->slot);
        o->slot = -1;
    }
    return bad ? -1 : 0;
}
