/* main.c — the albatros driver: `albatros SUBCOMMAND [options]`. */
#include "cli.h"
#include "commands.h"

#include <string.h>

typedef struct {
    const char *name;
    int (*run)(int argc, char **argv);
    const char *summary;
} command;

/* ALB_NO_EXTERNAL (make crosscheck's musl build): only what needs none of
 * libpng, libusb, hidapi and OpenEXR */
static const command commands[] = {
    {"gp", cmd_gp, "run the geometry processor: scene -> VP word stream"},
#ifndef ALB_NO_EXTERNAL
    {"render", cmd_render, "render a scene: GP -> FIFO -> VP -> frames (EXR, PNG)"},
    {"vp", cmd_vp, "run the VP alone on a word stream (RTL replay)"},
    {"reference", cmd_reference, "render a scene with the exact double-precision reference"},
    {"method", cmd_method, "render a scene by one classic hidden-surface method (z-buffer, ...)"},
    {"compare", cmd_compare, "compare two frames: face mismatches, colour error, diff image"},
    {"accuracy", cmd_accuracy, "measure the VP against the exact reference on scenes"},
    {"stability", cmd_stability, "methods and configurations on the stress families; speed vs accuracy"},
    {"scene", cmd_scene, "write a generated scene (random polygons, slivers, stress families)"},
    {"stream", cmd_stream, "stream to a board (USB or simulated) and check it against the emulator"},
    {"board", cmd_board, "list, inspect or reset boards over HID"},
#endif
    {"dump", cmd_dump, "check a word stream and print it with field names"},
    {"vectors", cmd_vectors, "check (or bless) the golden vectors"},
    {"profiles", cmd_profiles, "list the family's profiles and their fields"},
};

static void usage(FILE *f)
{
    fprintf(f, "usage: albatros SUBCOMMAND [options]   (albatros SUBCOMMAND --help)\n\n"
               "An emulator of the Albatros half-plane video processor.\n\nSubcommands:\n");
    for (size_t i = 0; i < sizeof commands / sizeof commands[0]; i++)
        fprintf(f, "  %-10s %s\n", commands[i].name, commands[i].summary);
    fprintf(f, "\n  --version  print the version\n  --help     this text\n");
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
        return 0;
    }
    if (strcmp(argv[1], "--version") == 0 || strcmp(argv[1], "version") == 0) {
        printf("albatros %s\n", ALBATROS_VERSION);
        return 0;
    }
    for (size_t i = 0; i < sizeof commands / sizeof commands[0]; i++)
        if (strcmp(argv[1], commands[i].name) == 0)
            return commands[i].run(argc - 2, argv + 2);
    fprintf(stderr, "albatros: unknown subcommand '%s'\n", argv[1]);
    usage(stderr);
    return 2;
}
