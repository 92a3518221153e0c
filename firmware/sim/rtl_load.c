/* rtl_load.c — finding and loading the RTL board's VP (firmware/sim/rtl_vp.h):
 * a shared object per parameter set, built by `make rtl-board` (Verilator),
 * so albatros itself builds without Verilator and says what to do when the
 * object is missing or was built for other parameters than the profile's. */
#include "rtl_load.h"

#include <dlfcn.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* The profile's fields as the RTL's parameters, in the order of
 * rtl/profile-params.sh (the object reports its own the same way). */
void sim_rtl_params(const alb_profile *p, char *buf, size_t len)
{
    snprintf(buf, len,
             "WIDTH=%u HEIGHT=%u AA=%u EDGE_FRAC_BITS=%u COEF_BITS=%u DEPTH_BITS=%u "
             "COLOUR_BITS=%u RECIP_BITS=%u SHADE_FRAC_BITS=%u FIFO_DEPTH=%u FACE_SLOTS=%u "
             "EDGE_UNITS=%u FILL_RATE=%u FILL_QUEUE=%u FRAME_QUEUE=%u DIVIDER_LATENCY=%u "
             "SHADE_LATENCY=%u FRAME_FACES=%u",
             p->width, p->height, p->aa_levels, p->edge_frac_bits, p->coef_bits, p->depth_bits,
             p->colour_bits, p->recip_bits, p->shade_frac_bits, p->fifo_depth, p->face_slots,
             p->edge_units, p->fill_rate, p->fill_queue, p->frame_queue, p->divider_latency,
             p->shade_latency, p->frame_faces);
}

/* The value of NAME in a "NAME=VALUE ..." list into val; 0 if absent. */
static int param_value(const char *list, const char *name, size_t nlen, char *val, size_t vlen)
{
    for (const char *s = list; *s;) {
        while (*s == ' ')
            s++;
        const char *eq = strchr(s, '='), *end = strchr(s, ' ');
        if (!end)
            end = s + strlen(s);
        if (eq && eq < end && (size_t)(eq - s) == nlen && !strncmp(s, name, nlen)) {
            snprintf(val, vlen, "%.*s", (int)(end - eq - 1), eq + 1);
            return 1;
        }
        s = end;
    }
    return 0;
}

/* The first parameter of want that have lacks or has otherwise, described
 * into why; 0 if every one agrees. */
int sim_rtl_params_differ(const char *want, const char *have, char *why, size_t len)
{
    for (const char *s = want; *s;) {
        while (*s == ' ')
            s++;
        const char *eq = strchr(s, '='), *end = strchr(s, ' ');
        if (!end)
            end = s + strlen(s);
        if (!eq || eq > end)
            break;
        char theirs[32];
        size_t nlen = (size_t)(eq - s);
        int vlen = (int)(end - eq - 1);
        if (!param_value(have, s, nlen, theirs, sizeof theirs)) {
            snprintf(why, len, "it has no parameter %.*s (the profile's is %.*s)", (int)nlen, s, vlen,
                     eq + 1);
            return 1;
        }
        if (strlen(theirs) != (size_t)vlen || strncmp(theirs, eq + 1, (size_t)vlen)) {
            snprintf(why, len, "it was built with %.*s=%s, the profile has %.*s", (int)nlen, s,
                     theirs, (int)(end - s), s);
            return 1;
        }
        s = end;
    }
    return 0;
}

/* The shading units an RTL's parameters leave out (rtl/README.md: SHADE_UNIT,
 * TEX_UNIT, FOG_UNIT 0; absent or 1, the unit is built): not profile fields,
 * so a board without them runs any profile, refusing a stream that needs one
 * (E_UNIT).  Their names into buf ("the texture and fog units (TEX_UNIT=0
 * FOG_UNIT=0)"); how many. */
int sim_rtl_units_out(const char *have, char *buf, size_t len)
{
    static const char *const param[3] = {"SHADE_UNIT", "TEX_UNIT", "FOG_UNIT"};
    static const char *const unit[3] = {"shade", "texture", "fog"};
    size_t out[3], n = 0;
    for (size_t i = 0; i < 3; i++) {
        char val[32];
        if (param_value(have, param[i], strlen(param[i]), val, sizeof val) && !strcmp(val, "0"))
            out[n++] = i;
    }
    if (len)
        buf[0] = 0;
    if (!n)
        return 0;
    char names[64] = "", params[64] = "";
    for (size_t i = 0; i < n; i++) {
        size_t at = strlen(names), pat = strlen(params);
        snprintf(names + at, sizeof names - at, "%s%s", i == 0 ? "" : i + 1 == n ? " and " : ", ",
                 unit[out[i]]);
        snprintf(params + pat, sizeof params - pat, "%s%s=0", i ? " " : "", param[out[i]]);
    }
    snprintf(buf, len, "the %s unit%s (%s)", names, n > 1 ? "s" : "", params);
    return (int)n;
}

