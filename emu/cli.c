/* cli.c — option parsing and set-up shared by the subcommands. */
/* realpath (XSI) */
#define _XOPEN_SOURCE 700
#include "cli.h"
#include "../common/vec3.h"

#include <ctype.h>
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

const char run_opts_help[] =
    "Profile (docs/profiles.md):\n"
    "  --profile NAME     family member: a512 (default), a1024, a1024x512, a256, t32\n"
    "  --set KEY=VALUE    override a profile field, e.g. --set bound=none --set aa=2\n"
    "Camera for OBJ scenes, in the OBJ file's coordinates (docs/scene-format.md):\n"
    "  --eye X,Y,Z        eye point (default 0,0,5)\n"
    "  --at X,Y,Z         look-at point (default 0,0,0)\n"
    "  --up X,Y,Z         up vector (default 0,1,0)\n"
    "  --fov DEG          vertical field of view (default 60)\n"
    "  --size WxH         resolution (sets the profile's width and height)\n"
    "Depth (docs/vp.md, section 4; every scene, OBJ or not):\n"
    "  --near D           the depth scale: the depth store holds near/Z, saturating\n"
    "                     nearer than D and resolving Z to about Z^2 / (D 2^depth_bits);\n"
    "                     replaces the scene's `near` (default 0.1, OBJ files too)\n";

void run_opts_init(run_opts *o)
{
    memset(o, 0, sizeof *o);
    alb_profile_lookup("a512", &o->prof);
    o->cam.eye = v3(0, 0, 5);
    o->cam.at = v3(0, 0, 0);
    o->cam.up = v3(0, 1, 0);
    o->cam.fov_y = 60;
}

static int parse_vec(const char *s, vec3 *v)
{
    char *end;
    double c[3];
    for (int i = 0; i < 3; i++) {
        c[i] = strtod(s, &end);
        if (end == s || !isfinite(c[i]))
            return -1;
        s = end;
        if (i < 2) {
            if (*s != ',')
                return -1;
            s++;
        }
    }
    if (*s)
        return -1;
    *v = v3(c[0], c[1], c[2]);
    return 0;
}

/* One side of --size at *s: decimal digits (sscanf's %u would take "-1" as
 * 4294967295 and wrap 4294967298 to 2).  *v saturates above the largest
 * side, so any length of digits is safe. */
static bool parse_side(const char **s, unsigned long *v)
{
    const char *p = *s;
    *v = 0;
    for (; *p >= '0' && *p <= '9'; p++)
        if (*v <= ALB_PROFILE_MAX_SIDE)
            *v = *v * 10 + (unsigned long)(*p - '0');
    if (p == *s)
        return false;
    *s = p;
    return true;
}

static int parse_size(run_opts *o, const char *value, char *err, size_t len)
{
    const char *s = value, *hs = NULL;
    unsigned long w, h;
    bool ok = parse_side(&s, &w) && *s == 'x';
    if (ok) {
        hs = ++s;
        ok = parse_side(&s, &h) && *s == 0;
    }
    if (!ok) {
        snprintf(err, len, "--size %s: expected WIDTHxHEIGHT, e.g. 512x512", value);
        return -1;
    }
    if (w > ALB_PROFILE_MAX_SIDE || h > ALB_PROFILE_MAX_SIDE) {   /* quoted as written */
        if (w > ALB_PROFILE_MAX_SIDE)
            snprintf(err, len, "--size %s: width %.*s is too large (at most %d)", value,
                     (int)(hs - 1 - value), value, ALB_PROFILE_MAX_SIDE);
        else
            snprintf(err, len, "--size %s: height %s is too large (at most %d)", value, hs,
                     ALB_PROFILE_MAX_SIDE);
        return -1;
    }
    o->cam.width = o->prof.width = (unsigned)w;
    o->cam.height = o->prof.height = (unsigned)h;
    return 1;
}

/* One --set or --size on the profile as it stands. */
static int apply_override(run_opts *o, bool is_size, const char *value, char *err, size_t len)
{
    if (is_size)
        return parse_size(o, value, err, len);
    if (!strncmp(value, "near=", 5)) {
        snprintf(err, len, "--set %s: near is the scene's depth scale, not a profile field: use "
                 "--near %s", value, value + 5);
        return -1;
    }
    char msg[300];
    if (alb_profile_set(&o->prof, value, msg, sizeof msg)) {
        snprintf(err, len, "--set %s", msg);
        return -1;
    }
    return 1;
}

/* Apply a --set or --size now and remember it for any later --profile. */
static int add_override(run_opts *o, bool is_size, const char *value, char *err, size_t len)
{
    if (o->noverrides == RUN_OPTS_MAX_OVERRIDES) {
        snprintf(err, len, "--%s %s: at most %d --set and --size options", is_size ? "size" : "set",
                 value, RUN_OPTS_MAX_OVERRIDES);
        return -1;
    }
    int rc = apply_override(o, is_size, value, err, len);
    if (rc > 0) {
        o->overrides[o->noverrides].is_size = is_size;
        o->overrides[o->noverrides++].value = value;
    }
    return rc;
}

