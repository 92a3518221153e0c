/* vec3.h — the 3-vector of the scene database (scene units, doubles). */
#ifndef ALBATROS_VEC3_TYPE_H
#define ALBATROS_VEC3_TYPE_H

/* The library exports what its public headers declare, nothing else. */
#pragma GCC visibility push(default)
#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
    double x, y, z;
} alb_vec3;

#ifdef __cplusplus
}
#endif
#pragma GCC visibility pop

#endif
