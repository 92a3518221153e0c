/* s51.c — the s51 console on two pipes (s51.h).  Every command is followed
 * by `expression N`, whose decimal answer on a line of its own ends the
 * command's output; a command that does not come back within timeout_ms
 * (a run that never stops) is an error, not a hang. */
#include "s51.h"

#include <errno.h>
#include <poll.h>
#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#define WRITE_CHUNK 128  /* bytes per `set memory` command */

static int fail(s51_t *s, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static int fail(s51_t *s, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(s->error, sizeof s->error, fmt, ap);
    va_end(ap);
    return -1;
}

int s51_open(s51_t *s, const char *cpu, const char *image, const char *preload)
{
    int in[2], out[2];

    memset(s, 0, sizeof *s);
    s->pid = -1;
    s->to = s->from = -1;
    s->sentinel = 1000000000u;
    s->timeout_ms = 20000;
    if (access(image, R_OK) != 0)
        return fail(s, "%s: %s", image, strerror(errno));
    signal(SIGPIPE, SIG_IGN);   /* a dead simulator is an error, not a signal */
    if (pipe(in) != 0)
        return fail(s, "pipe: %s", strerror(errno));
    if (pipe(out) != 0) {
        close(in[0]);
        close(in[1]);
        return fail(s, "pipe: %s", strerror(errno));
    }
    s->pid = fork();
    if (s->pid < 0) {
        close(in[0]);
        close(in[1]);
        close(out[0]);
        close(out[1]);
        return fail(s, "fork: %s", strerror(errno));
    }
    if (s->pid == 0) {
        dup2(in[0], 0);
        dup2(out[1], 1);
        dup2(out[1], 2);
        close(in[0]);
        close(in[1]);
        close(out[0]);
        close(out[1]);
        if (preload && setenv("LD_PRELOAD", preload, 1) != 0)
            _exit(127);
        /* -b: no colour escapes; -R: a fixed seed for the memories' random
         * power-on contents */
        execlp("s51", "s51", "-t", cpu, "-b", "-R", "1", image, (char *)NULL);
        fprintf(stderr, "s51: cannot run it: %s (apt-get install sdcc-ucsim)\n", strerror(errno));
        _exit(127);
    }
    close(in[0]);
    close(out[1]);
    s->open = true;
    s->to = in[1];
    s->from = out[0];
    s->cap = 1 << 16;
    s->out = malloc(s->cap);
    if (!s->out) {
        s51_close(s);
        return fail(s, "out of memory");
    }
    s->out[0] = 0;
    /* the banner and the image's loading, then a console that answers */
    if (s51_cmd(s, "info memory") != 0)
        return -1;
    if (!strstr(s->out, "xram")) {
        char msg[300];
        snprintf(msg, sizeof msg, "s51 -t %s %s did not start: %.200s", cpu, image, s->out);
        s51_close(s);
        return fail(s, "%s", msg);
    }
    return 0;
}

void s51_close(s51_t *s)
{
    if (!s->open)
        return;
    s->open = false;
    if (s->to >= 0) {
        (void)!write(s->to, "kill\n", 5);
        close(s->to);
    }
    if (s->from >= 0)
        close(s->from);
    if (s->pid > 0) {
        /* it quits on `kill` or at the end of its input; give it a moment */
        int status;
        for (int i = 0; i < 50 && waitpid(s->pid, &status, WNOHANG) == 0; i++) {
            struct timespec ms = {0, 10000000};
            nanosleep(&ms, NULL);
            if (i == 49) {
                kill(s->pid, SIGKILL);
                waitpid(s->pid, &status, 0);
            }
        }
    }
    free(s->out);
    s->out = NULL;
    s->pid = -1;
    s->to = s->from = -1;
}

static long ms_since(const struct timespec *t0)
{
    struct timespec now;
    clock_gettime(CLOCK_MONOTONIC, &now);
    return (long)(now.tv_sec - t0->tv_sec) * 1000 + (now.tv_nsec - t0->tv_nsec) / 1000000;
}

static int send_all(s51_t *s, const char *p, size_t n)
{
    while (n) {
        ssize_t k = write(s->to, p, n);
        if (k < 0) {
            if (errno == EINTR)
                continue;
            return fail(s, "writing to s51: %s", strerror(errno));
        }
        p += k;
        n -= (size_t)k;
    }
    return 0;
}

/* Where the sentinel's answer line starts in out[from .. len), or NULL. */
static char *find_sentinel(s51_t *s, const char *mark, size_t from)
{
    size_t m = strlen(mark);
    for (char *p = s->out + from; (p = strstr(p, mark)) != NULL; p++) {
        bool bol = p == s->out || p[-1] == '\n';
        if (bol && (p[m] == '\n' || p[m] == '\r'))
            return p;
    }
    return NULL;
}

int s51_cmd(s51_t *s, const char *fmt, ...)
{
    char line[4096], mark[16];
    va_list ap;
    int n;

    if (s->to < 0)
        return fail(s, "s51 is not running");
    va_start(ap, fmt);
    n = vsnprintf(line, sizeof line - 32, fmt, ap);
    va_end(ap);
    if (n < 0 || (size_t)n >= sizeof line - 32)
        return fail(s, "command too long");
    s->sentinel++;
    snprintf(mark, sizeof mark, "%u", s->sentinel);
    n += snprintf(line + n, sizeof line - (size_t)n, "\nexpression %u\n", s->sentinel);
    if (send_all(s, line, (size_t)n) != 0)
        return -1;
    s->len = 0;
    s->out[0] = 0;
    struct timespec t0;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    size_t searched = 0;   /* out[0 .. searched) holds no answer line */
    for (;;) {
        char *end = find_sentinel(s, mark, searched);
        if (end) {
            *end = 0;
            s->len = (size_t)(end - s->out);
            return 0;
        }
        long left = (long)s->timeout_ms - ms_since(&t0);
        if (left <= 0)
            return fail(s, "s51 did not answer `%.60s` within %u ms", line, s->timeout_ms);
        struct pollfd pf = {s->from, POLLIN, 0};
        int r = poll(&pf, 1, (int)left);
        if (r < 0 && errno != EINTR)
            return fail(s, "poll: %s", strerror(errno));
        if (r <= 0)
            continue;
        if (s->len + 4097 > s->cap) {
            size_t cap = s->cap * 2;
            char *p = realloc(s->out, cap);
            if (!p)
                return fail(s, "out of memory");
            s->out = p;
            s->cap = cap;
        }
        ssize_t k = read(s->from, s->out + s->len, 4096);
        if (k < 0 && errno == EINTR)
            continue;
        if (k <= 0)
            return fail(s, "s51 exited (during `%.60s`): %.200s", line, s->out);
        /* an answer line may begin up to a newline before the new bytes */
        searched = s->len > 1 ? s->len - 1 : 0;
        while (searched > 0 && s->out[searched - 1] != '\n')
            searched--;
        s->len += (size_t)k;
        s->out[s->len] = 0;
    }
}

static int hexnib(char c)
{
    return c >= '0' && c <= '9' ? c - '0' : c >= 'A' && c <= 'F' ? c - 'A' + 10 :
           c >= 'a' && c <= 'f' ? c - 'a' + 10 : -1;
}

static int hexbyte(const char *p)
{
    int h = hexnib(p[0]), l = h < 0 ? -1 : hexnib(p[1]);
    return l < 0 ? -1 : h << 4 | l;
}

/* `dump /i` answers in Intel-hex records, checksummed, unlike the default
 * layout whose column widths and register names vary. */
int s51_read(s51_t *s, const char *mem, unsigned addr, uint8_t *out, unsigned n)
{
    unsigned got = 0;

    if (!n)
        return 0;
    if (s51_cmd(s, "dump /i %s 0x%x 0x%x", mem, addr, addr + n - 1) != 0)
        return -1;
    for (const char *p = s->out; (p = strchr(p, ':')) != NULL; p++) {
        int len = hexbyte(p + 1), hi = hexbyte(p + 3), lo = hexbyte(p + 5), type = hexbyte(p + 7);
        if (len < 0 || hi < 0 || lo < 0 || type < 0 || type != 0)
            continue;
        unsigned a = (unsigned)(hi << 8 | lo), sum = (unsigned)(len + hi + lo + type);
        uint8_t rec[256];
        for (int i = 0; i < len; i++) {
            int b = hexbyte(p + 9 + 2 * i);
            if (b < 0)
                return fail(s, "dump %s 0x%x: a broken record: %.80s", mem, addr, p);
            rec[i] = (uint8_t)b;
            sum += (unsigned)b;
        }
        int check = hexbyte(p + 9 + 2 * len);
        if (check < 0 || ((sum + (unsigned)check) & 0xFFu) != 0)
            return fail(s, "dump %s 0x%x: a record with a bad checksum: %.80s", mem, addr, p);
        /* the space's own addresses, 16 bits of them (sfr 0x80.., xram ..0xFFFF) */
        if (a != ((addr + got) & 0xFFFFu) || got + (unsigned)len > n)
            return fail(s, "dump %s 0x%x: a record for 0x%x after %u bytes", mem, addr, a, got);
        memcpy(out + got, rec, (size_t)len);
        got += (unsigned)len;
    }
    if (got != n)
        return fail(s, "dump %s 0x%x: %u of %u bytes: %.200s", mem, addr, got, n, s->out);
    return 0;
}

int s51_write(s51_t *s, const char *mem, unsigned addr, const uint8_t *v, unsigned n)
{
    while (n) {
        char line[WRITE_CHUNK * 4 + 64];
        unsigned k = n < WRITE_CHUNK ? n : WRITE_CHUNK;
        int len = snprintf(line, sizeof line, "set memory %s 0x%x", mem, addr);
        /* decimal: s51 echoes every character it reads, one write each */
        for (unsigned i = 0; i < k; i++)
            len += snprintf(line + len, sizeof line - (size_t)len, " %u", v[i]);
        if (s51_cmd(s, "%s", line) != 0)
            return -1;
        addr += k;
        v += k;
        n -= k;
    }
    return 0;
}

int s51_read8(s51_t *s, const char *mem, unsigned addr, uint8_t *v)
{
    return s51_read(s, mem, addr, v, 1);
}

int s51_write8(s51_t *s, const char *mem, unsigned addr, uint8_t v)
{
    return s51_write(s, mem, addr, &v, 1);
}

int s51_break_fetch(s51_t *s, unsigned addr)
{
    if (s51_cmd(s, "break 0x%x", addr) != 0)
        return -1;
    return strstr(s->out, "Breakpoint") ? 0 : fail(s, "break 0x%x: %.200s", addr, s->out);
}

int s51_break_write(s51_t *s, const char *mem, unsigned addr)
{
    /* s51 says nothing when it sets an event breakpoint, and prints the
     * command's usage when it cannot: look for it in the list instead */
    char want[64];
    if (s51_cmd(s, "break %s w 0x%x", mem, addr) != 0 || s51_cmd(s, "info breakpoints") != 0)
        return -1;
    snprintf(want, sizeof want, "0x%06x write", addr);
    return strstr(s->out, want) ? 0 : fail(s, "break %s w 0x%x: not set: %.200s", mem, addr, s->out);
}

int s51_run(s51_t *s, unsigned long max_insns, s51_stop *stop)
{
    memset(stop, 0, sizeof *stop);
    if (s51_cmd(s, "step %lu", max_insns) != 0)
        return -1;
    const char *p = strstr(s->out, "Stop at 0x");
    if (!p || sscanf(p, "Stop at 0x%x", &stop->pc) != 1)
        return fail(s, "run: no stop: %.300s", s->out);
    const char *t = strstr(s->out, "Simulated ");
    unsigned long long ticks = 0;
    if (t && sscanf(t, "Simulated %llu ticks", &ticks) == 1)
        stop->ticks = ticks;
    const char *r = strstr(s->out, "SP 0x");
    /* "DPTR= 0x..", or with two data pointers the active one: "*DPTR0= 0x.." */
    const char *d = strstr(s->out, "DPTR= 0x");
    if (!d && (d = strstr(s->out, "*DPTR")) != NULL)
        d = strstr(d, "= 0x") ? strstr(d, "= 0x") - 4 : NULL;
    unsigned st[8];
    if (r && d &&
        sscanf(r, "SP 0x%x -> %x %x %x %x %x %x %x %x", &stop->sp, &st[0], &st[1], &st[2], &st[3],
               &st[4], &st[5], &st[6], &st[7]) == 9 &&
        sscanf(d + 4, "= 0x%x", &stop->dptr) == 1) {
        for (int i = 0; i < 8; i++)
            stop->stack[i] = (uint8_t)st[i];
        stop->regs = true;
    }
    const char *e = strstr(s->out, "Event `write' at ");
    if (e) {
        if (sscanf(e, "Event `write' at %7[a-z][0x%x]", stop->space, &stop->addr) != 2)
            return fail(s, "run: unreadable event: %.200s", e);
        stop->kind = S51_WRITE;
    } else if (strstr(p, "Breakpoint")) {
        stop->kind = S51_FETCH;
    } else if (strstr(p, "stepped")) {
        stop->kind = S51_LIMIT;
    } else {
        return fail(s, "run: stopped for an unknown reason: %.200s", p);
    }
    return 0;
}

int s51_clocks(s51_t *s, uint64_t *clocks)
{
    unsigned long long c;
    if (s51_cmd(s, "timer get time") != 0)
        return -1;
    const char *p = strstr(s->out, " clks)");
    if (!p)
        return fail(s, "timer get: %.200s", s->out);
    while (p > s->out && p[-1] >= '0' && p[-1] <= '9')
        p--;
    if (sscanf(p, "%llu", &c) != 1)
        return fail(s, "timer get: %.200s", s->out);
    *clocks = c;
    return 0;
}

int s51_rom_reads(s51_t *s, unsigned from, unsigned to, uint64_t *count)
{
    unsigned seen = 0;
    if (s51_cmd(s, "statistic rom 0x%x 0x%x", from, to) != 0)
        return -1;
    for (const char *p = s->out; (p = strstr(p, "rom[0x")) != NULL; p++) {
        unsigned a;
        unsigned long long reads;
        if (sscanf(p, "rom[0x%x] writes= %*u (%*[^)]) reads= %llu", &a, &reads) != 2)
            continue;
        if (a < from || a > to)
            continue;
        count[a - from] = reads;
        seen++;
    }
    if (seen != to - from + 1)
        return fail(s, "statistic rom: %u of %u addresses", seen, to - from + 1);
    return 0;
}
