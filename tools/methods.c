/* methods.c — the table of classic hidden-surface methods (methods.h); each
 * lives in tools/methods/NAME.c with its render function and summary. */
#include "methods.h"
#include "methods/common.h"

#include <string.h>

static const method table[] = {
    {"zbuffer", mth_zbuffer_summary, mth_zbuffer_render},
    {"scanline-zbuffer", mth_scanline_zbuffer_summary, mth_scanline_zbuffer_render},
    {"watkins", mth_watkins_summary, mth_watkins_render},
    {"watkins-nosplit", mth_watkins_nosplit_summary, mth_watkins_nosplit_render},
    {"warnock", mth_warnock_summary, mth_warnock_render},
    {"painter", mth_painter_summary, mth_painter_render},
    {"raycast", mth_raycast_summary, mth_raycast_render},
};

const method *methods_all(unsigned *n)
{
    *n = sizeof table / sizeof table[0];
    return table;
}

const method *method_find(const char *name)
{
    for (size_t i = 0; i < sizeof table / sizeof table[0]; i++)
        if (strcmp(table[i].name, name) == 0)
            return &table[i];
    return NULL;
}
