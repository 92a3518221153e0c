/* cmd_stability.c — `albatros stability`: the classic methods and the
 * Albatros configurations over the stress families, and speed against
 * accuracy; as independent jobs (one per family, one for speed) for make -j,
 * GNU parallel or a Slurm array, and a report step (docs/stability.md).
 * `albatros method`: one classic method on one scene, to frames that
 * `albatros compare` reads (docs/methods.md). */
#include "cli.h"
#include "albatros/file.h"
#include "commands.h"
#include "albatros/exr.h"
#include "albatros/preview.h"
#include "../tools/methods.h"
#include "../tools/sweep.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

/* Options that change a job's result, kept in their order so that --jobs
 * prints them on every job line (the same profile in every job). */
#define STAB_MAX_PASS 32

typedef struct {
    const char *families[16];
    unsigned nfam;
    bool speed, report, jobs, help, quiet, profile_given;
    const char *out;
    unsigned seeds;
    run_opts *o;
    const char *pass_name[STAB_MAX_PASS], *pass_value[STAB_MAX_PASS];
    unsigned npass;
} stab_args;

/* --profile, --set, --size: applied as every subcommand applies them, and
 * remembered for the job lines. */
static int stab_profile_opt(stab_args *a, const char *name, const char *value)
{
    char err[400];
    if (run_opts_apply(a->o, name, value, err, sizeof err) < 0) {
        fprintf(stderr, "albatros stability: %s\n", err);
        return -1;
    }
    if (a->npass == STAB_MAX_PASS) {
        fprintf(stderr, "albatros stability: at most %d --profile, --set and --size options\n",
                STAB_MAX_PASS);
        return -1;
    }
    /* name is the parser's buffer: keep a string of our own */
    static const char *const kept[] = {"profile", "set", "size"};
    unsigned k = 0;
    while (k < 2 && strcmp(kept[k], name))
        k++;
    a->profile_given |= k == 0;
    a->pass_name[a->npass] = kept[k];
    a->pass_value[a->npass++] = value;
    return 0;
}

static int stab_opt(void *ctx, const char *name, const char *value)
{
    stab_args *a = ctx;
    if (!strcmp(name, "family")) {
        unsigned i = 0;
        while (sweep_family(i) && strcmp(sweep_family(i), value))
            i++;
        if (!sweep_family(i) || a->nfam == 16) {
            fprintf(stderr, "albatros stability: --family %s: unknown (known:", value);
            for (i = 0; sweep_family(i); i++)
                fprintf(stderr, " %s", sweep_family(i));
            fprintf(stderr, ")\n");
            return -1;
        }
        a->families[a->nfam++] = value;
    } else if (!strcmp(name, "seeds")) {
        char *end;
        unsigned long v = strtoul(value, &end, 10);
        if (end == value || *end || v < 1 || v > 100) {
            fprintf(stderr, "albatros stability: --seeds %s: expected 1..100\n", value);
            return -1;
        }
        a->seeds = (unsigned)v;
    } else if (!strcmp(name, "profile") || !strcmp(name, "set") || !strcmp(name, "size")) {
        return stab_profile_opt(a, name, value);
    } else if (!strcmp(name, "eye") || !strcmp(name, "at") || !strcmp(name, "up") ||
               !strcmp(name, "fov")) {
        /* common options elsewhere, but nothing here would read them */
        fprintf(stderr, "albatros stability: --%s: the stress scenes set their own observer "
                        "(camera options are for OBJ scenes)\n", name);
        return -1;
    } else if (!strcmp(name, "out")) {
        a->out = value;
    } else if (!strcmp(name, "speed")) {
        a->speed = true;
    } else if (!strcmp(name, "report")) {
        a->report = true;
    } else if (!strcmp(name, "jobs")) {
        a->jobs = true;
    } else if (!strcmp(name, "quiet") || !strcmp(name, "q")) {
        a->quiet = true;
    } else if (!strcmp(name, "help")) {
        a->help = true;
    }
    return 0;
}

/* One word of a job line: bare if the shell would read it unchanged, else
 * in single quotes. */
static void print_word(const char *w)
{
    if (*w && strspn(w, "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789"
                        "_-+=.,:/@%") == strlen(w)) {
        fputs(w, stdout);
        return;
    }
    putchar('\'');
    for (; *w; w++)
        if (*w == '\'')
            fputs("'\\''", stdout);
        else
            putchar(*w);
    putchar('\'');
}

/* "albatros stability" and every option that changes a result: the profile
 * (a256 unless given), the --set and --size options in their order, and -q. */
static void print_job_head(const stab_args *a)
{
    cli_print_self(stdout);
    fputs(" stability", stdout);
    if (!a->profile_given)
        fputs(" --profile a256", stdout);
    for (unsigned i = 0; i < a->npass; i++) {
        printf(" --%s ", a->pass_name[i]);
        print_word(a->pass_value[i]);
    }
    if (a->quiet)
        fputs(" -q", stdout);
}

