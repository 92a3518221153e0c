/* cmd_scene.c — `albatros scene KIND`: write a generated scene (random
 * polygons, slivers) for experiments and measurements. */
#include "cli.h"
#include "commands.h"
#include "../tools/scenegen.h"

#include <stdlib.h>
#include <string.h>

typedef struct {
    const char *output;
    unsigned long long seed, faces, per_angle;
    bool help, flat;
    double size;
} scene_args;

static int scene_opt(void *ctx, const char *name, const char *value)
{
    scene_args *a = ctx;
    if (strcmp(name, "output") == 0) {
        a->output = value;
        return 0;
    }
    if (strcmp(name, "help") == 0 || strcmp(name, "flat") == 0) {
        *(name[0] == 'h' ? &a->help : &a->flat) = true;
        return 0;
    }
    char *end;
    if (strcmp(name, "size") == 0) {
        double r = strtod(value, &end);
        if (end == value || *end || !(r > 0 && r <= 10)) {
            fprintf(stderr, "albatros scene: --size %s: expected a radius over distance in "
                            "(0, 10]\n", value);
            return -1;
        }
        a->size = r;
        return 0;
    }
    unsigned long long v = strtoull(value, &end, 10);
    if (end == value || *end || v > 10000000ull) {
        fprintf(stderr, "albatros scene: --%s %s: expected a number up to 10000000\n", name, value);
        return -1;
    }
    if (strcmp(name, "seed") == 0)
        a->seed = v;
    else if (strcmp(name, "faces") == 0)
        a->faces = v;
    else
        a->per_angle = v;
    return 0;
}

int cmd_scene(int argc, char **argv)
{
    static const char *const spec[] = {"output=", "seed=", "faces=", "per-angle=", "flat", "size=",
                                       "help", NULL};
    scene_args a = {NULL, 1, 12, 6, false, false, 0};
    const char *pos[1];
    int npos;
    if (cli_parse("scene", argc, argv, spec, scene_opt, &a, NULL, pos, 1, &npos))
        return 2;
    if (a.help || npos != 1 || (strcmp(pos[0], "random") && strcmp(pos[0], "slivers"))) {
        printf("usage: albatros scene random [--faces N] [--seed S] [--flat] [--size R] [-o FILE]\n"
               "       albatros scene slivers [--per-angle K] [--seed S] [-o FILE]\n\n"
               "Write a generated scene (docs/scene-format.md) to FILE or stdout:\n"
               "  random   N convex polygons, overlapping, some crossing Z = 0 or back-facing;\n"
               "           intensity per vertex, or one colour per face with --flat;\n"
               "           mean radius R times the distance (default 0.3)\n"
               "  slivers  K triangles for each tip angle from 10 down to 0.01 degrees\n");
        return a.help ? 0 : 2;
    }
    char *text;
    if (pos[0][0] == 'r') {
        scenegen_params p = scenegen_defaults();
        p.faces = (unsigned)a.faces;
        p.flat = a.flat;
        if (a.size > 0)
            p.size = a.size;
        text = scenegen_random(a.seed, &p);
    } else {
        text = scenegen_slivers(a.seed, (unsigned)a.per_angle);
    }
    if (!text) {
        fprintf(stderr, "albatros scene: out of memory\n");
        return 1;
    }
    FILE *f = a.output ? fopen(a.output, "w") : stdout;
    int rc = 0;
    if (!f || fputs(text, f) < 0 || (a.output && fclose(f))) {
        fprintf(stderr, "albatros scene: cannot write %s\n", a.output ? a.output : "stdout");
        rc = 1;
    }
    free(text);
    return rc;
}
