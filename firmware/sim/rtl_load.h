/* rtl_load.h — finding and loading the RTL board's VP, a shared object built
 * per parameter set (rtl/board/build.sh), for the simulated board. */
#ifndef ALBATROS_SIM_RTL_LOAD_H
#define ALBATROS_SIM_RTL_LOAD_H

#include "albatros/profile.h"
#include "rtl_vp.h"

#include <stddef.h>

typedef struct {
    void *dl;
    const alb_rtl_vp_api *api;
    char file[4200];          /* the object loaded */
} sim_rtl;

/* Load the RTL board for profile p.  path NULL: the default,
 * <program's directory>/rtl-board/PROFILE/albatros-rtl-board.so, which must
 * have been built for p's parameters; a path (the object or its directory)
 * is taken as named, and parameters differing from p's are described in
 * warn (the live check then shows what they change).  -1 with err set. */
int sim_rtl_load(sim_rtl *r, const alb_profile *p, const char *path, char *warn, size_t warnlen,
                 char *err, size_t errlen);
void sim_rtl_unload(sim_rtl *r);

/* p's RTL parameters, "WIDTH=32 HEIGHT=32 ...", as rtl/profile-params.sh. */
void sim_rtl_params(const alb_profile *p, char *buf, size_t len);
/* The first parameter of want missing from have or different there, into
 * why: 1; 0 if all agree. */
int sim_rtl_params_differ(const char *want, const char *have, char *why, size_t len);
/* The shading units an RTL's parameter list leaves out (SHADE_UNIT,
 * TEX_UNIT, FOG_UNIT 0), named into buf ("the texture and fog units
 * (TEX_UNIT=0 FOG_UNIT=0)", "" if none); how many. */
int sim_rtl_units_out(const char *have, char *buf, size_t len);

#endif
