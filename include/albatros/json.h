/* json.h — the one JSON writer every --json output goes through (RFC 8259):
 * strings escaped (quotes, backslashes, control characters; bytes that are
 * not UTF-8 — a path may hold any — become U+FFFD), numbers that JSON
 * cannot hold (NaN, infinities) written as null, separators placed by the
 * writer so that no caller can produce an invalid document.  The layout is
 * fixed: ", " between items, ": " after keys, and arrays opened with
 * alb_json_begin_lines put each item on a line of its own. */
#ifndef ALBATROS_JSON_H
#define ALBATROS_JSON_H

#include <stdbool.h>
#include <stdio.h>

/* The library exports what its public headers declare, nothing else. */
#pragma GCC visibility push(default)
#ifdef __cplusplus
extern "C" {
#endif

#define ALB_JSON_MAX_DEPTH 16

typedef struct {
    FILE *f;
    unsigned depth;
    bool has_items[ALB_JSON_MAX_DEPTH];   /* the container at each depth */
    bool lines[ALB_JSON_MAX_DEPTH];       /* ... puts items on lines */
    bool in_object[ALB_JSON_MAX_DEPTH];
    bool after_key;
    bool misuse;          /* a value without a key in an object, a key in an
                             array, too deep, an unbalanced end: nothing more
                             is written (tests check it stays false) */
} alb_json;

void alb_json_init(alb_json *j, FILE *f);
void alb_json_begin_object(alb_json *j);
void alb_json_end_object(alb_json *j);
void alb_json_begin_array(alb_json *j);
/* An array with one item per line, indented two spaces, "]" on its own line. */
void alb_json_begin_lines(alb_json *j);
void alb_json_end_array(alb_json *j);
void alb_json_key(alb_json *j, const char *key);

void alb_json_string(alb_json *j, const char *s);
/* len bytes of s (which may hold NULs: written as \u0000). */
void alb_json_string_n(alb_json *j, const char *s, size_t len);
void alb_json_uint(alb_json *j, unsigned long long v);
void alb_json_int(alb_json *j, long long v);
/* With `decimals` digits after the point (printf's %.*f, in the C locale's
 * notation whatever the process's); null if not finite. */
void alb_json_fixed(alb_json *j, double v, int decimals);
/* Shortest round-trip form (%.17g); null if not finite. */
void alb_json_double(alb_json *j, double v);
void alb_json_bool(alb_json *j, bool v);
void alb_json_null(alb_json *j);
/* A newline after the top-level value, as a line-oriented tool expects. */
void alb_json_end_line(alb_json *j);

/* key and value at once, the common case */
void alb_json_kv_string(alb_json *j, const char *key, const char *v);
void alb_json_kv_uint(alb_json *j, const char *key, unsigned long long v);
void alb_json_kv_int(alb_json *j, const char *key, long long v);
void alb_json_kv_fixed(alb_json *j, const char *key, double v, int decimals);
void alb_json_kv_bool(alb_json *j, const char *key, bool v);

#ifdef __cplusplus
}
#endif
#pragma GCC visibility pop

#endif
