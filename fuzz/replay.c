/* replay.c — run a libFuzzer harness without libFuzzer: every file named,
 * and every file in every directory named, goes to LLVMFuzzerTestOneInput in
 * a child process of its own, so that one crashing input is reported and the
 * rest still run.  A file passes if the harness returns (and the child exits
 * 0) within REPLAY_TIMEOUT seconds; the sanitizers of `make asan` turn
 * memory errors and leaks into failures.  Ends with "N passed, N failed". */
#include "fuzz.h"
#include "albatros/file.h"

#include <dirent.h>
#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#define REPLAY_TIMEOUT 60   /* seconds per input: a hang is a failure */

typedef struct {
    unsigned passed, failed;
} tally;

static int read_all(const char *path, uint8_t **data, size_t *size)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return -1;
    char *buf;
    int rc = alb_file_read_all(f, &buf, size);
    fclose(f);
    *data = (uint8_t *)buf;
    return rc ? -1 : 0;
}

/* The harness on one file, in a child: 0 if it returned. */
static int run_one(const char *path)
{
    uint8_t *data;
    size_t size;
    if (read_all(path, &data, &size)) {
        fprintf(stderr, "FAIL %s: cannot read: %s\n", path, strerror(errno));
        return -1;
    }
    fflush(NULL);
    pid_t pid = fork();
    if (pid < 0) {
        fprintf(stderr, "FAIL %s: fork: %s\n", path, strerror(errno));
        free(data);
        return -1;
    }
    if (pid == 0) {
        alarm(REPLAY_TIMEOUT);
        LLVMFuzzerTestOneInput(data, size);
        free(data);
        exit(0);
    }
    free(data);
    int status;
    while (waitpid(pid, &status, 0) < 0)
        if (errno != EINTR) {
            fprintf(stderr, "FAIL %s: waitpid: %s\n", path, strerror(errno));
            return -1;
        }
    if (WIFEXITED(status) && WEXITSTATUS(status) == 0)
        return 0;
    if (WIFSIGNALED(status))
        fprintf(stderr, "FAIL %s: %s\n", path, WTERMSIG(status) == SIGALRM
                ? "timed out" : strsignal(WTERMSIG(status)));
    else
        fprintf(stderr, "FAIL %s: exit status %d\n", path, WEXITSTATUS(status));
    return -1;
}

static int by_name(const void *a, const void *b)
{
    return strcmp(*(char *const *)a, *(char *const *)b);
}

static void run_path(const char *path, tally *t);

/* A directory's entries in name order (reproducible reports), recursively. */
static void run_dir(const char *dir, tally *t)
{
    DIR *d = opendir(dir);
    if (!d) {
        fprintf(stderr, "FAIL %s: cannot open directory: %s\n", dir, strerror(errno));
        t->failed++;
        return;
    }
    char **names = NULL;
    size_t n = 0, cap = 0;
    struct dirent *e;
    while ((e = readdir(d))) {
        if (e->d_name[0] == '.')   /* ., .. and hidden files */
            continue;
        if (n == cap) {
            char **nn = realloc(names, (cap = cap ? 2 * cap : 64) * sizeof *nn);
            if (!nn)
                break;
            names = nn;
        }
        size_t len = strlen(dir) + strlen(e->d_name) + 2;
        if (!(names[n] = malloc(len)))
            break;
        snprintf(names[n++], len, "%s/%s", dir, e->d_name);
    }
    closedir(d);
    if (n)
        qsort(names, n, sizeof *names, by_name);
    for (size_t i = 0; i < n; i++) {
        run_path(names[i], t);
        free(names[i]);
    }
    free(names);
}

static void run_path(const char *path, tally *t)
{
    struct stat st;
    if (stat(path, &st)) {
        fprintf(stderr, "FAIL %s: %s\n", path, strerror(errno));
        t->failed++;
    } else if (S_ISDIR(st.st_mode)) {
        run_dir(path, t);
    } else if (run_one(path) == 0) {
        t->passed++;
    } else {
        t->failed++;
    }
}

int main(int argc, char **argv)
{
    tally t = {0, 0};
    if (argc < 2) {
        fprintf(stderr, "usage: %s FILE|DIR...\n", argv[0]);
        return 2;
    }
    if (!fuzz_tmpdir()) {   /* made once here, shared by the children */
        fprintf(stderr, "%s: cannot make a scratch directory: %s\n", argv[0], strerror(errno));
        return 1;
    }
    for (int i = 1; i < argc; i++)
        run_path(argv[i], &t);
    printf("%u passed, %u failed\n", t.passed, t.failed);
    return t.failed ? 1 : 0;
}
