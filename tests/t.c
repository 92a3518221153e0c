/* t.c — the runner behind t.h.  Usage: unit [--bindir DIR] [FILTER...]. */
#include "t.h"

#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

typedef struct {
    const char *name, *file;
    t_fn fn;
} t_case;

static t_case cases[1024];
static unsigned ncases;
static unsigned checks, failures;
static const char *current;
static char tmpdir[512];
static const char *bindir = "build";

void t_register(const char *name, const char *file, t_fn fn)
{
    if (ncases < sizeof cases / sizeof cases[0])
        cases[ncases++] = (t_case){name, file, fn};
}

void t_pass(void) { checks++; }

void t_fail(const char *file, int line, const char *fmt, ...)
{
    va_list ap;
    checks++;
    failures++;
    fprintf(stderr, "%s:%d: %s: ", file, line, current);
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fputc('\n', stderr);
}

const char *t_tmpdir(void)
{
    if (!tmpdir[0]) {
        const char *base = getenv("TMPDIR");
        snprintf(tmpdir, sizeof tmpdir, "%s/albatros-test-%ld-%s", base ? base : "/tmp",
                 (long)getpid(), current);
        mkdir(tmpdir, 0700);
    }
    return tmpdir;
}

const char *t_bindir(void) { return bindir; }

static int selected(const t_case *c, int argc, char **argv, int first)
{
    if (first >= argc)
        return 1;
    for (int i = first; i < argc; i++)
        if (strstr(c->name, argv[i]) || strstr(c->file, argv[i]))
            return 1;
    return 0;
}

int main(int argc, char **argv)
{
    int first = 1;
    if (argc > 2 && strcmp(argv[1], "--bindir") == 0) {
        bindir = argv[2];
        first = 3;
    }
    unsigned passed = 0, failed = 0;
    for (unsigned i = 0; i < ncases; i++) {
        if (!selected(&cases[i], argc, argv, first))
            continue;
        unsigned f0 = failures, c0 = checks;
        current = cases[i].name;
        tmpdir[0] = 0;
        cases[i].fn();
        if (checks == c0) {
            fprintf(stderr, "%s: %s: made no checks\n", cases[i].file, cases[i].name);
            failures++;
        }
        if (failures == f0)
            passed++;
        else {
            failed++;
            fprintf(stderr, "FAIL %s\n", cases[i].name);
        }
        if (tmpdir[0] && failures == f0) {
            char cmd[600];
            snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmpdir);
            if (system(cmd) != 0)
                fprintf(stderr, "warning: could not remove %s\n", tmpdir);
        }
    }
    printf("%u passed, %u failed\n", passed, failed);
    return (failed || passed == 0) ? 1 : 0;
}
