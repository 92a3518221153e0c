/* fuzz_scene.c — the scene text parser (gp/scene.c, docs/scene-format.md)
 * and, on every scene it accepts, the screen-space resolution and the GP
 * (profile a256), whose stream must then decode. */
#include "fuzz.h"

#include <stdbool.h>
#include <stdio.h>
#include <string.h>

/* The scene's name places it in the scratch directory, where `texture NAME
 * file PATH` finds t.png (4x4, valid) and odd.png (3x3, rejected). */
static const char *scene_name(void)
{
    static char name[300];
    if (!name[0]) {
        const char *dir = fuzz_tmpdir();
        if (!dir || fuzz_write_png("t.png", 4, 4) || fuzz_write_png("odd.png", 3, 3))
            return NULL;
        snprintf(name, sizeof name, "%s/fuzz.scene", dir);
    }
    return name;
}

/* The input may hold `texture NAME file PATH`. */
static bool names_a_file(const uint8_t *data, size_t size)
{
    for (size_t i = 0; i + 4 <= size; i++)
        if (memcmp(data + i, "file", 4) == 0)
            return true;
    return false;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const char *name = scene_name();
    alb_profile prof;
    /* Texture paths stay inside the scratch directory: a fuzzed "/dev/stdin"
     * would block the run. */
    if (!name || (memchr(data, '/', size) && names_a_file(data, size)) ||
        alb_profile_lookup("a256", &prof))
        return 0;
    alb_diag d;
    alb_diag_init(&d, NULL);
    alb_scene s;
    if (alb_scene_parse((const char *)data, size, name, &s, &d) != ALB_OK)
        return 0;
    if (alb_scene_resolve_screenspace(&s, prof.width, prof.height, &d) == ALB_OK)
        fuzz_run_gp(&s, &prof, NULL);
    alb_scene_free(&s);
    return 0;
}
