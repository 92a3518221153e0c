/* memh.c — see memh.h. */
#include "memh.h"

#include <ctype.h>
#include <string.h>

bool memh_looks_like(const char *text, size_t len)
{
    size_t i = 0;
    while (i < len && isspace((unsigned char)text[i]))
        i++;
    if (i == len)
        return len > 0;
    char c = text[i];
    if (!(isxdigit((unsigned char)c) || c == '/' || c == '@' || c == '_'))
        return false;
    for (size_t k = i; k < len && k < i + 64; k++)
        if (!isprint((unsigned char)text[k]) && !isspace((unsigned char)text[k]))
            return false;
    return true;
}

static alb_err fail(alb_diag *d, const char *path, unsigned line, unsigned col, const char *msg,
                    const char *tok, size_t toklen)
{
    return alb_diag_at(d, ALB_ERR_PARSE, path, line, col, "%s%s%.*s%s", msg, toklen ? " '" : "",
                       (int)(toklen > 40 ? 40 : toklen), tok, toklen ? "'" : "");
}

alb_err memh_scan(const char *text, size_t len, const char *path, unsigned bits, memh_fn fn,
                  void *ctx, alb_diag *d)
{
    unsigned line = 1;
    size_t line_start = 0, count = 0;
    /* memh is text: a NUL is refused wherever it stands, comments included
     * (and the readers stop reading at the first: alb_file_read_text) */
    const char *nul = memchr(text, 0, len);
    if (nul) {
        size_t at = (size_t)(nul - text), ls = 0;
        for (size_t i = 0; i < at; i++)
            if (text[i] == '\n') {
                line++;
                ls = i + 1;
            }
        return fail(d, path, line, (unsigned)(at - ls + 1), "byte 0x00: a $readmemh file is text",
                    "", 0);
    }
    for (size_t i = 0; i < len;) {
        char c = text[i];
        unsigned col = (unsigned)(i - line_start + 1);
        if (c == '\n') {
            line++;
            line_start = ++i;
            continue;
        }
        if (isspace((unsigned char)c)) {
            i++;
            continue;
        }
        if (c == '/' && i + 1 < len && text[i + 1] == '/') {
            while (i < len && text[i] != '\n')
                i++;
            continue;
        }
        if (c == '/' && i + 1 < len && text[i + 1] == '*') {
            size_t end = i + 2;
            while (end + 1 < len && !(text[end] == '*' && text[end + 1] == '/'))
                end++;
            if (end + 1 >= len)
                return fail(d, path, line, col, "unterminated comment", "", 0);
            for (; i < end + 2; i++)
                if (text[i] == '\n') {
                    line++;
                    line_start = i + 1;
                }
            continue;
        }
        bool addr = c == '@';
        size_t k = addr ? i + 1 : i;
        uint32_t v[MEMH_MAX_BITS / 32] = {0};
        unsigned digits = 0, limbs = addr ? 2 : bits / 32;
        bool wide = false;
        for (; k < len && (isxdigit((unsigned char)text[k]) || text[k] == '_'); k++) {
            if (text[k] == '_')
                continue;
            unsigned h = isdigit((unsigned char)text[k]) ? (unsigned)(text[k] - '0')
                                                         : (unsigned)(tolower(text[k]) - 'a' + 10);
            wide |= (v[limbs - 1] >> 28) != 0;   /* this digit pushes a bit out */
            for (unsigned l = limbs - 1; l > 0; l--)
                v[l] = v[l] << 4 | v[l - 1] >> 28;
            v[0] = v[0] << 4 | h;
            digits++;
        }
        bool sep = k == len || isspace((unsigned char)text[k]) || text[k] == '/';
        if (!digits || !sep) {
            size_t e = k;
            while (e < len && !isspace((unsigned char)text[e]))
                e++;
            return fail(d, path, line, col,
                        addr ? "expected a hex address after @, found"
                             : "expected a hex value (x and z digits are not values), found",
                        text + i, e - i);
        }
        if (wide) {
            char msg[64];
            snprintf(msg, sizeof msg, addr ? "address too large:" : "value wider than %u bits:",
                     bits);
            return fail(d, path, line, col, msg, text + i, k - i);
        }
        if (addr) {
            uint64_t a = (uint64_t)v[1] << 32 | v[0];
            if (a != count)
                return alb_diag_at(d, ALB_ERR_PARSE, path, line, col,
                                   "address @%llx: the file has no holes, the next value is "
                                   "%zu (@%zx)", (unsigned long long)a, count, count);
        } else {
            if (fn(ctx, v, line, col))
                return d->msg[0] ? ALB_ERR_PARSE
                                 : alb_diag_at(d, ALB_ERR_NOMEM, path, 0, 0, "out of memory");
            count++;
        }
        i = k;
    }
    return ALB_OK;
}