/* A new profile, then every --set and --size so far in their order: the
 * options' result does not depend on where --profile stands
 * (docs/profiles.md). */
static int apply_profile(run_opts *o, const char *value, char *err, size_t len)
{
    alb_profile p;
    if (alb_profile_lookup(value, &p)) {
        char list[200] = "";
        for (const char *const *n = alb_profile_names(); *n; n++)
            snprintf(list + strlen(list), sizeof list - strlen(list), " %s", *n);
        snprintf(err, len, "--profile %s: unknown profile (known:%s)", value, list);
        return -1;
    }
    o->prof = p;
    for (unsigned i = 0; i < o->noverrides; i++)
        if (apply_override(o, o->overrides[i].is_size, o->overrides[i].value, err, len) < 0)
            return -1;
    return 1;
}

int run_opts_apply(run_opts *o, const char *name, const char *value, char *err, size_t len)
{
    if (strcmp(name, "profile") == 0)
        return apply_profile(o, value, err, len);
    if (strcmp(name, "set") == 0 || strcmp(name, "size") == 0)
        return add_override(o, strcmp(name, "size") == 0, value, err, len);
    if (strcmp(name, "eye") == 0 || strcmp(name, "at") == 0 || strcmp(name, "up") == 0) {
        vec3 *v = name[0] == 'e' ? &o->cam.eye : name[0] == 'a' ? &o->cam.at : &o->cam.up;
        if (parse_vec(value, v)) {
            snprintf(err, len, "--%s %s: expected three numbers X,Y,Z", name, value);
            return -1;
        }
        o->cam_given = true;
        return 1;
    }
    if (strcmp(name, "near") == 0) {
        char *end;
        double v = strtod(value, &end);
        /* the word stream stores near as IEEE-754 binary32 (docs/word-format.md §1) */
        if (end == value || *end || !(v >= FLT_MIN && v <= FLT_MAX)) {
            snprintf(err, len, "--near %s: expected a distance in %g .. %g (the word stream "
                     "stores near as IEEE-754 binary32)", value, FLT_MIN, FLT_MAX);
            return -1;
        }
        o->near = v;
        o->near_given = true;
        return 1;
    }
    if (strcmp(name, "fov") == 0) {
        char *end;
        double v = strtod(value, &end);
        if (end == value || *end || !(v > 0 && v < 180)) {
            snprintf(err, len, "--fov %s: expected degrees in (0, 180)", value);
            return -1;
        }
        o->cam.fov_y = v;
        o->cam_given = true;
        return 1;
    }
    return 0;
}

static const char *const common_spec[] = {"profile=", "set=", "eye=", "at=", "up=",
                                           "fov=", "size=", "near=", NULL};

/* Does spec contain name, and does it take a value? 0 = absent, 1 = flag, 2 = value. */
static int spec_kind(const char *const *spec, const char *name, size_t nlen)
{
    for (; spec && *spec; spec++) {
        size_t l = strlen(*spec);
        bool val = l && (*spec)[l - 1] == '=';
        if (val)
            l--;
        if (l == nlen && strncmp(*spec, name, nlen) == 0)
            return val ? 2 : 1;
    }
    return 0;
}

int cli_parse(const char *cmd, int argc, char **argv, const char *const *spec, opt_cb cb,
              void *ctx, run_opts *o, const char **pos, int maxpos, int *npos)
{
    *npos = 0;
    bool only_pos = false;
    for (int i = 0; i < argc; i++) {
        const char *a = argv[i];
        if (only_pos || a[0] != '-' || a[1] == 0) {
            if (*npos >= maxpos) {
                fprintf(stderr, "albatros %s: unexpected argument '%s' (see --help)\n", cmd, a);
                return -1;
            }
            pos[(*npos)++] = a;
            continue;
        }
        if (strcmp(a, "--") == 0) {
            only_pos = true;
            continue;
        }
        const char *name = a[1] == '-' ? a + 2 : a + 1;
        if (a[1] != '-' && strlen(name) == 1 && name[0] == 'o')
            name = "output";
        if (a[1] != '-' && strlen(name) == 1 && name[0] == 'h')
            name = "help";
        const char *eq = strchr(name, '=');
        size_t nlen = eq ? (size_t)(eq - name) : strlen(name);
        int own = spec_kind(spec, name, nlen), common = o ? spec_kind(common_spec, name, nlen) : 0;
        int kind = own ? own : common;
        if (!kind) {
            fprintf(stderr, "albatros %s: unknown option '%s' (see albatros %s --help)\n", cmd, a, cmd);
            return -1;
        }
        char namebuf[64];
        snprintf(namebuf, sizeof namebuf, "%.*s", (int)nlen, name);
        const char *value = NULL;
        if (kind == 2) {
            if (eq)
                value = eq + 1;
            else if (i + 1 < argc)
                value = argv[++i];
            else {
                fprintf(stderr, "albatros %s: option '--%s' needs a value\n", cmd, namebuf);
                return -1;
            }
        } else if (eq) {
            fprintf(stderr, "albatros %s: option '--%s' takes no value\n", cmd, namebuf);
            return -1;
        }
        if (own) {
            if (cb(ctx, namebuf, value))
                return -1;
        } else {
            char err[400];
            if (run_opts_apply(o, namebuf, value, err, sizeof err) < 0) {
                fprintf(stderr, "albatros %s: %s\n", cmd, err);
                return -1;
            }
        }
    }
    /* The camera as a whole (--up along --eye..--at, say) is an option error
     * like any other, reported here rather than when an OBJ is read. */
    if (o) {
        alb_diag d;
        alb_diag_init(&d, NULL);
        if (alb_scene_camera_check(&o->cam, &d)) {
            fprintf(stderr, "albatros %s: %s\n", cmd, d.msg);
            return -1;
        }
    }
    return 0;
}

