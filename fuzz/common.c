/* common.c — what the harnesses share: the per-process scratch directory
 * (made once with mkdtemp, reused by every run, each run overwriting its
 * fixed file names, emptied and removed at exit: the only state outside the
 * harnesses) and the GP run every accepted scene gets. */
#include "fuzz.h"
#include "albatros/profile.h"
#include "albatros/words.h"
#include "albatros/gp.h"

#include <dirent.h>
#include <png.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/types.h>
#include <unistd.h>

static char scratch_dir[256];   /* "" until made */
static pid_t scratch_owner;      /* the process that made it removes it */

static void scratch_remove(void)
{
    if (getpid() != scratch_owner)   /* a child of fuzz/replay.c exiting */
        return;
    DIR *dir = opendir(scratch_dir);
    if (dir) {
        struct dirent *e;
        while ((e = readdir(dir))) {
            char path[512];
            if (strcmp(e->d_name, ".") && strcmp(e->d_name, ".."))
                if (snprintf(path, sizeof path, "%s/%s", scratch_dir, e->d_name) <
                    (int)sizeof path)
                    unlink(path);
        }
        closedir(dir);
    }
    rmdir(scratch_dir);
}

const char *fuzz_tmpdir(void)
{
    if (scratch_dir[0])
        return scratch_dir;
    const char *base = getenv("TMPDIR");
    if (!base || !*base || strlen(base) > 200)
        base = "/tmp";
    char tmpl[sizeof scratch_dir];
    snprintf(tmpl, sizeof tmpl, "%s/albatros-fuzz-XXXXXX", base);
    if (!mkdtemp(tmpl))
        return NULL;
    memcpy(scratch_dir, tmpl, sizeof scratch_dir);
    scratch_owner = getpid();
    atexit(scratch_remove);
    return scratch_dir;
}

int fuzz_write(const char *name, const void *data, size_t size, char *path, size_t len)
{
    const char *dir = fuzz_tmpdir();
    if (!dir || snprintf(path, len, "%s/%s", dir, name) >= (int)len)
        return -1;
    FILE *f = fopen(path, "wb");
    if (!f)
        return -1;
    int bad = size && fwrite(data, 1, size, f) != size;
    bad |= fclose(f) != 0;
    return bad ? -1 : 0;
}

int fuzz_write_png(const char *name, unsigned w, unsigned h)
{
    char path[512];
    if (fuzz_write(name, "", 0, path, sizeof path))
        return -1;
    uint8_t *rgb = malloc((size_t)w * h * 3);
    if (!rgb)
        return -1;
    for (size_t i = 0; i < (size_t)w * h; i++) {
        rgb[3 * i] = (uint8_t)(i * 37);
        rgb[3 * i + 1] = (uint8_t)(i * 11);
        rgb[3 * i + 2] = (uint8_t)(255 - i);
    }
    png_image img;
    memset(&img, 0, sizeof img);
    img.version = PNG_IMAGE_VERSION;
    img.width = w;
    img.height = h;
    img.format = PNG_FORMAT_RGB;
    int ok = png_image_write_to_file(&img, path, 0, rgb, 0, NULL);
    png_image_free(&img);
    free(rgb);
    return ok ? 0 : -1;
}

/* The GP's stream decodes to its END: a GP that emits words its own decoder
 * rejects is a bug, reported as a crash. */
static void check_stream(const alb_ws_buf *b)
{
    alb_ws_reader r;
    alb_ws_event *ev = malloc(sizeof *ev);
    alb_diag d;
    alb_diag_init(&d, NULL);
    if (!ev)
        return;
    alb_ws_reader_init(&r, b->w, b->n, "<gp>");
    while (!r.ended) {
        if (alb_ws_next(&r, ev, &d)) {
            fprintf(stderr, "fuzz: the GP emitted a stream its decoder rejects: offset %lld: "
                            "%s\n", d.offset, d.msg);
            abort();
        }
    }
    free(ev);
}

static unsigned face_count(const alb_scene *s)
{
    unsigned n = 0;
    for (unsigned i = 0; i < s->nobj; i++)
        n += s->obj[i].nf;
    return n;
}

int fuzz_run_gp(const alb_scene *s, const alb_profile *prof, alb_ws_buf *out)
{
    if ((unsigned long long)s->nframes * (face_count(s) + 1) > FUZZ_GP_WORK_MAX)
        return -1;
    alb_diag d;
    alb_diag_init(&d, NULL);
    alb_gp *gp = NULL;
    alb_ws_buf b;
    alb_ws_buf_init(&b);
    int rc = -1;
    if (alb_gp_create(&gp, s, prof, &d) == ALB_OK && alb_gp_run(gp, &b, NULL, &d) == ALB_OK) {
        check_stream(&b);
        rc = 0;
    }
    alb_gp_destroy(gp);
    if (!rc && out)
        *out = b;
    else
        alb_ws_buf_free(&b);
    return rc;
}
