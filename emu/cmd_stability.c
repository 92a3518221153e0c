/* cmd_stability.c — `albatros stability`: the classic methods and the
 * Albatros configurations over the stress families, and speed against
 * accuracy; as independent jobs (one per family, one for speed) for make -j,
 * GNU parallel or a Slurm array, and a report step (docs/stability.md). */
#include "cli.h"
#include "commands.h"
#include "../tools/sweep.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

typedef struct {
    const char *families[16];
    unsigned nfam;
    bool speed, report, jobs, help, all;
    const char *out;
    unsigned seeds;
} stab_args;

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
    } else if (!strcmp(name, "out")) {
        a->out = value;
    } else if (!strcmp(name, "speed")) {
        a->speed = true;
    } else if (!strcmp(name, "report")) {
        a->report = true;
    } else if (!strcmp(name, "jobs")) {
        a->jobs = true;
    } else if (!strcmp(name, "help")) {
        a->help = true;
    }
    return 0;
}

static FILE *open_csv(const char *dir, const char *name, char *path, size_t len)
{
    snprintf(path, len, "%s/%s.csv", dir, name);
    FILE *f = fopen(path, "w");
    if (!f)
        fprintf(stderr, "albatros stability: cannot write %s: %s\n", path, strerror(errno));
    return f;
}

int cmd_stability(int argc, char **argv)
{
    static const char *const spec[] = {"family=", "speed", "report", "jobs", "out=", "seeds=",
                                       "help", NULL};
    stab_args a = {.out = "stability-out", .seeds = 2};
    run_opts o;
    run_opts_init(&o);
    profile_lookup("a256", &o.prof);
    const char *pos[1];
    int npos;
    if (cli_parse("stability", argc, argv, spec, stab_opt, &a, &o, pos, 0, &npos))
        return 2;
    if (a.help) {
        printf("usage: albatros stability [--family F]... [--speed] [--report] [--out DIR]\n"
               "                          [--seeds N] [--jobs] [--profile P --set K=V]\n\n"
               "Every classic method and Albatros configuration on the stress families,\n"
               "against the exact reference (docs/stability.md).  Without --family,\n"
               "--speed or --report: every job, then the report.  Jobs write\n"
               "DIR/stability-FAMILY.csv and DIR/speed.csv; --report writes\n"
               "DIR/stability.{csv,md,png} and DIR/speed.{md,png} (gnuplot).\n"
               "--jobs prints one command per job, for make -j, GNU parallel or a Slurm array.\n"
               "Profile a256 unless --profile says otherwise.\n");
        return 0;
    }
    if (cli_check_profile(&o.prof))
        return 2;
    bool everything = !a.nfam && !a.speed && !a.report;
    if (a.jobs) {
        for (unsigned i = 0; sweep_family(i); i++)
            printf("albatros stability --profile %s --seeds %u --out %s --family %s\n",
                   o.prof.name, a.seeds, a.out, sweep_family(i));
        printf("albatros stability --profile %s --out %s --speed\n", o.prof.name, a.out);
        return 0;
    }
    if (mkdir(a.out, 0777) && errno != EEXIST) {
        fprintf(stderr, "albatros stability: cannot create %s: %s\n", a.out, strerror(errno));
        return 1;
    }
    FILE *progress = cli_isatty_stderr() ? stderr : NULL;
    char path[600];
    unsigned nfam = a.nfam;
    if (everything)
        for (nfam = 0; sweep_family(nfam) && nfam < 16; nfam++)
            a.families[nfam] = sweep_family(nfam);
    for (unsigned i = 0; i < nfam; i++) {
        char name[64];
        snprintf(name, sizeof name, "stability-%s", a.families[i]);
        FILE *f = open_csv(a.out, name, path, sizeof path);
        if (!f)
            return 1;
        int rc = sweep_family_run(a.families[i], &o.prof, a.seeds, f, progress);
        if (fclose(f) || rc) {
            fprintf(stderr, "albatros stability: %s failed\n", path);
            return 1;
        }
    }
    if (a.speed || everything) {
        FILE *f = open_csv(a.out, "speed", path, sizeof path);
        if (!f)
            return 1;
        int rc = sweep_speed_run(&o.prof, f, progress);
        if (fclose(f) || rc)
            return 1;
    }
    if (a.report || everything) {
        if (sweep_report(a.out))
            return 1;
        printf("wrote %s/stability.md, %s/stability.png, %s/speed.md, %s/speed.png\n", a.out,
               a.out, a.out, a.out);
    }
    return 0;
}