static bool ends_with(const char *s, const char *suffix)
{
    size_t a = strlen(s), b = strlen(suffix);
    if (a < b)
        return false;
    for (size_t i = 0; i < b; i++)
        if (tolower((unsigned char)s[a - b + i]) != suffix[i])
            return false;
    return true;
}

int cli_load_scene(const char *path, const run_opts *o, alb_scene *s)
{
    alb_diag d;
    alb_diag_init(&d, stderr);
    alb_err e;
    if (!path) {
        e = alb_scene_load_builtin(s, &d);
    } else if (ends_with(path, ".obj")) {
        alb_scene_camera cam = o->cam;
        cam.width = o->prof.width;
        cam.height = o->prof.height;
        e = alb_scene_load_obj(path, &cam, s, &d);
    } else {
        if (o->cam_given)
            fprintf(stderr, "albatros: warning: --eye/--at/--up/--fov apply to OBJ scenes only; "
                            "%s has its own observer\n", path);
        e = alb_scene_load(path, s, &d);
    }
    if (!e && (e = alb_scene_resolve_screenspace(s, o->prof.width, o->prof.height, &d)))
        alb_scene_free(s);
    if (e) {
        alb_diag_print(&d, stderr);
        return 1;
    }
    if (o->near_given) {
        /* the depth scale alone: near/Z for every surface (a screen-space
         * scene's near D/Dmax too), nothing else of the scene moves */
        s->near = o->near;
        s->near_line = s->near_col = 0;
    }
    return 0;
}

bool cli_is_obj(const char *path) { return path && ends_with(path, ".obj"); }

int cli_check_profile(const alb_profile *p)
{
    char msg[300];
    if (alb_profile_check(p, msg, sizeof msg)) {
        fprintf(stderr, "albatros: profile %s: %s\n", p->name, msg);
        return 1;
    }
    /* the screen spans 2 units of the intercept format: 2^(levels-1)
     * samples per unit, so F - levels + 1 bits fall below a sample */
    int below = (int)p->edge_frac_bits - (int)alb_profile_levels(p) + 1;
    if (below < 2)
        fprintf(stderr, "albatros: warning: edge_frac_bits=%u leaves %d bit%s below the sample "
                        "grid: edges snap to %s of a sample; use edge_frac_bits >= %u\n",
                p->edge_frac_bits, below, below == 1 ? "" : "s",
                below >= 1 ? "halves" : "multiples", alb_profile_levels(p) + 1);
    return 0;
}

int cli_split_words(char *text, char **argv, int max)
{
    int n = 0;
    char *p = text;
    for (;;) {
        while (*p && isspace((unsigned char)*p))
            p++;
        if (!*p)
            break;
        if (*p == '#') {      /* comment to end of line */
            while (*p && *p != '\n')
                p++;
            continue;
        }
        if (n == max)
            return -1;
        argv[n++] = p;
        while (*p && !isspace((unsigned char)*p))
            p++;
        if (*p)
            *p++ = 0;
    }
    return n;
}

bool cli_isatty_stderr(void) { return isatty(2) != 0; }

void cli_frame_path(char *out, size_t len, const char *path, unsigned number, unsigned nframes)
{
    const char *dot = strrchr(path, '.'), *slash = strrchr(path, '/');
    if (nframes <= 1) {
        snprintf(out, len, "%s", path);
        return;
    }
    if (!dot || (slash && dot < slash))
        dot = path + strlen(path);
    snprintf(out, len, "%.*s.%04u%s", (int)(dot - path), path, number, dot);
}

const char *cli_argv0 = "albatros";

void cli_print_self(FILE *f)
{
    char *abs = strchr(cli_argv0, '/') ? realpath(cli_argv0, NULL) : NULL;
    const char *self = abs ? abs : cli_argv0;
    /* a shell word: quoted if it holds anything but safe characters */
    if (strspn(self, "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789/._-+") ==
        strlen(self)) {
        fputs(self, f);
    } else {
        fputc('\'', f);
        for (const char *p = self; *p; p++)
            *p == '\'' ? fputs("'\\''", f) : fputc(*p, f);
        fputc('\'', f);
    }
    free(abs);
}
