/* cmd_compare.c — `albatros compare A.exr B.exr`: how two frames differ —
 * pixels with a different face, colour error (max, mean, PSNR) — with a diff
 * image.  Exit status as cmp(1): 0 identical, 1 different, 2 trouble. */
#include "cli.h"
#include "commands.h"
#include "exr.h"
#include "preview.h"

#include <math.h>
#include <string.h>

typedef struct {
    const char *diff;
    bool json, help;
} compare_args;

static int compare_opt(void *ctx, const char *name, const char *value)
{
    compare_args *a = ctx;
    if (strcmp(name, "diff") == 0)
        a->diff = value;
    else if (strcmp(name, "json") == 0)
        a->json = true;
    else if (strcmp(name, "help") == 0)
        a->help = true;
    return 0;
}

int cmd_compare(int argc, char **argv)
{
    static const char *const spec[] = {"diff=", "json", "help", NULL};
    compare_args a = {0};
    const char *pos[2];
    int npos;
    if (cli_parse("compare", argc, argv, spec, compare_opt, &a, NULL, pos, 2, &npos))
        return 2;
    if (a.help || npos != 2) {
        printf("usage: albatros compare A.exr B.exr [--diff DIFF.png] [--json]\n\n"
               "Compare two frames: pixels whose face differs, colour error in frame-store\n"
               "units (max, mean, PSNR), and a diff image (red: face differs, yellow: colour\n"
               "only, grey: equal).  Exit 0 if identical, 1 if they differ, 2 on error.\n");
        return a.help ? 0 : 2;
    }
    frame_t f[2];
    diag_t d;
    diag_init(&d, NULL);
    memset(f, 0, sizeof f);
    for (int i = 0; i < 2; i++)
        if (exr_read_frame(pos[i], &f[i], &d)) {
            diag_print(&d, stderr);
            if (i)
                frame_free(&f[0]);
            return 2;
        }
    int rc = 2;
    if (f[0].width != f[1].width || f[0].height != f[1].height ||
        f[0].colour_bits != f[1].colour_bits) {
        fprintf(stderr, "albatros compare: %s is %ux%u (%u-bit colour), %s is %ux%u (%u-bit)\n",
                pos[0], f[0].width, f[0].height, f[0].colour_bits, pos[1], f[1].width,
                f[1].height, f[1].colour_bits);
        goto done;
    }
    frame_diff r;
    frame_compare(&f[0], &f[1], &r);
    if (a.diff && preview_write_diff(a.diff, &f[0], &f[1], NULL, NULL, &d)) {
        diag_print(&d, stderr);
        goto done;
    }
    if (a.json)
        printf("{\"pixels\": %zu, \"face_diff\": %zu, \"colour_diff\": %zu, \"coverage_diff\": "
               "%zu, \"max_error\": %u, \"mean_error\": %.6f, \"psnr\": %.3f}\n",
               r.pixels, r.face_diff, r.colour_diff, r.coverage_diff, r.max_error, r.mean_error,
               isinf(r.psnr) ? 999.0 : r.psnr);
    else
        printf("%zu pixels: %zu with a different face (%.4f%%), %zu with a different colour; "
               "colour error max %u, mean %.4f, PSNR %s%.2f dB\n",
               r.pixels, r.face_diff, 100.0 * (double)r.face_diff / (double)r.pixels,
               r.colour_diff, r.max_error, r.mean_error, isinf(r.psnr) ? "inf " : "",
               isinf(r.psnr) ? 0.0 : r.psnr);
    rc = (r.face_diff || r.colour_diff || r.coverage_diff) ? 1 : 0;
done:
    frame_free(&f[0]);
    frame_free(&f[1]);
    return rc;
}