/* The jobs chosen by --family and --speed; every job if neither is given. */
static void print_jobs(const stab_args *a)
{
    bool all = !a->nfam && !a->speed;
    for (unsigned i = 0; all ? sweep_family(i) != NULL : i < a->nfam; i++) {
        print_job_head(a);
        printf(" --seeds %u --out ", a->seeds);
        print_word(a->out);
        printf(" --family %s\n", all ? sweep_family(i) : a->families[i]);
    }
    if (!all && !a->speed)
        return;
    print_job_head(a);
    fputs(" --out ", stdout);
    print_word(a->out);
    fputs(" --speed\n", stdout);
}

/* A CSV of the sweep, DIR/NAME.csv: under its name only once complete
 * (file.h), so a failed or interrupted job leaves the last good one. */
static FILE *open_csv(const char *dir, const char *name, alb_out *out, char **path)
{
    alb_diag d;
    alb_diag_init(&d, NULL);
    FILE *f = NULL;
    if (!(*path = alb_strprintf("%s/%s.csv", dir, name)))
        fprintf(stderr, "albatros stability: out of memory\n");
    else if (alb_out_open(out, *path, 0, &d) || !(f = alb_out_stdio(out, &d)))
        alb_diag_print(&d, stderr);
    return f;
}

static int close_csv(alb_out *out, char *path, int rc)
{
    alb_diag d;
    alb_diag_init(&d, NULL);
    if (rc) {
        alb_out_abort(out);
        fprintf(stderr, "albatros stability: %s failed\n", path);
    } else if (alb_out_commit(out, &d)) {
        alb_diag_print(&d, stderr);
        rc = 1;
    }
    free(path);
    return rc ? 1 : 0;
}

static int run_families(stab_args *a, const sweep_progress *progress)
{
    for (unsigned i = 0; i < a->nfam; i++) {
        char name[64], *path;
        alb_out out;
        snprintf(name, sizeof name, "stability-%s", a->families[i]);
        FILE *f = open_csv(a->out, name, &out, &path);
        if (!f) {
            free(path);
            return 1;
        }
        int rc = sweep_family_run(a->families[i], &a->o->prof, a->seeds, f, progress);
        if (close_csv(&out, path, rc))
            return 1;
    }
    return 0;
}

int cmd_stability(int argc, char **argv)
{
    static const char *const spec[] = {"family=", "speed", "report", "jobs", "out=", "seeds=",
                                       "profile=", "set=", "size=", "quiet", "q", "help",
                                       "eye=", "at=", "up=", "fov=", NULL};
    run_opts o;
    run_opts_init(&o);
    alb_profile_lookup("a256", &o.prof);
    stab_args a = {.out = "stability-out", .seeds = 2, .o = &o};
    const char *pos[1];
    int npos;
    int parsed = cli_parse("stability", argc, argv, spec, stab_opt, &a, &o, pos, 0, &npos);
    if (parsed)
        return CLI_PARSE_EXIT(parsed);
    if (a.help) {
        printf("usage: albatros stability [--family F]... [--speed] [--report] [--out DIR]\n"
               "                          [--seeds N] [--jobs] [-q] [--profile P]\n"
               "                          [--set K=V]... [--size WxH]\n\n"
               "Every classic method and Albatros configuration on the stress families,\n"
               "against the exact reference (docs/stability.md).  Without --family,\n"
               "--speed or --report: every job, then the report.  Jobs write\n"
               "DIR/stability-FAMILY.csv and DIR/speed.csv; --report writes\n"
               "DIR/stability.{csv,md,png}, and DIR/speed.{md,png} if DIR has a speed.csv\n"
               "(gnuplot).  --jobs prints one command per job, with every option that\n"
               "changes a result, for make -j, GNU parallel or a Slurm array: every job, or\n"
               "with --family or --speed only those families' jobs and the speed job.\n"
               "Progress goes to stderr: one line redrawn on a terminal, one line per\n"
               "severity in a log; -q: none.  Profile a256 unless --profile says otherwise.\n");
        return 0;
    }
    if (cli_check_profile(&o.prof))
        return 2;
    bool everything = !a.nfam && !a.speed && !a.report;
    if (a.jobs) {
        print_jobs(&a);
        return 0;
    }
    if (mkdir(a.out, 0777) && errno != EEXIST) {
        fprintf(stderr, "albatros stability: cannot create %s: %s\n", a.out, strerror(errno));
        return 1;
    }
    sweep_progress progress = {a.quiet ? NULL : stderr, cli_isatty_stderr()};
    if (everything)
        for (a.nfam = 0; sweep_family(a.nfam) && a.nfam < 16; a.nfam++)
            a.families[a.nfam] = sweep_family(a.nfam);
    if (run_families(&a, &progress))
        return 1;
    if (a.speed || everything) {
        char *path;
        alb_out out;
        FILE *f = open_csv(a.out, "speed", &out, &path);
        if (!f) {
            free(path);
            return 1;
        }
        if (close_csv(&out, path, sweep_speed_run(&o.prof, f, &progress)))
            return 1;
    }
    if (a.report || everything) {
        bool with_speed;
        if (sweep_report(a.out, &with_speed))
            return 1;
        if (!a.quiet)
            printf("wrote %s/stability.csv, %s/stability.md, %s/stability.png", a.out, a.out,
                   a.out);
        if (!a.quiet && with_speed)
            printf(", %s/speed.md, %s/speed.png", a.out, a.out);
        if (!a.quiet)
            putchar('\n');
    }
    return 0;
}

