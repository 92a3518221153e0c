/* json.c — the JSON writer of every --json output (json.h). */
#include "albatros/json.h"

#include <locale.h>
#include <math.h>
#include <string.h>

void alb_json_init(alb_json *j, FILE *f)
{
    memset(j, 0, sizeof *j);
    j->f = f;
}

static unsigned indent_of(const alb_json *j)
{
    unsigned n = 0;
    for (unsigned d = 1; d <= j->depth; d++)
        n += j->lines[d];
    return 2 * n;
}

/* The separator before a new item of the container being written. */
static void separate(alb_json *j)
{
    unsigned d = j->depth;
    if (j->has_items[d])
        fputc(',', j->f);
    if (j->lines[d])
        fprintf(j->f, "\n%*s", (int)indent_of(j), "");
    else if (j->has_items[d])
        fputc(' ', j->f);
    j->has_items[d] = true;
}

/* Whether a value may come now; writes the separator it needs. */
static bool value_ok(alb_json *j)
{
    if (j->misuse)
        return false;
    if (j->depth == 0) {
        if (j->has_items[0])
            j->misuse = true;   /* one document */
        j->has_items[0] = true;
        return !j->misuse;
    }
    if (j->in_object[j->depth]) {
        if (!j->after_key)
            return !(j->misuse = true);
        j->after_key = false;
        return true;
    }
    separate(j);
    return true;
}

static void open_container(alb_json *j, char c, bool object, bool lines)
{
    if (!value_ok(j))
        return;
    if (j->depth + 1 >= ALB_JSON_MAX_DEPTH) {
        j->misuse = true;
        return;
    }
    fputc(c, j->f);
    j->depth++;
    j->in_object[j->depth] = object;
    j->lines[j->depth] = lines;
    j->has_items[j->depth] = false;
}

static void close_container(alb_json *j, char c, bool object)
{
    if (j->misuse)
        return;
    if (j->depth == 0 || j->in_object[j->depth] != object || j->after_key) {
        j->misuse = true;
        return;
    }
    if (j->lines[j->depth] && j->has_items[j->depth]) {
        j->depth--;
        fprintf(j->f, "\n%*s", (int)indent_of(j), "");
        fputc(c, j->f);
        return;
    }
    j->depth--;
    fputc(c, j->f);
}

void alb_json_begin_object(alb_json *j) { open_container(j, '{', true, false); }
void alb_json_end_object(alb_json *j) { close_container(j, '}', true); }
void alb_json_begin_array(alb_json *j) { open_container(j, '[', false, false); }
void alb_json_begin_lines(alb_json *j) { open_container(j, '[', false, true); }
void alb_json_end_array(alb_json *j) { close_container(j, ']', false); }

/* The UTF-8 sequence at s (at most n bytes): its length if whole and
 * valid, else 0 with *bad the bytes to replace by one U+FFFD — the lead
 * byte and what follows of a valid start (Unicode's "maximal subpart", as
 * Python and browsers decode): overlong forms, surrogates and code points
 * above U+10FFFF are not UTF-8. */
static size_t utf8_len(const unsigned char *s, size_t n, size_t *bad)
{
    unsigned char c = s[0];
    size_t len;
    unsigned char lo = 0x80, hi = 0xBF;
    *bad = 1;
    if (c >= 0xC2 && c <= 0xDF)
        len = 2;
    else if (c >= 0xE0 && c <= 0xEF) {
        len = 3;
        if (c == 0xE0)
            lo = 0xA0;
        if (c == 0xED)
            hi = 0x9F;   /* not the surrogates D800..DFFF */
    } else if (c >= 0xF0 && c <= 0xF4) {
        len = 4;
        if (c == 0xF0)
            lo = 0x90;
        if (c == 0xF4)
            hi = 0x8F;
    } else {
        return 0;
    }
    for (size_t k = 1; k < len; k++) {
        if (k >= n || s[k] < (k == 1 ? lo : 0x80) || s[k] > (k == 1 ? hi : 0xBF)) {
            *bad = k;
            return 0;
        }
    }
    return len;
}

