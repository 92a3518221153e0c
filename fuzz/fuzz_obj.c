/* fuzz_obj.c — the Wavefront OBJ importer (gp/obj.c) with its MTL reader,
 * through the file path the CLI uses, and the GP (profile a256) on every
 * model it accepts.  An input holding the line MTL_MARKER is split there:
 * the OBJ before it, the material library f.mtl after it (seeds say
 * `mtllib f.mtl`). */
#include "fuzz.h"

#include <stdbool.h>
#include <string.h>
#include <unistd.h>

#define MTL_MARKER "\n#--mtl--\n"

/* A '/' followed by anything that cannot continue an OBJ index ("1/2/3",
 * "1//3", "-1/-1") may start a path: `mtllib /dev/stdin` would block the run
 * and `mtllib ../..` reach outside the scratch directory. */
static bool may_name_a_path(const uint8_t *data, size_t size)
{
    for (size_t i = 0; i < size; i++) {
        if (data[i] != '/')
            continue;
        if (i + 1 == size)
            return false;
        uint8_t c = data[i + 1];
        if (!((c >= '0' && c <= '9') || c == '/' || c == '-' || c == '+' || c == ' ' ||
              c == '\t' || c == '\r' || c == '\n'))
            return true;
    }
    return false;
}

static const uint8_t *find(const uint8_t *data, size_t size, const char *s)
{
    size_t n = strlen(s);
    for (size_t i = 0; i + n <= size; i++)
        if (memcmp(data + i, s, n) == 0)
            return data + i;
    return NULL;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char obj_path[512], mtl_path[512];
    if (may_name_a_path(data, size))
        return 0;
    const uint8_t *mark = find(data, size, MTL_MARKER);
    size_t obj_len = mark ? (size_t)(mark - data) : size;
    if (fuzz_write("fuzz.obj", data, obj_len, obj_path, sizeof obj_path))
        return 0;
    if (mark) {
        size_t skip = obj_len + strlen(MTL_MARKER);
        if (fuzz_write("f.mtl", data + skip, size - skip, mtl_path, sizeof mtl_path))
            return 0;
    } else if (fuzz_write("f.mtl", "", 0, mtl_path, sizeof mtl_path) || unlink(mtl_path)) {
        return 0;   /* no stale library from an earlier input */
    }
    alb_profile prof;
    if (alb_profile_lookup("a256", &prof))
        return 0;
    alb_scene_camera cam = {{0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 60, prof.width, prof.height};
    alb_diag d;
    alb_diag_init(&d, NULL);
    alb_scene s;
    if (alb_scene_load_obj(obj_path, &cam, &s, &d) != ALB_OK)
        return 0;
    fuzz_run_gp(&s, &prof, NULL);
    alb_scene_free(&s);
    return 0;
}
