/* gp_helpers.h — run the GP on scene text inside a test and decode frame 0. */
#ifndef ALBATROS_TEST_GP_HELPERS_H
#define ALBATROS_TEST_GP_HELPERS_H

#include "albatros/gp.h"

typedef struct {
    alb_ws_buf buf;
    alb_gp_stats st;
    alb_ws_config cfg;
    alb_ws_frame frame;
    alb_ws_face *faces;   /* of frame 0 */
    unsigned nfaces;
    char err[600];    /* diagnostic if the run failed */
} gp_run_result;

/* Parse text, run the GP with profile `prof` (NULL: a512 with the
 * assignments in `sets`, space-separated key=value), decode frame 0.
 * Returns 0 on success. */
int gp_run_text(const char *text, const char *sets, gp_run_result *r);
void gp_run_free(gp_run_result *r);

#include "albatros/vp.h"
#include "../tools/scenegen.h"

/* Parse scene text (screen-space scenes resolved for the profile), run GP and
 * VP with profile "a512" or `profile_name`, plus the `sets`; frame 0 goes to
 * *out (free with alb_frame_free) and the VP statistics to *st (may be NULL).
 * Also returns the profile used in *prof_out if not NULL.  0 on success;
 * otherwise err holds the reason. */
int render_text(const char *text, const char *profile_name, const char *sets, alb_frame *out,
                alb_vp_stats *st, alb_profile *prof_out, char *err, size_t errlen);

/* The built-in scene's text as a NUL-terminated malloc'd copy (NULL if out of
 * memory), for tests that edit or render it. */
char *builtin_scene_copy(void);

/* Apply "key=value key=value ..." to a profile (the test's own, valid). */
void profile_set_all(alb_profile *p, const char *sets);
/* The small profile of the randomised tests: t32 at 64 x 64 samples,
 * edge_frac_bits 11, then `sets`. */
void small_profile(alb_profile *p, const char *sets);
/* The GP's stream of scene text with profile p into *b (initialised here);
 * 0, or -1 if the scene or the GP failed. */
int stream_of(const char *text, const alb_profile *p, alb_ws_buf *b);
/* The same for a screen-space scene, resolved for p's screen first. */
int screen_stream_of(const char *text, const alb_profile *p, alb_ws_buf *b);
/* The profile a golden vector's options file gives (--profile and --set
 * only; a512 without), from test-vectors/NAME/options. */
void vector_profile(const char *name, alb_profile *p);
/* A random scene (scenegen_random of seed with gp) with `extra` more
 * `frame` lines (each copies the last) and its stream in *b; the scene's
 * text (to free), or NULL on failure. */
char *random_frames_stream(uint64_t seed, const scenegen_params *gp, unsigned extra,
                           const alb_profile *p, alb_ws_buf *b);

/* fn on every golden vector of test-vectors/ with its profile and expected
 * stream (folders without one are skipped); how many there were. */
typedef void (*vector_fn)(const char *name, const alb_profile *p, const alb_ws_buf *stream,
                          void *ctx);
unsigned for_each_vector(vector_fn fn, void *ctx);

#endif