static void put_string(FILE *f, const char *str, size_t n)
{
    const unsigned char *s = (const unsigned char *)str;
    fputc('"', f);
    for (size_t i = 0; i < n;) {
        unsigned char c = s[i];
        if (c == '"' || c == '\\') {
            fputc('\\', f);
            fputc(c, f);
            i++;
        } else if (c < 0x20 || c == 0x7F) {
            const char *esc = c == '\n' ? "\\n" : c == '\t' ? "\\t" : c == '\r' ? "\\r"
                            : c == '\b' ? "\\b" : c == '\f' ? "\\f" : NULL;
            if (esc)
                fputs(esc, f);
            else
                fprintf(f, "\\u%04x", c);
            i++;
        } else if (c < 0x80) {
            fputc(c, f);
            i++;
        } else {
            size_t bad, len = utf8_len(s + i, n - i, &bad);
            if (len) {
                fwrite(s + i, 1, len, f);
                i += len;
            } else {
                fputs("\\ufffd", f);   /* not UTF-8: the replacement character */
                i += bad;
            }
        }
    }
    fputc('"', f);
}

void alb_json_key(alb_json *j, const char *key)
{
    if (j->misuse)
        return;
    if (j->depth == 0 || !j->in_object[j->depth] || j->after_key) {
        j->misuse = true;
        return;
    }
    separate(j);
    put_string(j->f, key, strlen(key));
    fputs(": ", j->f);
    j->after_key = true;
}

void alb_json_string_n(alb_json *j, const char *s, size_t len)
{
    if (value_ok(j))
        put_string(j->f, s, len);
}

void alb_json_string(alb_json *j, const char *s)
{
    if (!s)
        alb_json_null(j);
    else
        alb_json_string_n(j, s, strlen(s));
}

void alb_json_uint(alb_json *j, unsigned long long v)
{
    if (value_ok(j))
        fprintf(j->f, "%llu", v);
}

void alb_json_int(alb_json *j, long long v)
{
    if (value_ok(j))
        fprintf(j->f, "%lld", v);
}

/* A number printf wrote in the process's locale, in JSON's notation: the
 * decimal point is '.' whatever LC_NUMERIC says (a host program may have
 * set a decimal-comma locale). */
static void put_number(FILE *f, char *buf)
{
    const char *dp = localeconv()->decimal_point;
    char *at = dp && *dp && strcmp(dp, ".") ? strstr(buf, dp) : NULL;
    if (at) {
        size_t dl = strlen(dp);
        *at = '.';
        memmove(at + 1, at + dl, strlen(at + dl) + 1);
    }
    fputs(buf, f);
}

void alb_json_fixed(alb_json *j, double v, int decimals)
{
    if (!isfinite(v)) {
        alb_json_null(j);
        return;
    }
    char buf[400];
    if (value_ok(j)) {
        snprintf(buf, sizeof buf, "%.*f", decimals < 0 ? 0 : decimals > 17 ? 17 : decimals, v);
        put_number(j->f, buf);
    }
}

void alb_json_double(alb_json *j, double v)
{
    if (!isfinite(v)) {
        alb_json_null(j);
        return;
    }
    char buf[64];
    if (value_ok(j)) {
        snprintf(buf, sizeof buf, "%.17g", v);
        put_number(j->f, buf);
    }
}

void alb_json_bool(alb_json *j, bool v)
{
    if (value_ok(j))
        fputs(v ? "true" : "false", j->f);
}

void alb_json_null(alb_json *j)
{
    if (value_ok(j))
        fputs("null", j->f);
}

void alb_json_end_line(alb_json *j)
{
    if (j->depth != 0 || j->after_key)
        j->misuse = true;
    if (!j->misuse)
        fputc('\n', j->f);
}

void alb_json_kv_string(alb_json *j, const char *key, const char *v)
{
    alb_json_key(j, key);
    alb_json_string(j, v);
}

void alb_json_kv_uint(alb_json *j, const char *key, unsigned long long v)
{
    alb_json_key(j, key);
    alb_json_uint(j, v);
}

void alb_json_kv_int(alb_json *j, const char *key, long long v)
{
    alb_json_key(j, key);
    alb_json_int(j, v);
}

void alb_json_kv_fixed(alb_json *j, const char *key, double v, int decimals)
{
    alb_json_key(j, key);
    alb_json_fixed(j, v, decimals);
}

void alb_json_kv_bool(alb_json *j, const char *key, bool v)
{
    alb_json_key(j, key);
    alb_json_bool(j, v);
}
