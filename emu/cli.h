/* cli.h — what the subcommands share: option parsing (with the same options
 * accepted on the command line and in a golden vector's `options` file), the
 * scene/profile set-up, and output helpers. */
#ifndef ALBATROS_CLI_H
#define ALBATROS_CLI_H

#include "albatros/profile.h"
#include "albatros/gp.h"
#include "albatros/exr.h"
#include "albatros/preview.h"

#include <stdbool.h>
#include <stdio.h>

#define ALBATROS_VERSION "0.1.0"

/* --set and --size options a run_opts remembers, so that a later --profile
 * does not undo them (docs/profiles.md: the order of options does not matter). */
#define RUN_OPTS_MAX_OVERRIDES 32

/* Options common to every subcommand that runs the GP. */
typedef struct {
    alb_profile prof;
    alb_scene_camera cam;
    bool cam_given;      /* any of --eye/--at/--up/--fov */
    double near;         /* --near: the depth scale, replacing the scene's */
    bool near_given;
    struct {
        bool is_size;     /* --size WxH, else --set KEY=VALUE */
        const char *value;
    } overrides[RUN_OPTS_MAX_OVERRIDES];
    unsigned noverrides;
} run_opts;

void run_opts_init(run_opts *o);
/* Apply one common option (name without "--"); 1 if it took the value, 0 if
 * the name is not a common option, -1 with a message on a bad value.  --set
 * and --size values are remembered (the pointer, so value must outlive o's
 * options) and applied again, in their order, after every --profile: the
 * result does not depend on where --profile stands, and a later --set of
 * the same key wins. */
int run_opts_apply(run_opts *o, const char *name, const char *value, char *err, size_t len);
/* Help text for the common options. */
extern const char run_opts_help[];

/* Parse a command line.  spec lists the subcommand's own options as
 * "name" (flag) or "name=" (takes a value); on each, cb is called.  Common
 * options go to o.  Positional arguments are collected in pos[].  Returns 0,
 * -1 after printing an error (the caller exits with status 2), or 1 after
 * printing the version for --version, which every subcommand takes (the
 * caller exits with status 0): CLI_PARSE_EXIT turns that into the status. */
#define CLI_PARSE_EXIT(rc) ((rc) < 0 ? 2 : 0)
typedef int (*opt_cb)(void *ctx, const char *name, const char *value);
int cli_parse(const char *cmd, int argc, char **argv, const char *const *spec, opt_cb cb,
              void *ctx, run_opts *o, const char **pos, int maxpos, int *npos);

/* Load the scene named by path (NULL: the built-in scene; *.obj: OBJ with
 * the camera of o), with o's --near if given.  Prints the error and returns
 * non-zero on failure. */
int cli_load_scene(const char *path, const run_opts *o, alb_scene *s);
/* Is path an OBJ file (by its extension, as cli_load_scene decides)? */
bool cli_is_obj(const char *path);
/* Validate the profile; prints the error. */
int cli_check_profile(const alb_profile *p);

/* Split a text of options ("--profile a256 --set bound=none ...") into argv;
 * returns the count, or -1 if there are more than max. */
int cli_split_words(char *text, char **argv, int max);

bool cli_isatty_stderr(void);

/* How this program was started (main's argv[0]), and how a command line
 * printed for others to run (stability --jobs) should call it: as typed if
 * it was found on PATH, else by its absolute path, so the jobs of a build
 * tree or an installed copy run the same program. */
extern const char *cli_argv0;
void cli_print_self(FILE *f);

/* An output path for one frame of nframes: "dir/f.exr" itself for a single
 * frame, "dir/f.0003.exr" (the number before the extension) for more.
 * malloc'd, any length; NULL if out of memory. */
char *cli_frame_path(const char *path, unsigned number, unsigned nframes);

/* The files of a run (docs/files.md): cli_input notes a file read (its
 * absence is the reader's to report); cli_output claims an output path,
 * refusing one that names an input or another output of the run, compared
 * by device and inode (or, for a file not written yet, by directory and
 * name), however spelled.  "-" and devices are never refused.  `what`
 * names the option ("-o", "--png", ...).  Returns the exit status after a
 * message: 0, 2 refused, 1 the path cannot be created. */
void cli_input(const char *path);
int cli_output(const char *cmd, const char *what, const char *path);
void cli_forget_files(void);
/* The frame outputs render, vp, reference and method share: -o (EXR),
 * --png, --view NAME:FILE, numbered per frame when there are several. */
#define CLI_MAX_VIEWS 8
typedef struct {
    const char *exr, *png, *dump;   /* -o, --png, --dump */
    struct {
        alb_preview_view view;
        const char *path;
        char what[48];           /* "--view level", for messages */
    } views[CLI_MAX_VIEWS];
    unsigned nviews;
    alb_exr_options exr_opt;     /* threads and provenance of the EXR */
} cli_frames;
/* -o, --png, --view: 1 if name is one of them (value taken), 0 if not, -1
 * after a message (a bad view, a PNG name for -o, ...). */
int cli_frames_option(cli_frames *o, const char *cmd, const char *name, const char *value);
bool cli_frames_any(const cli_frames *o);
/* Before any work: claim (cli_output) every file that frames numbered
 * numbers[0..n) will be written to; frame numbers that repeat with
 * numbered outputs are refused (each would overwrite the other's).  An
 * exit status as cli_output's. */
int cli_frames_claim(const cli_frames *o, const char *cmd, const uint32_t *numbers, unsigned n);
/* Write frame f's outputs (of a run of nframes); -1 after a message. */
int cli_frames_write(const cli_frames *o, const alb_frame *f, unsigned nframes);

/* The GP clamped some linear forms: name the first face (scene:line), the
 * form and its likely cause. */
void cli_warn_saturated(const char *scene, const alb_gp_stats *st);

/* An output of one format whose name ends in another's extension ("-o
 * x.png" writes OpenEXR): -1 with a message.  format: "exr" or "png". */
int cli_check_format(const char *cmd, const char *what, const char *path, const char *format);

#endif
