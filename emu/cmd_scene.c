/* cmd_scene.c — `albatros scene KIND`: write a generated scene (random
 * polygons, slivers, or one of the stress families of tools/stress.h at a
 * severity) for experiments and measurements. */
#include "cli.h"
#include "commands.h"
#include "albatros/file.h"
#include "../tools/scenegen.h"
#include "../tools/stress.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
    const char *output;
    unsigned long long seed, faces, per_angle;
    bool help, flat, severity_given;
    double size, severity;
    double behind, backfacing;   /* < 0: the generator's default */
    /* the first option given that only one generator takes, for the error
     * when another generator is chosen */
    const char *random_only, *slivers_only;
} scene_args;

static int scene_opt(void *ctx, const char *name, const char *value)
{
    scene_args *a = ctx;
    if (strcmp(name, "output") == 0) {
        a->output = value;
        return 0;
    }
    if (strcmp(name, "help") == 0) {
        a->help = true;
        return 0;
    }
    if (strcmp(name, "flat") == 0) {
        a->flat = true;
        a->random_only = a->random_only ? a->random_only : "--flat";
        return 0;
    }
    char *end;
    if (strcmp(name, "severity") == 0) {
        double v = strtod(value, &end);
        if (end == value || *end || !isfinite(v)) {
            fprintf(stderr, "albatros scene: --severity %s: expected a number\n", value);
            return -1;
        }
        a->severity = v;
        a->severity_given = true;
        return 0;
    }
    if (strcmp(name, "behind") == 0 || strcmp(name, "backfacing") == 0) {
        double f = strtod(value, &end);
        if (end == value || *end || !(f >= 0 && f <= 1)) {
            fprintf(stderr, "albatros scene: --%s %s: expected a fraction in [0, 1]\n", name,
                    value);
            return -1;
        }
        *(name[1] == 'e' ? &a->behind : &a->backfacing) = f;
        a->random_only = a->random_only ? a->random_only : name[1] == 'e' ? "--behind"
                                                                           : "--backfacing";
        return 0;
    }
    if (strcmp(name, "size") == 0) {
        double r = strtod(value, &end);
        if (end == value || *end || !(r > 0 && r <= 10)) {
            fprintf(stderr, "albatros scene: --size %s: expected a radius over distance in "
                            "(0, 10]\n", value);
            return -1;
        }
        a->size = r;
        a->random_only = a->random_only ? a->random_only : "--size";
        return 0;
    }
    unsigned long long v = strtoull(value, &end, 10);
    if (end == value || *end || v > 10000000ull) {
        fprintf(stderr, "albatros scene: --%s %s: expected a number up to 10000000\n", name, value);
        return -1;
    }
    /* a scene needs an object: 0 faces or 0 slivers would make one that
     * every reader refuses ("scene has no objects") */
    if (v == 0 && strcmp(name, "seed")) {
        fprintf(stderr, "albatros scene: --%s 0: expected 1 to 10000000 (a scene needs a "
                        "face)\n", name);
        return -1;
    }
    if (strcmp(name, "seed") == 0) {
        a->seed = v;
    } else if (strcmp(name, "faces") == 0) {
        a->faces = v;
        a->random_only = a->random_only ? a->random_only : "--faces";
    } else {
        a->per_angle = v;
        a->slivers_only = a->slivers_only ? a->slivers_only : "--per-angle";
    }
    return 0;
}

static bool is_stress_family(const char *name)
{
    for (const char *const *f = stress_families(); *f; f++)
        if (strcmp(*f, name) == 0)
            return true;
    return false;
}

