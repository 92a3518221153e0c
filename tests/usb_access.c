/* usb_access.c — an LD_PRELOAD shim for tests/usb-umockdev.sh: opening a
 * USB or hidraw device node needs the permission bits an unprivileged user
 * would need ("other" read and write; udev's uaccess ACL or the plugdev rule
 * grant them), whoever runs the test.  umockdev emulates ioctls but not
 * open(), and a test run as root (as CI is) passes every permission check,
 * so without this shim LIBUSB_ERROR_ACCESS could not happen under test.
 * tests/usb_board.c gives the nodes mode 0600 until "udev" has applied the
 * ACL (--acl-delay), then 0666.  Loaded in front of umockdev's preload, so
 * its stat() sees the testbed's files. */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <errno.h>
#include <fcntl.h>
#include <stdarg.h>
#include <string.h>
#include <sys/stat.h>

static int denied(const char *path, int flags)
{
    if (strncmp(path, "/dev/bus/usb/", 13) && strncmp(path, "/dev/hidraw", 11))
        return 0;
    struct stat st;
    if (stat(path, &st))
        return 0;   /* let open() report what is wrong */
    mode_t need = (flags & O_ACCMODE) == O_RDONLY ? S_IROTH
                : (flags & O_ACCMODE) == O_WRONLY ? S_IWOTH : S_IROTH | S_IWOTH;
    if ((st.st_mode & need) == need)
        return 0;
    errno = EACCES;
    return 1;
}

#define MODE_ARG(flags, mode)                                                 \
    mode_t mode = 0;                                                          \
    if ((flags) & (O_CREAT | O_TMPFILE)) {                                    \
        va_list ap;                                                           \
        va_start(ap, flags);                                                  \
        mode = (mode_t)va_arg(ap, int);                                       \
        va_end(ap);                                                           \
    }

int open(const char *path, int flags, ...);
int open64(const char *path, int flags, ...);
int __open_2(const char *path, int flags);
int __open64_2(const char *path, int flags);
int openat(int dirfd, const char *path, int flags, ...);
int openat64(int dirfd, const char *path, int flags, ...);

int open(const char *path, int flags, ...)
{
    MODE_ARG(flags, mode)
    if (denied(path, flags))
        return -1;
    int (*next)(const char *, int, ...);
    *(void **)&next = dlsym(RTLD_NEXT, "open");   /* POSIX: dlsym, XSH 2.12.3 */
    return next(path, flags, mode);
}

int open64(const char *path, int flags, ...)
{
    MODE_ARG(flags, mode)
    if (denied(path, flags))
        return -1;
    int (*next)(const char *, int, ...);
    *(void **)&next = dlsym(RTLD_NEXT, "open64");   /* POSIX: dlsym, XSH 2.12.3 */
    return next(path, flags, mode);
}

int __open_2(const char *path, int flags)
{
    if (denied(path, flags))
        return -1;
    int (*next)(const char *, int);
    *(void **)&next = dlsym(RTLD_NEXT, "__open_2");   /* POSIX: dlsym, XSH 2.12.3 */
    return next(path, flags);
}

int __open64_2(const char *path, int flags)
{
    if (denied(path, flags))
        return -1;
    int (*next)(const char *, int);
    *(void **)&next = dlsym(RTLD_NEXT, "__open64_2");   /* POSIX: dlsym, XSH 2.12.3 */
    return next(path, flags);
}

int openat(int dirfd, const char *path, int flags, ...)
{
    MODE_ARG(flags, mode)
    if (path[0] == '/' && denied(path, flags))
        return -1;
    int (*next)(int, const char *, int, ...);
    *(void **)&next = dlsym(RTLD_NEXT, "openat");   /* POSIX: dlsym, XSH 2.12.3 */
    return next(dirfd, path, flags, mode);
}

int openat64(int dirfd, const char *path, int flags, ...)
{
    MODE_ARG(flags, mode)
    if (path[0] == '/' && denied(path, flags))
        return -1;
    int (*next)(int, const char *, int, ...);
    *(void **)&next = dlsym(RTLD_NEXT, "openat64");   /* POSIX: dlsym, XSH 2.12.3 */
    return next(dirfd, path, flags, mode);
}
