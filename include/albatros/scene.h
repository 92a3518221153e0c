/* scene.h — the 3-D database the GP reads: objects of planar convex faces,
 * textures, lights, the observer, and per-frame poses.  Parsed from the text
 * format of docs/scene-format.md or imported from Wavefront OBJ.  Part of the
 * GP library's public interface: include gp/gp.h, which includes this. */
#ifndef ALBATROS_SCENE_H
#define ALBATROS_SCENE_H

#include "diag.h"
#include "vec3.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/* The library exports what its public headers declare, nothing else. */
#pragma GCC visibility push(default)
#ifdef __cplusplus
extern "C" {
#endif

#define ALB_SCENE_MAX_FACE_VERTICES 32
/* The narrowest view (degrees, vertical) and the smallest aspect the GP's
 * doubles carry: below, the screen scaling 1/tan(fov/2) overflows the
 * observer transform's inverse (docs/limits.md). */
#define ALB_SCENE_MIN_FOV 1e-6
#define ALB_SCENE_MIN_ASPECT 1e-6
#define ALB_SCENE_NAME_MAX 64

enum { ALB_SV_INTENSITY = 1, ALB_SV_NORMAL = 2, ALB_SV_UV = 4 };

typedef struct {
    alb_vec3 p;
    double i;            /* intensity, if has & ALB_SV_INTENSITY */
    alb_vec3 n;              /* normal, if has & ALB_SV_NORMAL */
    double u, v;         /* texture coordinates, if has & ALB_SV_UV */
    uint8_t has;
} alb_scene_vertex;

typedef enum { ALB_SHADE_FLAT, ALB_SHADE_VERTEX, ALB_SHADE_LIT } alb_shade_kind;
typedef enum { ALB_TEXMAP_NONE, ALB_TEXMAP_UV, ALB_TEXMAP_AXES } alb_texmap_kind;

typedef struct {
    unsigned first, count;   /* into the object's index array */
    uint8_t rgb[3];
    alb_shade_kind shade;
    double intensity;        /* ALB_SHADE_FLAT value */
    int texture;             /* scene texture index, -1 = none */
    alb_texmap_kind texmap;
    double axes[8];          /* ALB_TEXMAP_AXES: Au Bu Cu Du Av Bv Cv Dv (object space) */
    bool fog;
    unsigned line, col;      /* where it was defined (col: of the `f`; 0 unknown) */
    uint32_t id;             /* index in input order over the whole scene */
} alb_scene_face;

typedef struct {
    alb_vec3 pos;
    double yaw, pitch, roll; /* degrees */
} alb_scene_pose;

typedef struct {
    char name[ALB_SCENE_NAME_MAX];
    bool moving;             /* lit through its vertex normals (eq. 8) */
    alb_scene_vertex *v;
    unsigned nv, cap_v;
    unsigned *idx;
    unsigned nidx, cap_idx;
    alb_scene_face *f;
    unsigned nf, cap_f;
    unsigned line;
    /* its poses, each from a frame on: pose[k] holds from frame pose_from[k]
     * (pose_from[0] = 0, increasing) until the next — one entry per change,
     * not one per frame (alb_scene_pose_at) */
    alb_scene_pose *pose;
    unsigned *pose_from;
    unsigned npose, cap_pose;
} alb_scene_object;

typedef struct {
    alb_scene_pose pose;
    double fov_y;            /* vertical field of view, degrees */
    double aspect;           /* width / height; 0 = from the profile */
    /* A look-at camera (the OBJ importer's): the eye pose.pos looks toward
     * `at` with `up` up, an orientation built from the vectors alone, with
     * no angle (pose's yaw, pitch and roll are 0 and unused). */
    bool look_at;
    alb_vec3 at, up;
} alb_scene_observer;

typedef struct {
    alb_vec3 dir;                /* toward the light, world space; length = strength */
    double ambient;          /* I0 of eq. (8) */
} alb_scene_light;

typedef struct {
    alb_scene_observer obs;
    alb_scene_light light;
} alb_scene_frame;             /* the objects' poses: alb_scene_pose_at */

typedef struct {
    char name[ALB_SCENE_NAME_MAX];
    unsigned log2size;
    uint32_t *texels;        /* 0x00RRGGBB, row-major, row 0 at v = 0 */
    unsigned line;
} alb_scene_texture;

typedef struct {
    char file[256];
    double near;             /* depth scale: the VP stores near / Z */
    unsigned near_line, near_col;   /* where near's value was written (0: default) */
    uint8_t background[3];
    bool fog;
    uint8_t fog_rgb[3];
    double fog_near, fog_far;
    unsigned fog_line, fog_col;     /* where the fog statement's FAR was written */
    alb_scene_object *obj;
    unsigned nobj, cap_obj;
    alb_scene_texture *tex;
    unsigned ntex, cap_tex;
    alb_scene_frame *frames;
    unsigned nframes;
    unsigned nfaces;
    bool screenspace;        /* vertices are (pixel x, pixel y, depth): see
                                alb_scene_resolve_screenspace */
    char **files;            /* the other files read for it: textures, material
                                libraries (paths as opened) */
    unsigned nfiles;
} alb_scene;

/* Parse scene text; `name` is used in diagnostics and to resolve relative
 * texture paths.  On error *s is freed and d says file:line:col and why. */
alb_err alb_scene_parse(const char *text, size_t len, const char *name, alb_scene *s, alb_diag *d);
alb_err alb_scene_load(const char *path, alb_scene *s, alb_diag *d);
void alb_scene_free(alb_scene *s);

/* The built-in default scene (docs/builtin-scene.md). */
const char *alb_scene_builtin_text(size_t *len);
alb_err alb_scene_load_builtin(alb_scene *s, alb_diag *d);

/* Degenerate-face diagnostics: collinear, non-planar, non-convex, repeated
 * vertices.  Called by the parser and the OBJ importer.  vertex_cols[k] is the
 * column of the face's k-th vertex number on its line, where an error about
 * that vertex is reported; NULL: every error at the face's own column. */
alb_err alb_scene_check_face(const alb_scene *s, const alb_scene_object *o, const alb_scene_face *f,
                         const unsigned *vertex_cols, alb_diag *d);

/* Geometry helpers shared with the GP's database preparation. */
alb_vec3 alb_scene_face_newell(const alb_scene_object *o, const alb_scene_face *f);
static inline alb_vec3 alb_scene_face_vertex(const alb_scene_object *o, const alb_scene_face *f, unsigned k)
{
    return o->v[o->idx[f->first + k]].p;
}

/* Plain decimal number syntax, `[+-]digits[.digits][(e|E)[+-]digits]` (a
 * digit on at least one side of the point): what the scene and OBJ formats
 * accept where strtod would also take hexadecimal, "nan" and "inf". */
bool alb_scene_decimal_syntax(const char *s, size_t len);
/* What to add to "byte 0x..: not ASCII" for the byte at offset `at` of a
 * text: a hint if it starts a UTF-8 byte-order mark, else "". */
const char *alb_scene_byte_hint(const char *text, size_t len, size_t at);

/* Building blocks for importers: append and grow; NULL/-1 on allocation failure. */
alb_scene_object *alb_scene_add_object(alb_scene *s, const char *name);
alb_scene_face *alb_scene_add_face(alb_scene *s, alb_scene_object *o, const unsigned *vidx, unsigned n);
int alb_scene_add_vertex(alb_scene_object *o, const alb_scene_vertex *v);
/* Object oi's pose in frame f (binary search of its changes). */
const alb_scene_pose *alb_scene_pose_at(const alb_scene *s, unsigned f, unsigned oi);
/* Object oi takes pose p from frame f on (f at or after its last change;
 * the same frame replaces it); -1 if out of memory or out of order. */
int alb_scene_set_pose(alb_scene *s, unsigned oi, unsigned f, const alb_scene_pose *p);
/* Remember a file read for the scene (in s->files). */
int alb_scene_note_file(alb_scene *s, const char *path);
/* Finish: one frame of default state if none, a pose (at the origin) for
 * every object without one. */
alb_err alb_scene_finish(alb_scene *s, alb_diag *d);
void alb_scene_init(alb_scene *s, const char *name);
/* Observer at the origin looking along +Z, fov 60, default light. */
void alb_scene_default_frame(alb_scene_frame *f);

/* Screen-space scenes (the textbook's worked examples): vertices given as
 * (x, y, depth) in pixels of a width x height screen, x right from the left
 * border, y up from the bottom border, depth positive and larger nearer.
 * Converts them in place to observer-space points whose projection and 1/Z
 * are exactly those (docs/scene-format.md, "Screen space"), with the observer
 * at the origin and a 90-degree square view; faces are turned counter-
 * clockwise.  near/Z is near * depth / (largest depth), near the scene's if
 * written, else 1.  A scene without `screenspace` is left alone. */
alb_err alb_scene_resolve_screenspace(alb_scene *s, unsigned width, unsigned height, alb_diag *d);

/* Textures */
alb_err alb_scene_texture_checker(alb_scene_texture *t, unsigned log2size, const uint8_t a[3],
                              const uint8_t b[3], unsigned squares);
alb_err alb_scene_texture_png(alb_scene_texture *t, const char *path, alb_diag *d);

/* Wavefront OBJ import (obj.c) */
typedef struct {
    alb_vec3 eye, at, up;        /* camera: eye point, look-at point, up vector (world) */
    double fov_y;            /* vertical field of view, degrees */
    unsigned width, height;  /* resolution: sets the observer aspect = width/height */
} alb_scene_camera;
/* Import an OBJ file (with the Kd colours of its MTL libraries) as a
 * one-object scene with one frame whose observer is the camera.  Faces the GP
 * cannot draw are split into triangles, skipped if they have no area (one
 * summary warning), or rejected.  OBJ is right-handed, the scene left-handed:
 * the importer negates z (scene = file (x, y, -z)) and keeps each face's
 * vertex order, so fronts stay fronts and the model is not mirrored; the
 * camera is in the file's own coordinates, converted alike.  On error *s is
 * freed and d says where. */
alb_err alb_scene_load_obj(const char *path, const alb_scene_camera *cam, alb_scene *s, alb_diag *d);
/* The view part of a camera (finite eye, at and up; eye != at; up not along
 * the view; fov in (0, 180)), in the caller's coordinates: what the command
 * line checks before any file is read.  The messages name the options. */
alb_err alb_scene_camera_check(const alb_scene_camera *cam, alb_diag *d);

#ifdef __cplusplus
}
#endif
#pragma GCC visibility pop

#endif