static void scene_usage(void)
{
    printf("usage: albatros scene random [--faces N] [--seed S] [--flat] [--size R]\n"
           "                            [--behind F] [--backfacing F] [-o FILE]\n"
           "       albatros scene slivers [--per-angle K] [--seed S] [-o FILE]\n"
           "       albatros scene FAMILY --severity X [--seed S] [-o FILE]\n\n"
           "Write a generated scene (docs/scene-format.md) to FILE or stdout:\n"
           "  random   N convex polygons, overlapping, some crossing Z = 0 or back-facing;\n"
           "           intensity per vertex, or one colour per face with --flat;\n"
           "           mean radius R times the distance (default 0.3); a fraction F\n"
           "           of them crossing Z = 0 (--behind, default 0.1) or wound away\n"
           "           from the observer (--backfacing, default 0.1)\n"
           "  slivers  K triangles for each tip angle from 10 down to 0.01 degrees\n"
           "  FAMILY   a stress scene of albatros stability (docs/methods.md, \"Stress\n"
           "           families\"; the severity is clamped to the family's range):\n"
           "          ");
    for (const char *const *f = stress_families(); *f; f++)
        printf(" %s", *f);
    printf("\n");
}

/* An option of another generator is an error, not silently ignored. */
static int check_applies(const scene_args *a, const char *kind)
{
    const char *stray = strcmp(kind, "random") && a->random_only ? a->random_only
                        : strcmp(kind, "slivers") && a->slivers_only ? a->slivers_only
                                                                     : NULL;
    if (!stray)
        return 0;
    fprintf(stderr, "albatros scene: %s: %s is for %s only\n", kind, stray,
            stray == a->random_only ? "random" : "slivers");
    return -1;
}

int cmd_scene(int argc, char **argv)
{
    static const char *const spec[] = {"output=", "seed=", "faces=", "per-angle=", "flat", "size=",
                                       "severity=", "behind=", "backfacing=", "help", NULL};
    scene_args a = {.seed = 1, .faces = 12, .per_angle = 6, .behind = -1, .backfacing = -1};
    const char *pos[1];
    int npos;
    int parsed = cli_parse("scene", argc, argv, spec, scene_opt, &a, NULL, pos, 1, &npos);
    if (parsed)
        return CLI_PARSE_EXIT(parsed);
    bool stress = npos == 1 && is_stress_family(pos[0]);
    if (a.help || npos != 1 || (strcmp(pos[0], "random") && strcmp(pos[0], "slivers") && !stress)) {
        if (!a.help && npos == 1)
            fprintf(stderr, "albatros scene: unknown kind '%s'\n", pos[0]);
        scene_usage();
        return a.help ? 0 : 2;
    }
    if (stress != a.severity_given) {
        fprintf(stderr, stress ? "albatros scene: %s: give --severity X (docs/methods.md)\n"
                               : "albatros scene: %s: --severity is for the stress families\n",
                pos[0]);
        return 2;
    }
    if (check_applies(&a, pos[0]))
        return 2;
    char *text;
    if (stress) {
        text = stress_scene(pos[0], a.severity, a.seed);
    } else if (pos[0][0] == 'r') {
        scenegen_params p = scenegen_defaults();
        p.faces = (unsigned)a.faces;
        p.flat = a.flat;
        if (a.size > 0)
            p.size = a.size;
        if (a.behind >= 0)
            p.behind = a.behind;
        if (a.backfacing >= 0)
            p.backfacing = a.backfacing;
        text = scenegen_random(a.seed, &p);
    } else {
        text = scenegen_slivers(a.seed, (unsigned)a.per_angle);
    }
    if (!text) {
        fprintf(stderr, "albatros scene: out of memory\n");
        return 1;
    }
    /* a file only once complete (file.h); stdout is checked at exit */
    int rc = 0;
    alb_out out;
    alb_diag d;
    alb_diag_init(&d, NULL);
    const char *path = a.output ? a.output : "-";
    FILE *f = NULL;
    if ((rc = cli_output("scene", "-o", path))) {
        /* said why */
    } else if (alb_out_open(&out, path, ALB_OUT_DASH, &d) || !(f = alb_out_stdio(&out, &d))) {
        rc = 1;
    } else {
        fputs(text, f);
        rc = alb_out_commit(&out, &d) ? 1 : 0;
    }
    if (rc && d.msg[0])
        alb_diag_print(&d, stderr);
    free(text);
    return rc;
}
