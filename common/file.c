/* file.c — whole-file reads (file.h). */
#include "albatros/file.h"

#include <errno.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

int alb_file_read_all(FILE *f, char **buf, size_t *len)
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
        n += got;
        if (!got)
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

alb_err alb_file_load(const char *path, char **buf, size_t *len, alb_diag *d)
{
    *buf = NULL;
    FILE *f = fopen(path, "rb");
    if (!f)
        return alb_diag_at(d, ALB_ERR_IO, path, 0, 0, "cannot open: %s", strerror(errno));
    int rc = alb_file_read_all(f, buf, len);
    int err = errno;
    fclose(f);
    if (rc == -2)
        return alb_diag_at(d, ALB_ERR_NOMEM, path, 0, 0, "too large for memory");
    if (rc)
        return alb_diag_at(d, ALB_ERR_IO, path, 0, 0, "read error: %s", strerror(err));
    return ALB_OK;
}
