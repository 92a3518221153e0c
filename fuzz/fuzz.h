/* fuzz.h — what the libFuzzer harnesses share: the entry point libFuzzer
 * calls, and a per-process scratch directory for the input paths that read
 * files (OBJ, PNG, scene textures).  The harnesses print nothing and leak
 * nothing; fuzz/replay.c runs them without libFuzzer (docs: fuzz/README). */
#ifndef ALBATROS_FUZZ_H
#define ALBATROS_FUZZ_H

#include "albatros/profile.h"
#include "albatros/words.h"
#include "albatros/gp.h"

#include <stddef.h>
#include <stdint.h>

/* libFuzzer's entry point: one per harness; 0 always. */
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* The scratch directory, made on first use (mkdtemp under $TMPDIR or /tmp)
 * and removed with everything in it at exit; NULL if it cannot be made. */
const char *fuzz_tmpdir(void);

/* Write bytes to NAME in the scratch directory, replacing it; the full path
 * goes to path.  0, or -1 on failure. */
int fuzz_write(const char *name, const void *data, size_t size, char *path, size_t len);

/* A valid RGB PNG of w x h pixels (a colour ramp) as NAME in the scratch
 * directory.  0, or -1 on failure. */
int fuzz_write_png(const char *name, unsigned w, unsigned h);

/* Frames x faces the GP runs on for one input: its cost is linear in both,
 * and a few thousand `frame` lines must not make one input slow. */
#define FUZZ_GP_WORK_MAX 20000u

/* Run the GP on s with prof (if s is within FUZZ_GP_WORK_MAX) and check that
 * its stream decodes; abort()s, naming the word, if it does not.  0 with the
 * stream in *out (if out is not NULL; the caller frees it), -1 if the GP did
 * not run or failed. */
int fuzz_run_gp(const alb_scene *s, const alb_profile *prof, alb_ws_buf *out);

#endif
