/* file.c — whole-file reads (file.h). */
#include "albatros/file.h"

#include <stdint.h>
#include <stdlib.h>

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
