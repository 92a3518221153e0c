/* main.c — the albatros driver: `albatros SUBCOMMAND [options]`. */
#include "cli.h"
#include "commands.h"
#include "albatros/file.h"

#include <errno.h>
#include <signal.h>
#include <string.h>

typedef struct {
    const char *name;
    int (*run)(int argc, char **argv);
    const char *summary;
    int write_failed;   /* the exit status when stdout could not be written:
                           1, or compare's 2 ("trouble": 1 means "differ") */
} command;

/* ALB_NO_EXTERNAL (make crosscheck's musl build): only what needs none of
 * libpng, libusb, hidapi and OpenEXR */
static const command commands[] = {
    {"gp", cmd_gp, "run the geometry processor: scene -> VP word stream", 1},
#ifndef ALB_NO_EXTERNAL
    {"render", cmd_render, "render a scene: GP -> FIFO -> VP -> frames (EXR, PNG)", 1},
    {"vp", cmd_vp, "run the VP alone on a word stream (RTL replay)", 1},
    {"reference", cmd_reference, "render a scene with the exact double-precision reference", 1},
    {"method", cmd_method, "render a scene by one classic hidden-surface method (z-buffer, ...)", 1},
    {"compare", cmd_compare, "compare two frames: face mismatches, colour error, diff image", 2},
    {"accuracy", cmd_accuracy, "measure the VP against the exact reference on scenes", 1},
    {"stability", cmd_stability, "methods and configurations on the stress families; speed vs accuracy", 1},
    {"scene", cmd_scene, "write a generated scene (random polygons, slivers, stress families)", 1},
    {"stream", cmd_stream, "stream to a board (USB or simulated) and check it against the emulator", 1},
    {"board", cmd_board, "list, inspect or reset boards over HID", 1},
#endif
    {"dump", cmd_dump, "check a word stream and print it with field names", 1},
    {"vectors", cmd_vectors, "check (or bless) the golden vectors", 1},
    {"profiles", cmd_profiles, "list the family's profiles and their fields", 1},
};

static void usage(FILE *f)
{
    fprintf(f, "usage: albatros SUBCOMMAND [options]   (albatros SUBCOMMAND --help)\n\n"
               "An emulator of the Albatros half-plane video processor.\n\nSubcommands:\n");
    for (size_t i = 0; i < sizeof commands / sizeof commands[0]; i++)
        fprintf(f, "  %-10s %s\n", commands[i].name, commands[i].summary);
    fprintf(f, "\n  --version  print the version\n  --help     this text\n");
}

/* Ctrl-C, a kill or a hang-up: no temporary output file is left behind
 * (the old files are untouched: file.h), then the signal's own end. */
static void on_signal(int sig)
{
    alb_out_remove_temps();
    signal(sig, SIG_DFL);
    raise(sig);
}

static void catch_signals(void)
{
    static const int sigs[] = {SIGINT, SIGTERM, SIGHUP};
    for (size_t i = 0; i < sizeof sigs / sizeof sigs[0]; i++) {
        struct sigaction sa, old;
        memset(&sa, 0, sizeof sa);
        sa.sa_handler = on_signal;
        sigemptyset(&sa.sa_mask);
        /* a signal ignored by whoever started us (nohup) stays ignored */
        if (sigaction(sigs[i], NULL, &old) == 0 && old.sa_handler != SIG_IGN)
            sigaction(sigs[i], &sa, NULL);
    }
    /* over a file-size limit (ulimit -f) a write fails with EFBIG, which
     * the writers report and undo, instead of killing the process */
    signal(SIGXFSZ, SIG_IGN);
}

/* Whatever a subcommand printed must have reached stdout: a full disk, a
 * closed pipe (with SIGPIPE ignored) or a device error is an error, not
 * exit status 0. */
static int close_stdout(bool quiet)
{
    errno = 0;
    bool bad = fflush(stdout) != 0 || ferror(stdout);
    int err = errno;
    if (fclose(stdout) != 0 && !bad) {
        bad = true;
        err = errno;
    }
    if (bad && !quiet)
        fprintf(stderr, "albatros: stdout: write error: %s\n", err ? strerror(err) : "I/O error");
    return bad ? -1 : 0;
}

int main(int argc, char **argv)
{
    if (argc > 0 && argv[0])
        cli_argv0 = argv[0];
    if (argc < 2) {
        usage(stderr);
        return 2;
    }
    if (strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0 || strcmp(argv[1], "help") == 0) {
        usage(stdout);
        return close_stdout(false) ? 1 : 0;
    }
    if (strcmp(argv[1], "--version") == 0 || strcmp(argv[1], "version") == 0) {
        printf("albatros %s\n", ALBATROS_VERSION);
        return close_stdout(false) ? 1 : 0;
    }
    for (size_t i = 0; i < sizeof commands / sizeof commands[0]; i++)
        if (strcmp(argv[1], commands[i].name) == 0) {
            catch_signals();
            int rc = commands[i].run(argc - 2, argv + 2);
            cli_forget_files();
            /* a run that failed has said why (a write to "-" among them) */
            if (close_stdout(rc != 0) && rc == 0)
                rc = commands[i].write_failed;
            return rc;
        }
    fprintf(stderr, "albatros: unknown subcommand '%s'\n", argv[1]);
    usage(stderr);
    return 2;
}
