/* fuzz_png.c — texture images (gp/texture.c): a PNG file through libpng's
 * simplified API, checked for a square power-of-two side, turned into
 * texels. */
#include "fuzz.h"

#include <stdlib.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char path[512];
    if (fuzz_write("fuzz.png", data, size, path, sizeof path))
        return 0;
    alb_scene_texture t = {0};
    alb_diag d;
    alb_diag_init(&d, NULL);
    if (alb_scene_texture_png(&t, path, &d) == ALB_OK)
        free(t.texels);
    return 0;
}