/* <directory of this program>/rtl-board/PROFILE/albatros-rtl-board.so, where
 * `make rtl-board PROFILE=...` puts it beside build/albatros. */
static int default_path(const alb_profile *p, char *out, size_t len)
{
    char exe[4096];
    ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
    if (n <= 0)
        return -1;
    exe[n] = 0;
    char *slash = strrchr(exe, '/');
    if (!slash)
        return -1;
    *slash = 0;
    int k = snprintf(out, len, "%s/rtl-board/%s/%s", exe, p->name, ALB_RTL_VP_FILE);
    return k < 0 || (size_t)k >= len ? -1 : 0;
}

int sim_rtl_load(sim_rtl *r, const alb_profile *p, const char *path, char *warn, size_t warnlen,
                 char *err, size_t errlen)
{
    memset(r, 0, sizeof *r);
    if (warn && warnlen)
        warn[0] = 0;
    char file[4200];
    struct stat st;
    if (!path) {
        if (default_path(p, file, sizeof file)) {
            snprintf(err, errlen, "--sim=rtl: cannot tell where this program is (/proc/self/exe) "
                     "to find the RTL board: name it with --rtl-board FILE");
            return -1;
        }
    } else if (stat(path, &st) == 0 && S_ISDIR(st.st_mode)) {
        snprintf(file, sizeof file, "%s/%s", path, ALB_RTL_VP_FILE);
    } else {
        snprintf(file, sizeof file, "%s", path);
    }
    if (stat(file, &st) != 0) {
        if (path)
            snprintf(err, errlen, "--rtl-board %s: %s: %s (rtl/board/build.sh DIR PROFILE builds "
                     "one)", path, file, strerror(errno));
        else
            snprintf(err, errlen, "--sim=rtl: the RTL board for profile %s is not built (%s: %s); "
                     "build it with `make rtl-board PROFILE=%s` (needs Verilator; about a "
                     "minute), or name one with --rtl-board FILE", p->name, file, strerror(errno),
                     p->name);
        return -1;
    }
    r->dl = dlopen(file, RTLD_NOW | RTLD_LOCAL);
    if (!r->dl) {
        const char *why = dlerror();
        snprintf(err, errlen, "--sim=rtl: %s: cannot load the RTL board: %s", file,
                 why ? why : "dlopen failed");
        return -1;
    }
    /* POSIX: a function pointer through an object pointer, as dlsym's users do */
    alb_rtl_vp_api_fn get;
    void *sym = dlsym(r->dl, ALB_RTL_VP_SYMBOL);
    memcpy(&get, &sym, sizeof get);
    r->api = sym ? get() : NULL;
    if (!r->api || r->api->abi != ALB_RTL_VP_ABI) {
        snprintf(err, errlen, "--sim=rtl: %s: %s (this albatros takes ABI %u): rebuild it with "
                 "make rtl-board", file, !sym ? "not an RTL board (no " ALB_RTL_VP_SYMBOL ")"
                 : !r->api ? "the RTL board has no table" : "an RTL board of another ABI",
                 ALB_RTL_VP_ABI);
        sim_rtl_unload(r);
        return -1;
    }
    char want[600], why[200];
    sim_rtl_params(p, want, sizeof want);
    if (sim_rtl_params_differ(want, r->api->params, why, sizeof why)) {
        if (!path) {
            snprintf(err, errlen, "--sim=rtl: the RTL board %s was not built for this profile: "
                     "%s; build one with `make rtl-board PROFILE=%s SET='KEY=VALUE ...' "
                     "RTL_BOARD_DIR=DIR` (the --set options given here) and name it with "
                     "--rtl-board DIR", file, why, p->name);
            sim_rtl_unload(r);
            return -1;
        }
        /* named on purpose: run it, and let the live check show what differs */
        if (warn)
            snprintf(warn, warnlen, "--rtl-board %s: %s: its frames may differ from the "
                     "emulator's", path, why);
    }
    /* units left out: usable for any profile, but say so, since a stream
     * that needs one stops at its first such word (the board's VP error) */
    char units[160];
    int nout = sim_rtl_units_out(r->api->params, units, sizeof units);
    if (warn && warnlen && nout) {
        size_t at = strlen(warn);
        snprintf(warn + at, warnlen - at, "%sthe RTL board %s leaves out %s: a stream using "
                 "%s is refused (E_UNIT, rtl/README.md)", at ? "; " : "", file, units,
                 nout > 1 ? "them" : "it");
    }
    snprintf(r->file, sizeof r->file, "%s", file);
    return 0;
}

void sim_rtl_unload(sim_rtl *r)
{
    if (r->dl)
        dlclose(r->dl);
    r->dl = NULL;
    r->api = NULL;
}
