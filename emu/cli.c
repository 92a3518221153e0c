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
#include <errno.h>
#include <stdint.h>
#include <sys/stat.h>
#include "albatros/file.h"
#include "albatros/dump.h"

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
        if (end == value || *end || !(v >= ALB_SCENE_MIN_FOV && v < 180)) {
            snprintf(err, len, "--fov %s: expected degrees in [%g, 180)", value, ALB_SCENE_MIN_FOV);
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

/* Does spec contain name, and does it take a value? 0 = absent, 1 = flag,
 * 2 = value, 3 = a value only as --name=VALUE ("name=?": --sim, --sim=rtl). */
static int spec_kind(const char *const *spec, const char *name, size_t nlen)
{
    for (; spec && *spec; spec++) {
        size_t l = strlen(*spec);
        bool opt = l > 2 && !strcmp(*spec + l - 2, "=?");
        bool val = !opt && l && (*spec)[l - 1] == '=';
        l -= opt ? 2 : val;
        if (l == nlen && strncmp(*spec, name, nlen) == 0)
            return opt ? 3 : val ? 2 : 1;
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
        /* every subcommand, as the top level (docs: albatros --version) */
        if (strcmp(a, "--version") == 0) {
            printf("albatros %s\n", ALBATROS_VERSION);
            return 1;
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
        } else if (kind == 3) {
            value = eq ? eq + 1 : NULL;
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
    if (!e) {   /* no output may overwrite what the scene was read from */
        cli_input(path);
        for (unsigned i = 0; i < s->nfiles; i++)
            cli_input(s->files[i]);
    }
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

char *cli_frame_path(const char *path, unsigned number, unsigned nframes)
{
    const char *dot = strrchr(path, '.'), *slash = strrchr(path, '/');
    struct stat st;
    /* a device or FIFO takes every frame, as it is: /dev/null.0000 would
     * be a new file in /dev */
    if (nframes <= 1 || (stat(path, &st) == 0 && !S_ISREG(st.st_mode) && !S_ISDIR(st.st_mode)))
        return alb_strprintf("%s", path);
    if (!dot || (slash && dot < slash))
        dot = path + strlen(path);
    return alb_strprintf("%.*s.%04u%s", (int)(dot - path), path, number, dot);
}

/* ---- the files a command reads and writes ----
 * Every input and output is claimed by the file it names (device and
 * inode, or directory entry: alb_file_identify), so that no output
 * overwrites an input or another output of the same run however the two
 * paths are spelled.  Two hash indexes, by file and by entry, keep a run of
 * a hundred thousand numbered frames linear. */

typedef struct {
    alb_file_id id;
    char *path, *what;
    bool input;
} claim;

static struct {
    claim *c;
    size_t n, cap;
    size_t *by_file, *by_entry;   /* claim index + 1; 0 empty */
    size_t slots;                 /* of each index, a power of two */
} claims;

static uint64_t mix(uint64_t h, uint64_t v)
{
    h ^= v + 0x9E3779B97F4A7C15u + (h << 6) + (h >> 2);
    return h * 0xBF58476D1CE4E5B9u;
}

static size_t hash_file(const alb_file_id *id) { return (size_t)mix(mix(1, id->dev), id->ino); }

static size_t hash_entry(const alb_file_id *id)
{
    uint64_t h = mix(mix(2, id->dir_dev), id->dir_ino);
    for (const char *p = id->name; *p; p++)
        h = mix(h, (unsigned char)*p);
    return (size_t)h;
}

static bool same_file(const alb_file_id *a, const alb_file_id *b)
{
    return a->exists && b->exists && a->dev == b->dev && a->ino == b->ino;
}

static bool same_entry(const alb_file_id *a, const alb_file_id *b)
{
    return a->dir_dev == b->dir_dev && a->dir_ino == b->dir_ino && !strcmp(a->name, b->name);
}

static void index_claim(size_t k)
{
    const alb_file_id *id = &claims.c[k].id;
    size_t mask = claims.slots - 1, i;
    if (id->exists) {
        for (i = hash_file(id) & mask; claims.by_file[i]; i = (i + 1) & mask)
            ;
        claims.by_file[i] = k + 1;
    }
    for (i = hash_entry(id) & mask; claims.by_entry[i]; i = (i + 1) & mask)
        ;
    claims.by_entry[i] = k + 1;
}

/* The claim naming the same file as id, or NULL. */
static const claim *find_claim(const alb_file_id *id)
{
    if (!claims.slots)
        return NULL;
    size_t mask = claims.slots - 1, i;
    if (id->exists)
        for (i = hash_file(id) & mask; claims.by_file[i]; i = (i + 1) & mask)
            if (same_file(&claims.c[claims.by_file[i] - 1].id, id))
                return &claims.c[claims.by_file[i] - 1];
    for (i = hash_entry(id) & mask; claims.by_entry[i]; i = (i + 1) & mask)
        if (same_entry(&claims.c[claims.by_entry[i] - 1].id, id))
            return &claims.c[claims.by_entry[i] - 1];
    return NULL;
}

static int add_claim(alb_file_id *id, const char *path, const char *what, bool input)
{
    if (claims.n == claims.cap) {
        size_t cap = claims.cap ? 2 * claims.cap : 16;
        claim *c = realloc(claims.c, cap * sizeof *c);
        if (!c)
            return -1;
        claims.c = c;
        claims.cap = cap;
    }
    if (2 * (claims.n + 1) > claims.slots) {   /* at most half full */
        size_t slots = claims.slots ? 2 * claims.slots : 64;
        size_t *bf = calloc(slots, sizeof *bf), *be = calloc(slots, sizeof *be);
        if (!bf || !be) {
            free(bf);
            free(be);
            return -1;
        }
        free(claims.by_file);
        free(claims.by_entry);
        claims.by_file = bf;
        claims.by_entry = be;
        claims.slots = slots;
        for (size_t k = 0; k < claims.n; k++)
            index_claim(k);
    }
    claim *c = &claims.c[claims.n];
    c->path = alb_strprintf("%s", path);
    c->what = alb_strprintf("%s", what);
    if (!c->path || !c->what) {
        free(c->path);
        free(c->what);
        return -1;
    }
    c->id = *id;
    c->input = input;
    index_claim(claims.n++);
    return 0;
}

void cli_input(const char *path)
{
    alb_file_id id;
    if (!path || alb_file_identify(path, &id))
        return;   /* the reader reports a missing file */
    if (find_claim(&id) || add_claim(&id, path, "", true))
        alb_file_id_free(&id);
}

int cli_output(const char *cmd, const char *what, const char *path)
{
    if (!strcmp(path, "-"))
        return 0;
    struct stat st;
    /* a device or FIFO is written straight through: /dev/null may take
     * every output of a run */
    if (stat(path, &st) == 0 && !S_ISREG(st.st_mode) && !S_ISDIR(st.st_mode))
        return 0;
    alb_file_id id;
    if (alb_file_identify(path, &id)) {
        fprintf(stderr, "albatros %s: %s %s: cannot create: %s\n", cmd, what, path,
                strerror(errno));
        return 1;
    }
    const claim *c = find_claim(&id);
    if (c) {
        if (c->input)
            fprintf(stderr, "albatros %s: %s %s is the input %s: refusing to overwrite it\n",
                    cmd, what, path, c->path);
        else
            fprintf(stderr, "albatros %s: %s %s and %s %s are the same file: one would "
                            "overwrite the other\n", cmd, what, path, c->what, c->path);
        alb_file_id_free(&id);
        return 2;
    }
    if (add_claim(&id, path, what, false)) {
        alb_file_id_free(&id);
        fprintf(stderr, "albatros %s: out of memory\n", cmd);
        return 1;
    }
    return 0;
}

void cli_forget_files(void)
{
    for (size_t k = 0; k < claims.n; k++) {
        alb_file_id_free(&claims.c[k].id);
        free(claims.c[k].path);
        free(claims.c[k].what);
    }
    free(claims.c);
    free(claims.by_file);
    free(claims.by_entry);
    memset(&claims, 0, sizeof claims);
}

/* The name's extension, compared without case. */
static bool has_ext(const char *path, const char *ext)
{
    const char *slash = strrchr(path, '/'), *dot = strrchr(path, '.');
    if (!dot || (slash && dot < slash))
        return false;
    for (const char *e = ext; *e || *dot; e++, dot++)
        if (tolower((unsigned char)*dot) != *e)
            return false;
    return true;
}

int cli_check_format(const char *cmd, const char *what, const char *path, const char *format)
{
    static const struct {
        const char *format, *ext, *option;
    } known[] = {{"exr", ".exr", "-o"}, {"png", ".png", "--png or --view"}};
    for (size_t i = 0; i < sizeof known / sizeof known[0]; i++)
        if (strcmp(known[i].format, format) && has_ext(path, known[i].ext)) {
            fprintf(stderr, "albatros %s: %s %s: %s writes %s, but the name ends in %s (%s "
                            "writes that)\n", cmd, what, path, what,
                    !strcmp(format, "exr") ? "OpenEXR" : "PNG", known[i].ext, known[i].option);
            return -1;
        }
    return 0;
}

/* ---- frame outputs ---- */

#ifndef ALB_NO_EXTERNAL   /* the musl build writes no frames (Makefile: crosscheck) */

int cli_frames_option(cli_frames *o, const char *cmd, const char *name, const char *value)
{
    if (!strcmp(name, "output")) {
        if (cli_check_format(cmd, "-o", value, "exr"))
            return -1;
        o->exr = value;
        return 1;
    }
    if (!strcmp(name, "png")) {
        if (cli_check_format(cmd, "--png", value, "png"))
            return -1;
        o->png = value;
        return 1;
    }
    if (!strcmp(name, "dump")) {
        o->dump = value;
        return 1;
    }
    if (strcmp(name, "view"))
        return 0;
    const char *colon = strchr(value, ':');
    char vname[32];
    if (!colon || (size_t)(colon - value) >= sizeof vname) {
        fprintf(stderr, "albatros %s: --view %s: expected NAME:FILE.png, e.g. depth:d.png\n", cmd,
                value);
        return -1;
    }
    snprintf(vname, sizeof vname, "%.*s", (int)(colon - value), value);
    if (o->nviews == CLI_MAX_VIEWS || alb_preview_view_parse(vname, &o->views[o->nviews].view)) {
        fprintf(stderr, "albatros %s: --view %s: views are colour, depth, face, level, cycles, "
                        "coverage (at most %d)\n", cmd, value, CLI_MAX_VIEWS);
        return -1;
    }
    snprintf(o->views[o->nviews].what, sizeof o->views[o->nviews].what, "--view %s", vname);
    if (cli_check_format(cmd, o->views[o->nviews].what, colon + 1, "png"))
        return -1;
    o->views[o->nviews++].path = colon + 1;
    return 1;
}

bool cli_frames_any(const cli_frames *o) { return o->exr || o->png || o->dump || o->nviews; }

static int cmp_u32(const void *a, const void *b)
{
    uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return (x > y) - (x < y);
}

/* A frame number two frames of the run share: 0 if none, else 1 with *k. */
static int repeated_number(const uint32_t *numbers, unsigned n, uint32_t *k)
{
    uint32_t *s = malloc((n ? n : 1) * sizeof *s);
    if (!s)
        return -1;
    memcpy(s, numbers, n * sizeof *s);
    qsort(s, n, sizeof *s, cmp_u32);
    int rc = 0;
    for (unsigned i = 1; i < n && !rc; i++)
        if (s[i] == s[i - 1]) {
            *k = s[i];
            rc = 1;
        }
    free(s);
    return rc;
}

static int claim_one(const char *cmd, const char *what, const char *path, uint32_t number,
                     unsigned nframes)
{
    char *p = cli_frame_path(path, number, nframes);
    if (!p) {
        fprintf(stderr, "albatros %s: out of memory\n", cmd);
        return 1;
    }
    int rc = cli_output(cmd, what, p);
    free(p);
    return rc;
}

int cli_frames_claim(const cli_frames *o, const char *cmd, const uint32_t *numbers, unsigned n)
{
    if (!cli_frames_any(o))
        return 0;
    uint32_t k;
    int rep = n > 1 ? repeated_number(numbers, n, &k) : 0;
    if (rep < 0) {
        fprintf(stderr, "albatros %s: out of memory\n", cmd);
        return 1;
    }
    if (rep) {
        const char *path = o->exr ? o->exr : o->png ? o->png : o->dump ? o->dump : o->views[0].path;
        char *p = cli_frame_path(path, k, n);
        fprintf(stderr, "albatros %s: two frames of the stream have number %u: both would be "
                        "written to %s; outputs are numbered by frame number (docs/files.md)\n",
                cmd, (unsigned)k, p ? p : path);
        free(p);
        return 2;
    }
    int rc = 0;
    for (unsigned i = 0; i < n && !rc; i++) {
        if (o->exr)
            rc = claim_one(cmd, "-o", o->exr, numbers[i], n);
        if (!rc && o->png)
            rc = claim_one(cmd, "--png", o->png, numbers[i], n);
        if (!rc && o->dump)
            rc = claim_one(cmd, "--dump", o->dump, numbers[i], n);
        for (unsigned v = 0; v < o->nviews && !rc; v++)
            rc = claim_one(cmd, o->views[v].what, o->views[v].path, numbers[i], n);
    }
    return rc;
}

enum { WRITE_EXR = -1, WRITE_DUMP = -2 };

/* One output of a frame: the EXR, the dump or a PNG view (view >= 0). */
static alb_err write_frame_file(const cli_frames *o, const char *path, int view, const alb_frame *f,
                                unsigned nframes, alb_diag *d)
{
    char *p = cli_frame_path(path, f->number, nframes);
    if (!p)
        return alb_diag_at(d, ALB_ERR_NOMEM, path, 0, 0, "out of memory");
    alb_err e;
    if (view == WRITE_EXR) {
        e = alb_exr_write(p, f, &o->exr_opt, d);
    } else if (view == WRITE_DUMP) {
        /* raw by its name, else $writememh text (docs/cosim.md) */
        size_t n = strlen(path);
        bool raw = n > 4 && (!strcmp(path + n - 4, ".raw") || !strcmp(path + n - 4, ".bin"));
        e = alb_dump_write(p, f, raw ? ALB_DUMP_RAW : ALB_DUMP_MEMH, d);
    } else {
        e = alb_preview_write(p, f, (alb_preview_view)view, d);
    }
    free(p);
    return e;
}

int cli_frames_write(const cli_frames *o, const alb_frame *f, unsigned nframes)
{
    alb_diag d;
    alb_diag_init(&d, NULL);
    alb_err e = ALB_OK;
    if (o->exr)
        e = write_frame_file(o, o->exr, WRITE_EXR, f, nframes, &d);
    if (!e && o->dump)
        e = write_frame_file(o, o->dump, WRITE_DUMP, f, nframes, &d);
    if (!e && o->png)
        e = write_frame_file(o, o->png, ALB_PREVIEW_COLOUR, f, nframes, &d);
    for (unsigned i = 0; i < o->nviews && !e; i++)
        e = write_frame_file(o, o->views[i].path, (int)o->views[i].view, f, nframes, &d);
    if (e) {
        alb_diag_print(&d, stderr);
        return -1;
    }
    return 0;
}
#endif

void cli_warn_saturated(const char *scene, const alb_gp_stats *st)
{
    if (!st->coef_saturated)
        return;
    const char *form = st->saturated_form ? st->saturated_form : "depth";
    /* each form has its own likely cause */
    const char *why = !strcmp(form, "depth") ? "the face is nearly edge-on to the observer"
                    : !strcmp(form, "intensity") ? "its intensities are too large"
                                                 : "its texture coordinates are too large";
    fprintf(stderr, "%s:%u: warning: frame %u: the face's %s form exceeds the exponent range of "
                    "the coefficient format and was clamped (%s?); %u face%s in all "
                    "(docs/word-format.md)\n", scene, st->saturated_line, st->saturated_frame,
            form, why, st->coef_saturated, st->coef_saturated == 1 ? "" : "s");
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
