/* gp_helpers.h — run the GP on scene text inside a test and decode frame 0. */
#ifndef ALBATROS_TEST_GP_HELPERS_H
#define ALBATROS_TEST_GP_HELPERS_H

#include "../gp/gp.h"

typedef struct {
    ws_buf buf;
    gp_stats st;
    ws_config cfg;
    ws_frame frame;
    ws_face *faces;   /* of frame 0 */
    unsigned nfaces;
    char err[600];    /* diagnostic if the run failed */
} gp_run_result;

/* Parse text, run the GP with profile `prof` (NULL: a512 with the
 * assignments in `sets`, space-separated key=value), decode frame 0.
 * Returns 0 on success. */
int gp_run_text(const char *text, const char *sets, gp_run_result *r);
void gp_run_free(gp_run_result *r);

#endif