/* ---- albatros method ---- */

typedef struct {
    cli_frames out;
    bool help, list, quiet;
} method_args;

static int method_opt(void *ctx, const char *name, const char *value)
{
    method_args *a = ctx;
    int took = cli_frames_option(&a->out, "method", name, value);
    if (took)
        return took < 0 ? -1 : 0;
    if (!strcmp(name, "list")) {
        a->list = true;
    } else if (!strcmp(name, "quiet") || !strcmp(name, "q")) {
        a->quiet = true;
    } else if (!strcmp(name, "help")) {
        a->help = true;
    }
    return 0;
}

static void method_usage(FILE *f)
{
    unsigned n;
    const method *all = methods_all(&n);
    fprintf(f, "usage: albatros method NAME [SCENE] [-o FRAME.exr] [--png FRAME.png]\n"
               "                       [--view NAME:FILE.png] [-q] [options]\n"
               "       albatros method --list\n\n"
               "Render SCENE (the built-in scene if omitted) by one classic hidden-surface\n"
               "method (docs/methods.md), into the VP's frame format: the EXR has the same\n"
               "channels as render's, for albatros compare against albatros render or\n"
               "albatros reference.  Pixel centres, no anti-aliasing (aa=0 profiles only).\n"
               "With several frames, outputs are numbered as render numbers them.\n\n"
               "Methods:\n");
    for (unsigned i = 0; i < n; i++)
        fprintf(f, "  %-17s %s\n", all[i].name, all[i].summary);
    fputc('\n', f);
}

int cmd_method(int argc, char **argv)
{
    static const char *const spec[] = {"output=", "png=", "view=", "list", "quiet", "q", "help",
                                       NULL};
    method_args a = {0};
    run_opts o;
    run_opts_init(&o);
    const char *pos[2];
    int npos;
    int parsed = cli_parse("method", argc, argv, spec, method_opt, &a, &o, pos, 2, &npos);
    if (parsed)
        return CLI_PARSE_EXIT(parsed);
    if (a.help || a.list) {
        method_usage(stdout);
        if (a.help)
            printf("%s", run_opts_help);
        return 0;
    }
    const method *m = npos ? method_find(pos[0]) : NULL;
    if (!m) {
        if (npos)
            fprintf(stderr, "albatros method: unknown method '%s'\n\n", pos[0]);
        method_usage(stderr);
        return 2;
    }
    if (!cli_frames_any(&a.out)) {
        fprintf(stderr, "albatros method: nothing to write: give -o FRAME.exr, --png FILE or "
                        "--view NAME:FILE\n");
        return 2;
    }
    if (cli_check_profile(&o.prof))
        return 2;
    if (o.prof.aa_levels) {
        fprintf(stderr, "albatros method: the classic methods sample pixel centres only: use a "
                        "profile with aa=0 (--set aa=0)\n");
        return 2;
    }
    alb_scene scene;
    if (cli_load_scene(npos == 2 ? pos[1] : NULL, &o, &scene))
        return 1;
    char software[32];
    snprintf(software, sizeof software, "albatros %s", ALBATROS_VERSION);
    const char *src = npos == 2 ? pos[1] : "builtin", *slash = strrchr(src, '/');
    a.out.exr_opt = (alb_exr_options){1, software, o.prof.name, m->name, slash ? slash + 1 : src};
    uint32_t *numbers = malloc((scene.nframes ? scene.nframes : 1) * sizeof *numbers);
    int rc = numbers ? 0 : 1;
    for (unsigned f = 0; numbers && f < scene.nframes; f++)
        numbers[f] = f;
    if (numbers)
        rc = cli_frames_claim(&a.out, "method", numbers, scene.nframes);
    free(numbers);
    for (unsigned f = 0; f < scene.nframes && !rc; f++) {
        alb_frame fr;
        if (m->render(&scene, &o.prof, f, &fr)) {
            fprintf(stderr, "albatros method: %s: out of memory\n", m->name);
            rc = 1;
            break;
        }
        rc = cli_frames_write(&a.out, &fr, scene.nframes) ? 1 : 0;
        if (!rc && !a.quiet)
            fprintf(stderr, "%s frame %u\n", m->name, f);
        alb_frame_free(&fr);
    }
    alb_scene_free(&scene);
    return rc;
}
